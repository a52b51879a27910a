#include "cutdyn/app/lobes_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "cutdyn/core/error.hpp"

namespace cutdyn::app {
namespace {

constexpr std::size_t kMaxVariants = 100'000;

// The command line's message of a refusal: "where: problem" per problem, "; "-joined.
std::string message_of(const InvalidInput& e) {
  std::string out;
  const std::string where = e.where().empty() ? "input" : e.where();
  for (const std::string& p : e.problems()) out += (out.empty() ? "" : "; ") + where + ": " + p;
  return out;
}

}  // namespace

std::vector<LobesVariant> lobes_variants(const std::vector<io::Case>& cases,
                                         const std::vector<Sweep>& vary, const std::string& where) {
  Validator v;
  if (cases.empty()) v.add("no case to sweep");
  std::set<std::string> keys;
  std::size_t per_case = 1;
  for (const Sweep& s : vary) {
    if (!keys.insert(s.key).second) v.add(s.key + ": varied twice");
    if (s.values.empty()) v.add(s.key + ": no values");
    per_case *= std::max<std::size_t>(1, s.values.size());
    if (per_case > kMaxVariants) break;
  }
  if (per_case * std::max<std::size_t>(1, cases.size()) > kMaxVariants)
    v.add("more than " + std::to_string(kMaxVariants) +
          " variants: split the sweep, or vary fewer values");
  v.throw_if_any(where);

  std::vector<LobesVariant> out;
  for (const io::Case& base : cases) {
    std::vector<std::size_t> at(vary.size(), 0);
    for (std::size_t n = 0; n < per_case; ++n) {
      LobesVariant variant;
      variant.file = base.source;
      for (std::size_t k = 0; k < vary.size(); ++k) variant.values.push_back(vary[k].values[at[k]]);
      try {
        io::Case c = base;
        for (std::size_t k = 0; k < vary.size(); ++k)
          c = io::with_value(c, vary[k].key, variant.values[k]);
        variant.c = std::move(c);
      } catch (const InvalidInput& e) {
        variant.error = message_of(e);
      }
      out.push_back(std::move(variant));
      for (std::size_t k = vary.size(); k-- > 0;) {  // the last key fastest
        if (++at[k] < vary[k].values.size()) break;
        at[k] = 0;
      }
    }
  }
  // No variant has a case: the request is at fault (an unknown key, an index out of range),
  // not its values — refused whole, each distinct problem once.
  if (std::all_of(out.begin(), out.end(), [](const LobesVariant& x) { return !x.c; })) {
    std::vector<std::string> problems;
    for (const LobesVariant& x : out)
      if (std::find(problems.begin(), problems.end(), x.error) == problems.end())
        problems.push_back(x.error);
    if (problems.size() > 5) problems.resize(5);
    throw InvalidInput(problems, where);
  }
  return out;
}

std::vector<std::string> lobes_sweep_columns(const std::vector<io::Case>& cases,
                                             const std::vector<Sweep>& vary) {
  std::vector<std::string> columns;
  if (cases.size() > 1) columns.push_back("case");
  for (const Sweep& s : vary) columns.push_back(s.key);
  columns.insert(columns.end(), {"spindle_rpm", "critical_depth_mm", "chatter_hz", "lobe",
                                 "bifurcation", "beyond_limit"});
  if (std::any_of(cases.begin(), cases.end(), [](const io::Case& c) { return c.vibration; }))
    columns.insert(columns.end(),
                   {"duty_cycle", "conventional_depth_mm", "conventional_chatter_hz"});
  columns.push_back("error");
  return columns;
}

std::vector<std::vector<io::CsvCell>> lobes_variant_rows(const std::vector<std::string>& columns,
                                                         const LobesVariant& variant,
                                                         const LobesRequest& request) {
  // The leading cells: the case and the varied values.
  std::vector<io::CsvCell> lead;
  if (!columns.empty() && columns.front() == "case") lead.emplace_back(variant.file);
  for (double x : variant.values) lead.emplace_back(x);
  const auto error_row = [&](const std::string& error) {
    std::vector<io::CsvCell> row = lead;
    while (row.size() + 1 < columns.size()) row.emplace_back(std::string());
    row.emplace_back(error);
    return std::vector<std::vector<io::CsvCell>>{row};
  };
  if (!variant.c) return error_row(variant.error);
  ReportTable table;
  try {
    table = lobes_table(run_lobes(*variant.c, request));
  } catch (const InvalidInput& e) {
    return error_row(message_of(e));
  }
  std::vector<std::vector<io::CsvCell>> rows;
  for (const auto& cells : table.rows) {
    std::vector<io::CsvCell> row = lead;
    for (std::size_t k = lead.size(); k + 1 < columns.size(); ++k) {
      const auto it = std::find(table.columns.begin(), table.columns.end(), columns[k]);
      if (it == table.columns.end())
        row.emplace_back(std::nan(""));  // a column this case has not: an empty cell
      else
        row.push_back(cells[static_cast<std::size_t>(it - table.columns.begin())]);
    }
    row.emplace_back(std::string());
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace cutdyn::app
