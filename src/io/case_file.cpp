#include "cutdyn/io/case_file.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <memory>
#include <sstream>
#include <system_error>

#include "case_fields.hpp"
#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/io/frf_file.hpp"
#include "cutdyn/io/inputs.hpp"

namespace cutdyn::io {

namespace detail {
// Generated at build time from examples/*.toml (cmake/write_embedded_examples.cmake).
const std::vector<std::pair<std::string_view, std::string_view>>& embedded_examples();
}  // namespace detail

namespace {

// ---- text helpers ----------------------------------------------------------------------

// Optimal-string-alignment distance (Levenshtein plus adjacent transpositions), ignoring
// ASCII case: "rpm_stepz" → "rpm_steps" is 1, "Lobes" → "lobes" is 0.
std::size_t edit_distance(std::string_view a, std::string_view b) {
  auto lower = [](char ch) {
    return (ch >= 'A' && ch <= 'Z') ? static_cast<char>(ch - 'A' + 'a') : ch;
  };
  const std::size_t n = a.size(), m = b.size();
  std::vector<std::vector<std::size_t>> d(n + 1, std::vector<std::size_t>(m + 1, 0));
  for (std::size_t i = 0; i <= n; ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= m; ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= n; ++i) {
    for (std::size_t j = 1; j <= m; ++j) {
      const std::size_t cost = lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && lower(a[i - 1]) == lower(b[j - 2]) &&
          lower(a[i - 2]) == lower(b[j - 1])) {
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
      }
    }
  }
  return d[n][m];
}

const char* type_name(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::table:
      return "a table";
    case toml::node_type::array:
      return node.as_array()->is_array_of_tables() && !node.as_array()->empty()
                 ? "an array of tables"
                 : "an array";
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a float";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::date:
      return "a date";
    case toml::node_type::time:
      return "a time";
    case toml::node_type::date_time:
      return "a date-time";
    case toml::node_type::none:
      break;
  }
  return "nothing";
}

// ---- the source text, for quoting values as written --------------------------------------

class SourceText {
 public:
  explicit SourceText(std::string_view text) : text_(text) {
    line_starts_.push_back(0);
    for (std::size_t i = 0; i < text_.size(); ++i) {
      if (text_[i] == '\n') line_starts_.push_back(i + 1);
    }
  }

  // The value of `node` exactly as the file spells it ("2.26e8", "\"y\"", "nan"). Empty
  // for a table given by a [header] or an array of [[tables]]: there is no value to quote.
  std::string as_written(const toml::node& node) const {
    if (const toml::table* table = node.as_table(); table && !table->is_inline()) return {};
    if (const toml::array* array = node.as_array(); array && !array->empty() &&
                                                    array->is_array_of_tables() &&
                                                    !array->front().as_table()->is_inline()) {
      return {};
    }
    const toml::source_region& region = node.source();
    if (region.begin.line == region.end.line) {
      const auto begin = offset(region.begin), end = offset(region.end);
      if (begin && end && *end > *begin) {
        std::string_view raw = text_.substr(*begin, *end - *begin);
        while (!raw.empty() && (raw.back() == ' ' || raw.back() == '\t' || raw.back() == '\r')) {
          raw.remove_suffix(1);
        }
        if (!raw.empty()) return std::string(raw);
      }
    }
    // Spans several lines (a multi-line string or array): print it in TOML instead.
    std::ostringstream out;
    node.visit([&](auto&& value) { out << value; });
    return out.str();
  }

 private:
  // Byte offset of a 1-based line and column; toml++ counts columns in code points.
  std::optional<std::size_t> offset(const toml::source_position& pos) const {
    if (pos.line == 0 || pos.column == 0 || pos.line > line_starts_.size()) return std::nullopt;
    std::size_t i = line_starts_[pos.line - 1];
    for (toml::source_index col = 1; col < pos.column; ++col) {
      if (i >= text_.size()) return std::nullopt;
      ++i;
      while (i < text_.size() && (static_cast<unsigned char>(text_[i]) & 0xC0) == 0x80) ++i;
    }
    return i;
  }

  std::string_view text_;
  std::vector<std::size_t> line_starts_;
};

using detail::Alias;
using detail::Field;
using detail::find_section;
using detail::key_text;
using detail::number_text;
using detail::Range;
using detail::Section;
using detail::tidy_number;
using detail::Type;
using detail::Uses;
using detail::Value;

// ---- problems --------------------------------------------------------------------------

class Problems {
 public:
  explicit Problems(const SourceText* source) : source_(source) {}

  // "<key> = <value as written>: <rule>" (or "<key>: <rule>" when there is no value).
  void at(const std::string& key, const toml::node& node, std::string_view rule) {
    at_text(key, written(node), rule);
  }
  // The same with the value's text given.
  void at_text(const std::string& key, const std::string& value, std::string_view rule) {
    bad_.push_back(key);
    list_.push_back(key + (value.empty() ? "" : " = " + value) + ": " + std::string(rule));
  }
  // "<key>: missing (<why>)".
  void missing(const std::string& key, std::string_view why = "required") {
    bad_.push_back(key);
    list_.push_back(key + ": missing (" + std::string(why) + ")");
  }
  void add(std::string problem) { list_.push_back(std::move(problem)); }

  std::string value_part(const toml::node& node) const {
    const std::string text = written(node);
    return text.empty() ? std::string{} : " = " + text;
  }
  std::string written(const toml::node& node) const {
    return source_ != nullptr ? source_->as_written(node) : std::string{};
  }
  // Whether `key` already has a problem (then rules between keys leave it alone).
  bool bad(const std::string& key) const {
    return std::find(bad_.begin(), bad_.end(), key) != bad_.end();
  }

  bool empty() const { return list_.empty(); }
  std::size_t size() const { return list_.size(); }
  std::vector<std::string> take() { return std::move(list_); }

 private:
  const SourceText* source_;
  std::vector<std::string> list_;
  std::vector<std::string> bad_;
};

// ---- key paths ---------------------------------------------------------------------------

// "modes[0]" for an element of an array section, else the section's name.
std::string table_path(const Section& s, std::size_t index) {
  return s.array ? std::string(s.name) + "[" + std::to_string(index) + "]" : std::string(s.name);
}

std::string key_path(const std::string& table, std::string_view key) {
  return table.empty() ? key_text(key) : table + "." + key_text(key);
}

// A key path as in the messages, split: "modes[0].damping_ratio" is section "modes", index
// 0, key "damping_ratio"; "material.johnson_cook.a_mpa" is section "material.johnson_cook".
struct KeyPath {
  std::string section;
  std::optional<std::size_t> index;
  std::string key;
};

std::optional<KeyPath> split_key(std::string_view path) {
  KeyPath k;
  const auto dot = path.rfind('.');
  k.key = std::string(dot == std::string_view::npos ? path : path.substr(dot + 1));
  std::string table(dot == std::string_view::npos ? std::string_view{} : path.substr(0, dot));
  if (k.key.empty() || (dot != std::string_view::npos && table.empty())) return std::nullopt;
  if (!table.empty() && table.back() == ']') {
    const auto open = table.rfind('[');
    if (open == std::string::npos || open + 2 > table.size() - 1) return std::nullopt;
    const std::string digits = table.substr(open + 1, table.size() - open - 2);
    if (digits.empty() || digits.size() > 9 ||
        !std::all_of(digits.begin(), digits.end(), [](char ch) { return ch >= '0' && ch <= '9'; }))
      return std::nullopt;
    k.index = static_cast<std::size_t>(std::stoul(digits));
    table.erase(open);
  }
  if (table.find_first_of("[]") != std::string::npos) return std::nullopt;
  k.section = table;
  return k;
}

// The closest of `names` to `name` within two edits, or "".
std::string suggestion(std::string_view name, const std::vector<std::string_view>& names) {
  std::string_view best;
  std::size_t best_distance = 3;
  for (std::string_view candidate : names) {
    const std::size_t d = edit_distance(name, candidate);
    if (d < best_distance) {
      best_distance = d;
      best = candidate;
    }
  }
  return std::string(best);
}

// ---- which process takes which key --------------------------------------------------------

// Why a table that is present is not used by a case of `process` ("" when it is).
std::string unused_table_reason(std::string_view table, Process process, bool has_material) {
  if (process == Process::kMilling && table == "vibration")
    return "not used in a milling case (vibration-assisted cutting is modelled for turning)";
  if (process == Process::kTurning &&
      (table == "tool" || table == "operation" || table == "force_law"))
    return "not used in a turning case (" + std::string(table) +
           " is a milling table: tool, operation, force_law)";
  if (process == Process::kTurning && table == "drives")
    return "not used in a turning case (`cutdyn drive` takes milling cases: the feed drives "
           "under the milling force)";
  if (!has_material && table == "oxley")
    return "used only with a [material] (the settings of Oxley's theory)";
  return {};
}

// Why a key of a table the process uses is not used ("" when it is): a key of the other
// process (cutting, simulate), or a key that one model of the process reads only.
std::string unused_key_reason(const Section& s, std::string_view key, Process process,
                              bool has_material, bool has_force_law) {
  const Field* f = s.find(key);
  if (f == nullptr) return {};  // an alias, or unknown: the reader says which
  if (!f->used_in(process) && s.alias(key, process) == nullptr) {
    const char* name = process == Process::kMilling ? "milling" : "turning";
    std::string takes;
    for (const Field& g : s.fields)
      if (g.used_in(process)) takes += (takes.empty() ? "" : ", ") + std::string(g.key);
    if (process == Process::kMilling && s.name == "simulate")
      takes += "; --duration-s on the command line sets revolutions";
    return "not used in a " + std::string(name) + " case (" + name + " takes " + takes + ")";
  }
  if (s.name == "cutting" && process == Process::kTurning && !has_material &&
      (key == "rake_deg" || key == "workpiece_temperature_c"))
    return "used only with a [material] (Oxley's theory predicts the force coefficients from "
           "it)";
  if (s.name == "cutting" && process == Process::kMilling && has_force_law &&
      (key == "kte_n_per_mm" || key == "kre_n_per_mm"))
    return "not used with [force_law] (the simulation then takes the S1 law of [force_law]; "
           "the stability lobes take no edge forces)";
  return {};
}

// Takes out of `root` every key and table that `process` does not use, with a problem for
// each (docs/case-files.md, "Which process takes which key"): such a key gets this one
// problem, before the tables are read.
void remove_unused(toml::table& root, Process process, Problems& problems) {
  const bool has_material = root.contains("material");
  const bool has_force_law = root.contains("force_law");
  for (std::string_view table :
       {"vibration", "tool", "operation", "force_law", "drives", "oxley"}) {
    const toml::node* node = root.get(table);
    if (node == nullptr) continue;
    if (const std::string why = unused_table_reason(table, process, has_material); !why.empty()) {
      problems.at(std::string(table), *node, why);
      root.erase(table);
    }
  }
  for (std::string_view table : {"cutting", "simulate"}) {
    toml::table* t = root[table].as_table();
    if (t == nullptr) continue;
    const Section& s = *find_section(table, false);
    std::vector<std::string> unused;
    for (auto&& [key, node] : *t)
      if (!unused_key_reason(s, key.str(), process, has_material, has_force_law).empty())
        unused.emplace_back(key.str());
    for (const std::string& key : unused) {
      problems.at(std::string(table) + "." + key_text(key), *t->get(key),
                  unused_key_reason(s, key, process, has_material, has_force_law));
      t->erase(key);
    }
  }
}

// ---- reading a table through its field table --------------------------------------------

// A finite number (integer or float) in `range`, or a problem at `where`.
std::optional<double> checked_number(Problems& problems, const toml::node& node,
                                     const std::string& where, const Range& range) {
  double value = 0.0;
  if (const auto* i = node.as_integer()) {
    value = static_cast<double>(i->get());
  } else if (const auto* f = node.as_floating_point()) {
    value = f->get();
  } else {
    problems.at(where, node, std::string("wrong type: expected a number, got ") + type_name(node));
    return std::nullopt;
  }
  if (!std::isfinite(value)) {
    problems.at(where, node, "must be a finite number");
    return std::nullopt;
  }
  if (!range.contains(value)) {
    problems.at(where, node, range.rule());
    return std::nullopt;
  }
  return value;
}

std::string integer_rule(const Range& range) {
  return "must be an integer from " + number_text(range.lo) + " to " + number_text(range.hi);
}

std::string choice_rule(const Field& f) {
  std::string text;
  for (std::string_view name : f.choices)
    text += (text.empty() ? "\"" : ", \"") + std::string(name) + "\"";
  return "must be one of " + text;
}

// The value of `node` for `f`, checked (type, finite, range, choices) and in SI.
std::optional<Value> read_value(Problems& problems, const Field& f, const toml::node& node,
                                const std::string& where) {
  switch (f.type) {
    case Type::kNumber:
      if (auto v = checked_number(problems, node, where, f.range)) return Value(f.unit.to_si(*v));
      return std::nullopt;
    case Type::kInteger: {
      const auto* i = node.as_integer();
      if (i == nullptr) {
        problems.at(where, node,
                    std::string("wrong type: expected an integer, got ") + type_name(node));
        return std::nullopt;
      }
      const double v = static_cast<double>(i->get());
      if (!(v >= f.range.lo && v <= f.range.hi)) {
        problems.at(where, node, integer_rule(f.range));
        return std::nullopt;
      }
      return Value(v);
    }
    case Type::kBoolean:
      if (const auto* b = node.as_boolean()) return Value(b->get());
      problems.at(where, node,
                  std::string("wrong type: expected true or false, got ") + type_name(node));
      return std::nullopt;
    case Type::kChoice:
    case Type::kText: {
      const auto* s = node.as_string();
      if (s == nullptr) {
        problems.at(where, node,
                    std::string("wrong type: expected a string, got ") + type_name(node));
        return std::nullopt;
      }
      if (f.type == Type::kChoice &&
          std::find(f.choices.begin(), f.choices.end(), s->get()) == f.choices.end()) {
        problems.at(where, node, choice_rule(f));
        return std::nullopt;
      }
      return Value(s->get());
    }
    case Type::kNumbers: {
      const toml::array* array = node.as_array();
      if (array == nullptr || array->empty()) {
        problems.at(where, node,
                    std::string("wrong type: expected a non-empty array of numbers, got ") +
                        type_name(node));
        return std::nullopt;
      }
      std::vector<double> values;
      for (std::size_t i = 0; i < array->size(); ++i) {
        const auto v = checked_number(problems, *array->get(i),
                                      where + "[" + std::to_string(i) + "]", f.range);
        if (v) values.push_back(f.unit.to_si(*v));
      }
      if (values.size() != array->size()) return std::nullopt;
      return Value(std::move(values));
    }
  }
  return std::nullopt;
}

struct Reading {
  Problems& problems;
  Case& c;
  std::optional<Process> process;  // unknown when the process key is bad: every key is read
};

// Reads every key of `s` that `table` holds into element `index` of the Case, through the
// field table: type, range, requirement and the member. `all_optional`: a library material's
// tables, where each key overrides the entry's value.
void read_fields(Reading& r, const Section& s, const toml::table& table, std::size_t index,
                 bool all_optional = false) {
  const std::string path = table_path(s, index);
  for (const Field& f : s.fields) {
    if (!s.plan && r.process && !f.used_in(*r.process)) continue;  // taken out before
    std::string_view key = f.key;
    const toml::node* node = table.get(f.key);
    for (const Alias& a : s.aliases) {
      if (a.canonical != f.key || !r.process || s.alias(a.key, *r.process) == nullptr) continue;
      const toml::node* old = table.get(a.key);
      if (old == nullptr) continue;
      if (node != nullptr) {
        r.problems.add(key_path(path, a.key) + r.problems.value_part(*old) + " and " +
                       key_path(path, f.key) + r.problems.value_part(*node) + ": give " +
                       std::string(f.key) + " only (" + std::string(a.key) + " is its old name)");
      } else {
        node = old;
        key = a.key;
        r.c.warnings.push_back(key_path(path, a.key) + ": " + std::string(a.warning));
      }
    }
    const std::string where = key_path(path, key);
    if (node == nullptr) {
      if (!all_optional && (f.required || (f.required_if && f.required_if(r.c, index))))
        r.problems.missing(where);
      continue;
    }
    const auto value = read_value(r.problems, f, *node, where);
    if (!value) continue;
    if (const std::string why = f.set(r.c, index, *value); !why.empty())
      r.problems.at(where, *node, why);
  }
}

// "lobes.rpm_stepz: unknown key (did you mean rpm_steps?)" for every key of `table` that
// `s` does not know.
void report_unknown(Reading& r, const Section& s, const toml::table& table, std::size_t index) {
  std::vector<std::string_view> known;
  for (const Field& f : s.fields) known.push_back(f.key);
  for (const Alias& a : s.aliases) known.push_back(a.key);
  for (std::string_view t : s.subtables) known.push_back(t);
  for (auto&& [key, node] : table) {
    const std::string_view name = key.str();
    if (std::find(known.begin(), known.end(), name) != known.end()) continue;
    std::string problem = key_path(table_path(s, index), name) +
                          (node.is_table() ? ": unknown table" : ": unknown key");
    if (const std::string best = suggestion(name, known); !best.empty())
      problem += " (did you mean " + best + "?)";
    r.problems.add(std::move(problem));
  }
}

// The sub-table `key` of `parent`, or nullptr when absent or not a table (then a problem).
const toml::table* sub_table(Problems& problems, const toml::table& parent,
                             const std::string& parent_path, std::string_view key) {
  const toml::node* node = parent.get(key);
  if (node == nullptr) return nullptr;
  if (const toml::table* table = node->as_table()) return table;
  problems.at(key_path(parent_path, key), *node,
              std::string("wrong type: expected a table ([") + std::string(key) + "]), got " +
                  type_name(*node));
  return nullptr;
}

// ---- rules between keys (explicit: a field table holds per-key facts) ---------------------

// How the rules show the value of another key: as written in the file when reading it, from
// the Case when checking a sweep step. nullopt: the key is not given.
struct Quote {
  std::function<std::optional<std::string>(const std::string& path)> written;
};

std::string shown(const Quote& q, const std::string& path, double fallback) {
  if (auto w = q.written(path)) return *w;
  return number_text(fallback) + " (default)";
}

void rules_lobes(const Case& c, Problems& p, const Quote& q) {
  if (p.bad("lobes.rpm_min") || p.bad("lobes.rpm_max")) return;
  if (c.lobes.grid.rpm_max > c.lobes.grid.rpm_min) return;
  const LobesOptions defaults;
  if (auto max = q.written("lobes.rpm_max"))
    p.at_text(
        "lobes.rpm_max", *max,
        "must be greater than lobes.rpm_min = " + shown(q, "lobes.rpm_min", defaults.rpm_min));
  else
    p.at_text("lobes.rpm_min", q.written("lobes.rpm_min").value_or(""),
              "must be less than lobes.rpm_max = " + number_text(defaults.rpm_max) + " (default)");
}

void rules_simulate(const Case& c, Problems& p, const Quote& q) {
  const SimulateSection& s = c.simulate;
  if (c.process != Process::kMilling || p.bad("simulate.summary_revolutions") ||
      p.bad("simulate.revolutions") || s.summary_revolutions <= s.revolutions)
    return;
  p.at_text("simulate.summary_revolutions",
            shown(q, "simulate.summary_revolutions", s.summary_revolutions),
            "must be at most revolutions = " + format_value(s.revolutions));
}

void rules_tool(const Case& c, Problems& p, const Quote& q) {
  if (!c.tool || c.tool->pitch_rad.empty() || p.bad("tool.teeth")) return;
  const std::size_t n = c.tool->pitch_rad.size();
  if (static_cast<int>(n) != c.tool->teeth)
    p.at_text("tool.pitch_deg", q.written("tool.pitch_deg").value_or(""),
              "must give one angle per tooth (teeth = " + std::to_string(c.tool->teeth) +
                  "), got " + std::to_string(n));
}

void rules_operation(const Case& c, Problems& p, const Quote& q) {
  if (!c.operation || p.bad("operation.entry_deg") || p.bad("operation.exit_deg")) return;
  const MillingEngagement& op = c.operation->engagement;
  if (op.entry_rad.has_value() != op.exit_rad.has_value()) {
    const std::string key = op.entry_rad ? "operation.entry_deg" : "operation.exit_deg";
    p.at_text(key, q.written(key).value_or(""), "give entry_deg and exit_deg together");
  } else if (op.entry_rad && *op.entry_rad >= *op.exit_rad) {
    p.at_text("operation.exit_deg", q.written("operation.exit_deg").value_or(""),
              "must be greater than entry_deg = " + q.written("operation.entry_deg").value_or(""));
  }
}

void rules_vibration(const Case& c, Problems& p, const Quote& q) {
  if (!c.vibration) return;
  const VibrationAssist& v = *c.vibration;
  const auto duty = q.written("vibration.duty_cycle");
  const auto diameter = q.written("vibration.workpiece_diameter_mm");
  if (duty && diameter)
    p.add("vibration.duty_cycle = " + *duty +
          " and vibration.workpiece_diameter_mm = " + *diameter +
          ": give either duty_cycle (fixed) or workpiece_diameter_mm (duty cycle from the "
          "cutting speed), not both");
  if (!duty && !q.written("vibration.amplitude_um") && !v.amplitude_m)
    p.missing("vibration.amplitude_um", "required unless duty_cycle is given");
}

// T2 in seconds or as an angle, not both. (A sweep step's case carries every key, t2_s = 0
// included: the rule is on the values.)
void rules_force_law(const Case& c, Problems& p, const Quote& q) {
  if (!c.force_law || !c.force_law->t2_angle_rad || c.force_law->t2_s == 0.0) return;
  const std::string seconds = q.written("force_law.t2_s").value_or(format_value(c.force_law->t2_s));
  const std::string degrees =
      q.written("force_law.t2_deg")
          .value_or(format_value(units::rad_to_deg(*c.force_law->t2_angle_rad)));
  p.add("force_law.t2_s = " + seconds + " and force_law.t2_deg = " + degrees +
        ": give either t2_s (T2 in seconds) or t2_deg (the rotation during T2), not both");
}

void rules_oxley(const Case& c, Problems& p) {
  const OxleyOptions& o = c.oxley;
  if (o.c0_min >= o.c0_max)
    p.add("oxley.c0_min = " + format_value(o.c0_min) +
          " and oxley.c0_max = " + format_value(o.c0_max) + ": c0_min must be less than c0_max");
  if (o.delta_min >= o.delta_max)
    p.add("oxley.delta_min = " + format_value(o.delta_min) + " and oxley.delta_max = " +
          format_value(o.delta_max) + ": delta_min must be less than delta_max");
}

// What only the whole material shows (Tm > Tr; S and K positive up to melting).
void rules_material(const Case& c, Problems& p) {
  if (!c.material) return;
  Validator v;
  validate(*c.material, v);
  for (const std::string& problem : v.problems()) p.add("material." + problem);
}

// Force coefficients and the material to predict them from, not both.
void rules_coefficients(const Case& c, Problems& p, const Quote& q) {
  if (!c.material) return;
  if (c.cutting.kc_pa)
    p.add(
        "cutting.kc_n_per_mm2 and [material]: give the force coefficients or the material to "
        "predict them from, not both");
  if (c.cutting.kt_pa || c.cutting.kf_pa) {
    const char* key = c.process == Process::kTurning && !q.written("cutting.kt_n_per_mm2")
                          ? "kf_n_per_mm2"
                          : "kt_n_per_mm2";
    p.add(std::string("cutting.") + key +
          " and [material]: give the force coefficients or the material to predict them from, "
          "not both");
  }
}

void rules_bore(const Case& c, Problems& p, const Quote& q) {
  if (!c.bore) return;
  const BoreMillingCase& b = *c.bore;
  if (!p.bad("bore.allowance_mm") && !p.bad("bore.diameter_mm") && b.bore_diameter_m > 0.0 &&
      b.allowance_m >= 0.5 * b.bore_diameter_m)
    p.at_text("bore.allowance_mm", q.written("bore.allowance_mm").value_or(""),
              "must be less than the bore's radius");
  if (!p.bad("cutter.diameter_mm") && b.cutter_diameter_m > 0.0 && b.bore_diameter_m > 0.0 &&
      b.cutter_diameter_m >= b.bore_diameter_m)
    p.at_text(
        "cutter.diameter_mm", q.written("cutter.diameter_mm").value_or(""),
        "must be less than bore.diameter_mm = " + format_value(units::m_to_mm(b.bore_diameter_m)));
  if (c.bore_limits && !p.bad("limits.offset_min_mm") && !p.bad("limits.offset_max_mm") &&
      c.bore_limits->offset_max_m < c.bore_limits->offset_min_m)
    p.at_text("limits.offset_max_mm", q.written("limits.offset_max_mm").value_or(""),
              "must be at least offset_min_mm");
}

// Every rule between keys, for a sweep step (reading applies them table by table).
void rules_all(const Case& c, Problems& p, const Quote& q) {
  if (c.bore) {
    rules_bore(c, p, q);
    return;
  }
  rules_tool(c, p, q);
  rules_operation(c, p, q);
  rules_vibration(c, p, q);
  rules_force_law(c, p, q);
  rules_lobes(c, p, q);
  rules_simulate(c, p, q);
  rules_material(c, p);
  if (c.material) rules_oxley(c, p);
  rules_coefficients(c, p, q);
}

// ---- reading a file ----------------------------------------------------------------------

// The node at a key path of the file ("modes[0].natural_hz", "lobes.rpm_min"), or nullptr.
const toml::node* node_at(const toml::table& root, const std::string& path) {
  const auto k = split_key(path);
  if (!k) return nullptr;
  const toml::node* table = &root;
  if (!k->section.empty()) {
    std::string_view rest = k->section;
    while (table != nullptr && !rest.empty()) {
      const auto dot = rest.find('.');
      const std::string part(rest.substr(0, dot));
      table = table->as_table() ? table->as_table()->get(part) : nullptr;
      rest = dot == std::string_view::npos ? std::string_view{} : rest.substr(dot + 1);
    }
    if (table != nullptr && k->index) {
      const toml::array* array = table->as_array();
      table = array != nullptr && *k->index < array->size() ? array->get(*k->index) : nullptr;
    }
  }
  if (table == nullptr || table->as_table() == nullptr) return nullptr;
  return table->as_table()->get(k->key);
}

Quote file_quote(const toml::table& root, const Problems& problems) {
  return {[&root, &problems](const std::string& path) -> std::optional<std::string> {
    const toml::node* node = node_at(root, path);
    if (node == nullptr) return std::nullopt;
    return problems.written(*node);
  }};
}

void read_modes(Reading& r, const toml::table& root) {
  Problems& problems = r.problems;
  const toml::node* node = root.get("modes");
  // Optional here: the jobs that need the structure ask for it (a force or a rigid-cutter
  // simulation does not).
  if (node == nullptr) return;
  const toml::array* array = node->as_array();
  if (array == nullptr) {
    problems.at("modes", *node,
                std::string("wrong type: expected an array of tables ([[modes]]), got ") +
                    type_name(*node));
    return;
  }
  if (array->empty()) {
    problems.at("modes", *node, "must hold at least one mode");
    return;
  }
  const Section& s = *find_section("modes", false);
  for (std::size_t i = 0; i < array->size(); ++i) {
    const std::string path = "modes[" + std::to_string(i) + "]";
    const toml::table* table = array->get(i)->as_table();
    if (table == nullptr) {
      problems.at(path, *array->get(i),
                  std::string("wrong type: expected a table, got ") + type_name(*array->get(i)));
      continue;
    }
    const std::size_t index = r.c.modal.modes.size();
    r.c.modal.modes.push_back(Mode{});
    r.c.mode_mass_kg.emplace_back();
    read_fields(r, s, *table, index);
    const toml::node* k_node = table->get("stiffness_n_per_m");
    const toml::node* m_node = table->get("mass_kg");
    if (k_node != nullptr && m_node != nullptr) {
      problems.add(path + ".stiffness_n_per_m" + problems.value_part(*k_node) + " and " + path +
                   ".mass_kg" + problems.value_part(*m_node) +
                   ": give either stiffness_n_per_m or mass_kg, not both");
    } else if (k_node == nullptr && m_node == nullptr) {
      problems.missing(path + ".stiffness_n_per_m", "required unless mass_kg is given");
    }
    const toml::node* direction = table->get("direction");
    if (r.process == Process::kTurning && direction != nullptr &&
        direction->value<std::string>() == "y")
      problems.at(path + ".direction", *direction, "turning models the feed direction \"x\" only");
    report_unknown(r, s, *table, index);
  }
}

void read_drives(Reading& r, const toml::table& root) {
  Problems& problems = r.problems;
  const toml::node* node = root.get("drives");
  if (node == nullptr) return;
  const toml::array* array = node->as_array();
  if (array == nullptr || array->empty() || array->size() > 3) {
    problems.at("drives", *node, "must be one to three [[drives]] tables");
    return;
  }
  const Section& s = *find_section("drives", false);
  for (std::size_t i = 0; i < array->size(); ++i) {
    const std::string path = "drives[" + std::to_string(i) + "]";
    const toml::table* table = array->get(i)->as_table();
    if (table == nullptr) {
      problems.at(path, *array->get(i),
                  std::string("wrong type: expected a table, got ") + type_name(*array->get(i)));
      continue;
    }
    const std::size_t index = r.c.drives.size();
    FeedAxis axis;
    axis.name = "axis " + std::to_string(index);
    // The motor, for phase currents: given by its torque constant. Each axis draws its own
    // stream of the noise's seed (its index in [[drives]]).
    if (table->contains("torque_constant_nm_per_a") || table->contains("pole_pairs")) {
      axis.motor.emplace();
      axis.motor->stream = static_cast<unsigned>(index);
    }
    r.c.drives.push_back(axis);
    read_fields(r, s, *table, index);
    if (table->contains("axis") && table->contains("direction"))
      problems.at(path + ".direction", *table->get("direction"),
                  "give axis or direction, not both");
    if (!table->contains("axis") && !table->contains("direction"))
      problems.missing(path + ".axis", "axis or direction is required");
    report_unknown(r, s, *table, index);
  }
}

void read_frfs(Reading& r, const toml::table& root) {
  Problems& problems = r.problems;
  const toml::node* node = root.get("frf");
  if (node == nullptr) return;
  const toml::array* array = node->as_array();
  if (array == nullptr || array->empty() || !array->is_array_of_tables()) {
    problems.at("frf", *node, "must be one or more [[frf]] tables");
    return;
  }
  const Section& s = *find_section("frf", false);
  for (std::size_t i = 0; i < array->size(); ++i) {
    const std::size_t index = r.c.frfs.size();
    r.c.frfs.emplace_back();
    read_fields(r, s, *array->get(i)->as_table(), index);
    if (r.process == Process::kTurning && r.c.frfs.back().direction != "x" &&
        !r.c.frfs.back().direction.empty())
      problems.at("frf[" + std::to_string(i) + "].direction",
                  *array->get(i)->as_table()->get("direction"),
                  "turning models the feed direction \"x\" only");
    report_unknown(r, s, *array->get(i)->as_table(), index);
  }
}

// The measured FRFs of [[frf]], read from their files (relative to the case file's folder).
// A file's faults name the file and its line; its reader's assumptions become warnings.
// Files are read by `read_frf` when there is one (their path is then as the case names them).
void load_frf_files(Case& c, const FrfFileReader& read_frf) {
  const std::filesystem::path base = std::filesystem::path(c.source).parent_path();
  for (std::size_t i = 0; i < c.frfs.size(); ++i) {
    FrfTable& t = c.frfs[i];
    t.path = read_frf ? std::filesystem::path(t.file)
                      : std::filesystem::absolute(base / t.file).lexically_normal();
    FrfFileOptions options;
    if (!t.format.empty()) options.format = parse_frf_format(t.format);
    options.dataset = t.dataset;
    if (!t.units.empty()) options.units = t.units;
    FrfReadResult read;
    try {
      read = read_frf ? read_frf(t.file, options) : read_frf_file(t.path, options);
    } catch (const InvalidInput& e) {
      std::vector<std::string> problems;
      for (const std::string& p : e.problems())
        problems.push_back("frf[" + std::to_string(i) + "].file = \"" + t.file + "\": " + p);
      throw InvalidInput(problems, e.where());
    }
    // A direct table must behave as a receptance (docs/frf-files.md, "Is it a receptance?").
    if (t.direction != "xy") {
      if (const std::string problem = direct_receptance_problem(read.frf, read.quantity);
          !problem.empty())
        throw InvalidInput({"frf[" + std::to_string(i) + "].file = \"" + t.file + "\": " + problem},
                           t.path.string());
    }
    t.data = std::move(read.frf);
    for (const std::string& w : read.warnings)
      c.warnings.push_back("frf[" + std::to_string(i) + "] (" + t.path.string() + "): " + w);
  }
}

void read_material(Reading& r, const toml::table& t) {
  Problems& problems = r.problems;
  const Section& s = *find_section("material", false);
  std::optional<std::string> name;
  if (const toml::node* node = t.get("name")) {
    if (auto v = read_value(problems, *s.find("name"), *node, "material.name"))
      name = std::get<std::string>(*v);
  }
  const WorkMaterial* entry = name ? find_material(*name) : nullptr;
  const toml::table* jc_table = sub_table(problems, t, "material", "johnson_cook");
  const toml::table* th_table = sub_table(problems, t, "material", "thermal");
  if (name && !entry && (jc_table == nullptr || th_table == nullptr)) {
    std::string names;
    for (const WorkMaterial& m : material_library()) names += (names.empty() ? "" : ", ") + m.name;
    problems.at("material.name", *t.get("name"),
                "is not in the material library (" + names +
                    "); give it, or your own [material.johnson_cook] and [material.thermal] "
                    "tables");
    report_unknown(r, s, t, 0);
    return;
  }
  if (!name && (jc_table == nullptr || th_table == nullptr)) {
    if (!problems.bad("material.name"))
      problems.missing("material.name",
                       "give a library material, or both [material.johnson_cook] and "
                       "[material.thermal]");
    report_unknown(r, s, t, 0);
    return;
  }
  WorkMaterial material;
  if (entry) material = *entry;
  material.name = name.value_or("user material");
  if (!entry) material.reference = "given in the case";
  r.c.material = std::move(material);
  // Without a library entry every property is required; with one, each key overrides.
  const std::size_t before = problems.size();
  for (const auto& [sub, table] : {std::pair{"johnson_cook", jc_table}, {"thermal", th_table}}) {
    if (table == nullptr) continue;
    const Section& ss = *find_section("material." + std::string(sub), false);
    read_fields(r, ss, *table, 0, entry != nullptr);
    report_unknown(r, ss, *table, 0);
  }
  report_unknown(r, s, t, 0);
  if (problems.size() == before) rules_material(r.c, problems);
}

// A table of the file read through its section's field table: the keys, then the rules
// between them (`rules`), then the unknown keys.
template <typename Rules>
void read_table(Reading& r, const toml::table& root, std::string_view name, Rules rules) {
  const toml::node* node = root.get(name);
  if (node == nullptr) return;
  const toml::table* table = node->as_table();
  if (table == nullptr) {
    r.problems.at(std::string(name), *node,
                  std::string("wrong type: expected a table ([") + std::string(name) + "]), got " +
                      type_name(*node));
    return;
  }
  const Section& s = *find_section(name, r.c.bore.has_value());
  if (s.count(r.c) == 0 && s.create) s.create(r.c);
  read_fields(r, s, *table, 0);
  rules();
  report_unknown(r, s, *table, 0);
}

// A `cutdyn plan` case: [bore], [cutter] and the [process] table ([Zenkin2012];
// docs/models/bore-milling.md, keys in docs/case-files.md). A [process] TABLE marks it: TOML cannot
// hold both it and the `process = "..."` key of the dynamics cases (docs/case-files.md).
void read_plan(Reading& r, const toml::table& root, const Quote& quote) {
  Problems& problems = r.problems;
  Case& c = r.c;
  c.process = Process::kBoreMilling;
  c.bore.emplace();
  const auto nothing = [] {};
  if (root.contains("bore"))
    read_table(r, root, "bore", nothing);
  else
    problems.missing("bore", "required by a plan case: diameter_mm, length_mm, allowance_mm");
  if (root.contains("cutter"))
    read_table(r, root, "cutter", nothing);
  else
    problems.missing("cutter",
                     "required by a plan case: diameter_mm, teeth, offset_mm, lead_angle_deg");
  read_table(r, root, "process", nothing);
  if (root.contains("limits")) {
    c.bore_limits.emplace();
    read_table(r, root, "limits", nothing);
  }
  rules_bore(c, problems, quote);
  std::vector<std::string_view> known = {"process", "bore", "cutter", "limits"};
  for (auto&& [key, node] : root) {
    if (std::find(known.begin(), known.end(), key.str()) != known.end()) continue;
    std::string problem =
        key_text(key.str()) + (node.is_table() ? ": unknown table" : ": unknown key");
    if (const std::string best = suggestion(key.str(), known); !best.empty())
      problem += " (did you mean " + best + "?)";
    problems.add(std::move(problem));
  }
}

// ---- JSON --------------------------------------------------------------------------------

// A converted-back value, rounded to 15 significant digits so that the unit round trip
// prints what the file said (30, not 30.000000000000004); integral values print as integers.
nlohmann::json tidy(double value) {
  if (!std::isfinite(value)) return value;
  const double rounded = tidy_number(value);
  if (std::abs(rounded) < 1e15 && rounded == std::trunc(rounded)) {
    return static_cast<std::int64_t>(rounded);
  }
  return rounded;
}

}  // namespace

const char* to_string(Process process) {
  switch (process) {
    case Process::kTurning:
      return "turning";
    case Process::kMilling:
      return "milling";
    case Process::kBoreMilling:
      return "bore-milling";
  }
  return "?";
}

namespace {

// A JSON value as a TOML node: objects as tables, arrays of objects as arrays of tables.
// Problems name the key path ("modes[0].natural_hz").
std::optional<toml::table> table_of(const nlohmann::json& j, const std::string& path,
                                    std::vector<std::string>& problems);

std::unique_ptr<toml::node> node_of(const nlohmann::json& j, const std::string& path,
                                    std::vector<std::string>& problems) {
  switch (j.type()) {
    case nlohmann::json::value_t::boolean:
      return std::make_unique<toml::value<bool>>(j.get<bool>());
    case nlohmann::json::value_t::number_integer:
    case nlohmann::json::value_t::number_unsigned:
      return std::make_unique<toml::value<int64_t>>(j.get<int64_t>());
    case nlohmann::json::value_t::number_float:
      return std::make_unique<toml::value<double>>(j.get<double>());
    case nlohmann::json::value_t::string:
      return std::make_unique<toml::value<std::string>>(j.get<std::string>());
    case nlohmann::json::value_t::object: {
      auto t = table_of(j, path, problems);
      return t ? std::make_unique<toml::table>(std::move(*t)) : nullptr;
    }
    case nlohmann::json::value_t::array: {
      auto a = std::make_unique<toml::array>();
      for (std::size_t i = 0; i < j.size(); ++i) {
        auto element = node_of(j[i], path + "[" + std::to_string(i) + "]", problems);
        if (!element) return nullptr;
        a->push_back(std::move(*element));
      }
      return a;
    }
    default:
      problems.push_back(path + " = " + j.dump() + ": not a value a case can hold");
      return nullptr;
  }
}

std::optional<toml::table> table_of(const nlohmann::json& j, const std::string& path,
                                    std::vector<std::string>& problems) {
  toml::table t;
  for (const auto& [key, value] : j.items()) {
    if (value.is_null()) continue;  // absent
    const std::string at = path.empty() ? key : path + "." + key;
    auto node = node_of(value, at, problems);
    if (node) t.insert_or_assign(key, std::move(*node));
  }
  if (!problems.empty()) return std::nullopt;
  return t;
}

}  // namespace

nlohmann::json case_schema() { return detail::schema_json(); }

Case parse_case_json(const nlohmann::json& j, std::string_view source,
                     const FrfFileReader& read_frf) {
  if (!j.is_object())
    throw InvalidInput({"a case is a table of keys (a JSON object or Python dict), not " +
                        std::string(j.type_name())},
                       std::string(source));
  std::vector<std::string> problems;
  const auto table = table_of(j, "", problems);
  if (!table) throw InvalidInput(problems, std::string(source));
  std::ostringstream text;
  text << *table;
  return parse_case(text.str(), source, read_frf);
}

Case parse_case(std::string_view toml_text, std::string_view source,
                const FrfFileReader& read_frf) {
  toml::table root;
  try {
    root = toml::parse(toml_text, source);
  } catch (const toml::parse_error& e) {
    throw InvalidInput(
        {"line " + std::to_string(e.source().begin.line) + ", column " +
         std::to_string(e.source().begin.column) + ": " + std::string(e.description())},
        std::string(source));
  }

  const SourceText text(toml_text);
  Problems problems(&text);
  Case c;
  c.source = std::string(source);
  c.text = std::string(toml_text);
  Reading r{problems, c, std::nullopt};
  const Quote quote = file_quote(root, problems);

  if (const toml::node* p = root.get("process"); p != nullptr && p->is_table()) {
    read_plan(r, root, quote);
    if (!problems.empty()) throw InvalidInput(problems.take(), std::string(source));
    return c;
  }
  const Section& top = *find_section("", false);
  read_fields(r, top, root, 0);
  if (root.contains("process") && !problems.bad("process")) {
    r.process = c.process;
    remove_unused(root, c.process, problems);
  }
  read_modes(r, root);
  read_frfs(r, root);
  read_drives(r, root);
  const auto nothing = [] {};
  read_table(r, root, "cutting", nothing);
  read_table(r, root, "tool", nothing);
  read_table(r, root, "operation", [&] { rules_operation(c, problems, quote); });
  read_table(r, root, "vibration", [&] { rules_vibration(c, problems, quote); });
  read_table(r, root, "lobes", [&] { rules_lobes(c, problems, quote); });
  read_table(r, root, "simulate", [&] { rules_simulate(c, problems, quote); });
  read_table(r, root, "force_law", [&] { rules_force_law(c, problems, quote); });
  if (const toml::table* t = sub_table(problems, root, "", "material")) read_material(r, *t);
  if (const toml::node* node = root.get("oxley")) {
    if (const toml::table* t = node->as_table()) {
      const Section& s = *find_section("oxley", false);
      read_fields(r, s, *t, 0);
      report_unknown(r, s, *t, 0);
      rules_oxley(c, problems);
    } else {
      sub_table(problems, root, "", "oxley");
    }
  }
  if (c.material && problems.empty()) {
    if (c.process == Process::kMilling)
      problems.add(
          "material: Oxley's theory is orthogonal cutting, used by the turning commands; for "
          "milling give cutting.kt_n_per_mm2 and cutting.kr_n_per_mm2");
    else
      rules_coefficients(c, problems, quote);
  }
  report_unknown(r, top, root, 0);

  if (!problems.empty()) throw InvalidInput(problems.take(), std::string(source));
  load_frf_files(c, read_frf);
  for (std::string& w : plausibility_warnings(c)) c.warnings.push_back(std::move(w));
  return c;
}

Case with_value(const Case& c, std::string_view key, double value) {
  const std::string path(key);
  const std::string label = path + " = " + format_value(value);
  const std::string where = c.source + " with " + label;
  // A value the key cannot take: the case and the key = value once (the varied case's own
  // problems, found later, name it by its source "… with key = value").
  const auto fail = [&](const std::string& why) -> Case {
    throw InvalidInput({label + ": " + why}, c.source);
  };
  const bool plan = c.process == Process::kBoreMilling;
  const auto k = split_key(path);
  if (!k) return fail("not a key path (\"table.key\", \"table[i].key\" or \"key\")");
  const Section* s = find_section(k->section, plan);
  if (s == nullptr) {
    std::vector<std::string_view> names;
    for (const Section& t : detail::case_sections())
      if (t.plan == plan && !t.name.empty()) names.push_back(t.name);
    const std::string best = suggestion(k->section, names);
    return fail(k->section + ": unknown table" +
                (best.empty() ? "" : " (did you mean " + best + "?)"));
  }
  if (s->array && !k->index)
    return fail(std::string(s->name) + " is an array of tables: give the index, e.g. " +
                std::string(s->name) + "[0]." + k->key);
  if (!s->array && k->index)
    return fail(std::string(s->name) + " is a table, not an array of tables: no index");
  const Field* f = s->find(k->key);
  if (const Alias* a = plan ? nullptr : s->alias(k->key, c.process)) f = s->find(a->canonical);
  if (f == nullptr) {
    std::vector<std::string_view> names;
    for (const Field& g : s->fields) names.push_back(g.key);
    const std::string best = suggestion(k->key, names);
    return fail("unknown key" + (best.empty() ? "" : " (did you mean " + best + "?)"));
  }
  if (!f->numeric())
    return fail("not a number key (" + std::string(f->key) + " takes " +
                (f->type == Type::kBoolean   ? "true or false"
                 : f->type == Type::kNumbers ? "an array of numbers"
                                             : "a string") +
                "): only numbers can be swept");
  // The rules of the loader, for this key.
  if (!plan) {
    const std::string section(s->name.substr(0, s->name.find('.')));
    std::string why = unused_table_reason(section, c.process, c.material.has_value());
    if (why.empty())
      why =
          unused_key_reason(*s, k->key, c.process, c.material.has_value(), c.force_law.has_value());
    if (!why.empty()) return fail(why);
  }
  if (!std::isfinite(value)) return fail("must be a finite number");
  if (f->type == Type::kInteger) {
    if (value != std::trunc(value)) return fail("wrong type: expected an integer, got a float");
    if (!(value >= f->range.lo && value <= f->range.hi)) return fail(integer_rule(f->range));
  } else if (!f->range.contains(value)) {
    return fail(f->range.rule());
  }
  Case out = c;
  out.source = where;
  const std::size_t index = k->index.value_or(0);
  const bool created = s->count(out) == 0;
  if (created && !s->array) {
    if (const std::string why = s->create(out); !why.empty()) return fail(why);
  }
  if (index >= s->count(out))
    return fail("index out of range: the case has " + std::to_string(s->count(out)) + " [[" +
                std::string(s->name) + "]] table" + (s->count(out) == 1 ? "" : "s"));
  if (s->name == "modes") {
    const bool by_mass = index < c.mode_mass_kg.size() && c.mode_mass_kg[index].has_value();
    if ((f->key == "mass_kg" && !by_mass) || (f->key == "stiffness_n_per_m" && by_mass))
      return fail(std::string("this mode is given by ") +
                  (by_mass ? "mass_kg" : "stiffness_n_per_m") +
                  ": give either stiffness_n_per_m or mass_kg, not both");
  }
  if (const std::string why = f->set(out, index, Value(f->unit.to_si(value))); !why.empty())
    return fail(why);

  Problems problems(nullptr);
  const std::string table = table_path(*s, index);
  if (created)
    for (const Field& g : s->fields)
      if (g.required && &g != f) problems.missing(key_path(table, g.key));
  // The other keys as the Case holds them, in their units; this one as given.
  const Quote quote{[&](const std::string& p) -> std::optional<std::string> {
    if (p == path) return number_text(value);
    const auto kp = split_key(p);
    if (!kp) return std::nullopt;
    const Section* ps = find_section(kp->section, plan);
    const Field* pf = ps != nullptr ? ps->find(kp->key) : nullptr;
    if (pf == nullptr || ps->count(out) <= kp->index.value_or(0)) return std::nullopt;
    const auto v = pf->get(out, kp->index.value_or(0));
    if (!v) return std::nullopt;
    return detail::value_text(*pf, *v);
  }};
  rules_all(out, problems, quote);
  if (!problems.empty()) throw InvalidInput(problems.take(), where);
  return out;
}

Case load_case_file(const std::filesystem::path& path) {
  const std::string where = path.string();
  auto fail = [&](int error) -> Case {
    throw InvalidInput({"cannot read the file: " + std::generic_category().message(error)}, where);
  };
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return fail(EISDIR);
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) return fail(errno != 0 ? errno : ENOENT);
  std::ostringstream content;
  content << in.rdbuf();
  if (in.bad()) return fail(errno != 0 ? errno : EIO);
  note_input(path);
  return parse_case(content.str(), where);
}

const std::vector<std::pair<std::string_view, std::string_view>>& examples() {
  // The generator sorts by file name, where "a-b.toml" comes before "a.toml"; sort by name.
  static const std::vector<std::pair<std::string_view, std::string_view>> sorted = [] {
    auto list = detail::embedded_examples();
    std::sort(list.begin(), list.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    return list;
  }();
  return sorted;
}

std::optional<std::string_view> example_text(std::string_view name) {
  for (const auto& [example_name, text] : examples()) {
    if (example_name == name) return text;
  }
  return std::nullopt;
}

Case load_example(std::string_view name) {
  const std::string source = "example " + std::string(name);
  const auto text = example_text(name);
  if (!text) {
    std::string names;
    for (const auto& entry : examples()) {
      if (!names.empty()) names += ", ";
      names += entry.first;
    }
    throw InvalidInput(
        {"no built-in example called \"" + std::string(name) + "\"; available: " + names}, source);
  }
  return parse_case(*text, source);
}

nlohmann::json to_json(const Case& c) {
  using nlohmann::json;
  const bool plan = c.process == Process::kBoreMilling;
  json j = json::object();
  for (const Section& s : detail::case_sections()) {
    if (s.plan != plan) continue;
    const std::size_t n = s.count(c);
    for (std::size_t i = 0; i < n; ++i) {
      json table = json::object();
      for (const Field& f : s.fields) {
        if (!f.echo || (!plan && !f.used_in(c.process)) || (f.echo_if && !f.echo_if(c, i)))
          continue;
        const auto v = f.get(c, i);
        if (!v) continue;
        json& out = table[std::string(f.key)];
        if (const double* x = std::get_if<double>(&*v)) {
          out = f.type == Type::kInteger ? json(static_cast<std::int64_t>(*x))
                                         : json(tidy(f.unit.from_si(*x)));
        } else if (const bool* b = std::get_if<bool>(&*v)) {
          out = *b;
        } else if (const std::string* text = std::get_if<std::string>(&*v)) {
          out = *text;
        } else {
          out = json::array();
          for (double e : std::get<std::vector<double>>(*v)) out.push_back(tidy(f.unit.from_si(e)));
        }
      }
      if (table.empty() && !s.echo_empty) continue;
      if (s.name.empty()) {
        j.update(table);
      } else if (s.array) {
        j[std::string(s.name)].push_back(std::move(table));
      } else if (const auto dot = s.name.find('.'); dot != std::string_view::npos) {
        j[std::string(s.name.substr(0, dot))][std::string(s.name.substr(dot + 1))] =
            std::move(table);
      } else {
        j[std::string(s.name)].update(table);
      }
    }
  }
  return j;
}

}  // namespace cutdyn::io
