// `cutdyn lobes` rendered: the summary table, the lowest depth, stable pockets, the speeds
// stable at a target depth, and the CSV, JSON and figure of the lobes job's report.
#include <fmt/format.h>

#include <algorithm>
#include <variant>

#include "cli/common.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/io/output.hpp"
#include "cutdyn/io/plot.hpp"

namespace cutdyn::cli {
namespace {

using nlohmann::json;
using units::m_to_mm;

const std::vector<CriticalDepth>* reference_of(const app::LobesJobReport& r) {
  return r.reference.empty() ? nullptr : &r.reference;
}

// Every speed up to 20 rows (then every n-th), with the marks below the table.
void print_table(const app::LobesJobReport& r, std::ostream& out) {
  const auto& pts = r.lobes.points;
  const auto* ref = reference_of(r);
  std::string header = fmt::format("  {:>11}  {:>17}  {:>10}  {:>4}  {:>11}", "spindle_rpm",
                                   "critical_depth_mm", "chatter_hz", "lobe", "bifurcation");
  if (r.duty_cycle) header += fmt::format("  {:>10}", "duty_cycle");
  if (ref) header += fmt::format("  {:>21}", "conventional_depth_mm");
  out << header << "\n";
  const std::size_t stride = std::max<std::size_t>(1, (pts.size() + 19) / 20);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (i % stride != 0 && i + 1 != pts.size()) continue;
    const LobePoint& p = pts[i];
    std::string row = fmt::format("  {:>11.1f}  {:>16.4f}{}  {:>10.2f}  {:>4}  {:>11}", p.rpm,
                                  m_to_mm(p.boundary.depth_m), p.boundary.found ? ' ' : '+',
                                  p.boundary.chatter_hz, p.lobe, to_string(p.boundary.bifurcation));
    if (r.duty_cycle) row += fmt::format("  {:>10.4f}", p.duty_cycle);
    if (ref)
      row += fmt::format("  {:>20.4f}{}", m_to_mm((*ref)[i].depth_m), (*ref)[i].found ? ' ' : '+');
    out << row << "\n";
  }
  if (stride > 1) out << "  (every " << stride << "th speed shown; --out F.csv writes them all)\n";
  if (std::any_of(pts.begin(), pts.end(), [](const LobePoint& p) { return !p.boundary.found; }))
    out << "  + stable up to the depth limit at that speed\n";
}

// The lowest depth, the pockets and, at a target depth, the stable speeds and the advice.
void print_findings(const app::LobesJobReport& r, std::ostream& out) {
  const auto& pts = r.lobes.points;
  out << "\n  lowest critical depth " << depth_text(pts[r.lowest].boundary) << " at "
      << human(pts[r.lowest].rpm) << " rpm\n";
  if (!r.pockets.empty()) {
    out << "  stable pockets (local maxima):";
    for (std::size_t k = 0; k < r.pockets.size(); ++k)
      out << (k ? ";" : "") << " " << human(pts[r.pockets[k]].rpm) << " rpm, "
          << depth_text(pts[r.pockets[k]].boundary);
    out << "\n";
  }
  if (!r.target_depth_m) return;
  out << "\n  stable at " << human(m_to_mm(*r.target_depth_m)) << " mm:";
  for (std::size_t k = 0; k < r.stable_ranges.size(); ++k)
    out << (k == 0 ? " " : "; ") << human(r.stable_ranges[k].rpm_from) << "–"
        << human(r.stable_ranges[k].rpm_to) << " rpm";
  const SpeedAdvice& advice = r.advice;
  if (r.stable_ranges.empty()) {
    out << " no speed of the lobes\n";
  } else if (advice.found) {
    const LobePoint& p = pts[advice.index];
    out << "\n  recommended: " << human(advice.rpm) << " rpm (in " << human(advice.range.rpm_from)
        << "–" << human(advice.range.rpm_to) << " rpm, critical depth " << depth_text(p.boundary)
        << "): stable with the speed " << human(100.0 * advice.margin, 2) << " % (±"
        << human(advice.margin * advice.rpm, 3) << " rpm) off and the depth "
        << human(100.0 * advice.margin, 2) << " % larger\n";
  }
}

// One row of named values per speed, shared by the CSV and the JSON.
struct Rows {
  std::vector<std::string> columns;
  std::function<std::vector<io::CsvCell>(std::size_t)> row;
};
Rows rows_of(const app::LobesJobReport& r) {
  Rows out;
  out.columns = {"spindle_rpm", "critical_depth_mm", "chatter_hz",
                 "lobe",        "bifurcation",       "beyond_limit"};
  if (r.duty_cycle) out.columns.push_back("duty_cycle");
  const auto* ref = reference_of(r);
  if (ref) out.columns.insert(out.columns.end(), {"conventional_depth_mm", "conventional_chatter_hz"});
  out.row = [&r, ref](std::size_t i) {
    const LobePoint& p = r.lobes.points[i];
    std::vector<io::CsvCell> cells{p.rpm,
                                   m_to_mm(p.boundary.depth_m),
                                   p.boundary.chatter_hz,
                                   static_cast<long long>(p.lobe),
                                   std::string(to_string(p.boundary.bifurcation)),
                                   static_cast<long long>(p.boundary.found ? 0 : 1)};
    if (r.duty_cycle) cells.emplace_back(p.duty_cycle);
    if (ref) {
      cells.emplace_back(m_to_mm((*ref)[i].depth_m));
      cells.emplace_back((*ref)[i].chatter_hz);
    }
    return cells;
  };
  return out;
}

json lobes_json(const io::Case& c, const app::LobesJobReport& r, const Rows& rows) {
  const auto& pts = r.lobes.points;
  json points = json::array();
  for (std::size_t i = 0; i < pts.size(); ++i) {
    json j = json::object();
    const auto cells = rows.row(i);
    for (std::size_t k = 0; k < rows.columns.size(); ++k)
      std::visit([&](const auto& v) { j[rows.columns[k]] = v; }, cells[k]);
    j["beyond_limit"] = !pts[i].boundary.found;
    points.push_back(std::move(j));
  }
  json doc = json_document("lobes", c);
  doc.update({{"method", r.method},
              {"seconds", r.lobes.seconds},
              {"evaluations", r.lobes.evaluations},
              {"lowest",
               {{"spindle_rpm", pts[r.lowest].rpm},
                {"critical_depth_mm", m_to_mm(pts[r.lowest].boundary.depth_m)}}},
              {"points", std::move(points)}});
  if (r.lobes.status != LobesStatus::kSuccess) doc["warning"] = r.lobes.message;
  if (!r.warnings.empty()) doc["warnings"] = r.warnings;
  if (r.target_depth_m) {
    doc["target_depth_mm"] = m_to_mm(*r.target_depth_m);
    json ranges = json::array();
    for (const SpeedRange& s : r.stable_ranges)
      ranges.push_back({{"rpm_from", s.rpm_from}, {"rpm_to", s.rpm_to}});
    doc["stable_ranges"] = ranges;
    if (r.advice.found) {
      doc["recommended_rpm"] = r.advice.rpm;
      doc["recommended_margin"] = r.advice.margin;
      doc["recommended_range"] = {{"rpm_from", r.advice.range.rpm_from},
                                  {"rpm_to", r.advice.range.rpm_to}};
    }
  }
  return doc;
}

io::PlotSpec lobes_plot(const app::LobesJobReport& r) {
  const auto& pts = r.lobes.points;
  const auto* ref = reference_of(r);
  io::PlotSpec spec;
  spec.title = r.title;
  spec.x_label = "spindle speed (rpm)";
  spec.y_label = "critical depth of cut (mm)";
  spec.y_min = 0.0;
  spec.y_max = m_to_mm(r.depth_max_m);
  io::PlotSeries main{r.label, {}, {}, "stable-region"};
  io::PlotSeries reference{r.reference_label, {}, {}, "lines"};
  for (std::size_t i = 0; i < pts.size(); ++i) {
    main.x.push_back(pts[i].rpm);
    main.y.push_back(m_to_mm(pts[i].boundary.depth_m));
    if (ref) {
      reference.x.push_back(pts[i].rpm);
      reference.y.push_back(m_to_mm((*ref)[i].depth_m));
    }
  }
  spec.series.push_back(std::move(main));
  if (ref) spec.series.push_back(std::move(reference));
  return spec;
}

}  // namespace

void report_lobes(const io::Case& c, const app::LobesJobReport& r, const Outputs& files,
                  std::ostream& out, std::ostream& err) {
  if (r.lobes.status != LobesStatus::kSuccess)
    err << "cutdyn: warning: " << r.lobes.message << "\n";
  for (const std::string& w : r.warnings) err << "cutdyn: warning: " << w << "\n";
  out << "cutdyn lobes: " << c.source << "\n";
  out << "  " << r.description << "\n";
  out << fmt::format("  method {}, {} speeds {}–{} rpm, depth limit {} mm, {:.2f} s\n", r.method,
                     r.lobes.points.size(), human(r.lobes.options.rpm_min),
                     human(r.lobes.options.rpm_max), human(m_to_mm(r.depth_max_m)),
                     r.lobes.seconds);
  out << "\n";
  print_table(r, out);
  print_findings(r, out);
  const Rows rows = rows_of(r);
  io::OutputTransaction outputs;
  if (!files.csv.empty()) {
    io::CsvWriter csv(outputs.open(files.csv), rows.columns);
    for (std::size_t i = 0; i < r.lobes.points.size(); ++i) csv.row(rows.row(i));
  }
  if (!files.json.empty()) io::write_json(outputs.open(files.json), lobes_json(c, r, rows));
  if (!files.plot.empty()) io::write_plot(lobes_plot(r), files.plot, outputs);
  commit_outputs(outputs, files, out);
}

}  // namespace cutdyn::cli
