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
#include <sstream>
#include <system_error>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn::io {

namespace detail {
// Generated at build time from examples/*.toml (cmake/write_embedded_examples.cmake).
const std::vector<std::pair<std::string_view, std::string_view>>& embedded_examples();
}  // namespace detail

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

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

// A key as it would be written in a TOML path: bare if it can be, else quoted.
std::string key_text(std::string_view key) {
  const bool bare = !key.empty() && std::all_of(key.begin(), key.end(), [](char ch) {
    return (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') ||
           ch == '_' || ch == '-';
  });
  if (bare) return std::string(key);
  std::string quoted = "\"";
  for (char ch : key) {
    if (ch == '"' || ch == '\\') quoted += '\\';
    quoted += ch;
  }
  return quoted + "\"";
}

std::string join_quoted(std::initializer_list<std::string_view> names) {
  std::string text;
  for (std::string_view name : names) {
    if (!text.empty()) text += ", ";
    text += '"';
    text += name;
    text += '"';
  }
  return text;
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

// ---- problems --------------------------------------------------------------------------

class Problems {
 public:
  explicit Problems(const SourceText& source) : source_(source) {}

  // "<key> = <value as written>: <rule>" (or "<key>: <rule>" when there is no value).
  void at(const std::string& key, const toml::node& node, std::string_view rule) {
    list_.push_back(key + value_part(node) + ": " + std::string(rule));
  }
  // "<key>: missing (<why>)".
  void missing(const std::string& key, std::string_view why = "required") {
    list_.push_back(key + ": missing (" + std::string(why) + ")");
  }
  void add(std::string problem) { list_.push_back(std::move(problem)); }

  std::string value_part(const toml::node& node) const {
    const std::string written = source_.as_written(node);
    return written.empty() ? std::string{} : " = " + written;
  }
  std::string written(const toml::node& node) const { return source_.as_written(node); }

  bool empty() const { return list_.empty(); }
  std::size_t size() const { return list_.size(); }
  std::vector<std::string> take() { return std::move(list_); }

 private:
  const SourceText& source_;
  std::vector<std::string> list_;
};

// ---- reading one table -----------------------------------------------------------------

// An allowed interval for a number, with its rule text ("must be positive", "must be at
// least 0 and less than 1", ...).
struct Range {
  double lo = -kInf;
  bool lo_open = true;
  double hi = kInf;
  bool hi_open = true;

  bool contains(double v) const {
    return (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  }
  std::string rule() const {
    if (lo == 0.0 && lo_open && hi == kInf) return "must be positive";
    std::string text = "must be ";
    if (lo > -kInf) text += (lo_open ? "greater than " : "at least ") + format_value(lo);
    if (lo > -kInf && hi < kInf) text += " and ";
    if (hi < kInf) text += (hi_open ? "less than " : "at most ") + format_value(hi);
    return text;
  }
};

constexpr Range kPositive{0.0, true, kInf, true};
constexpr Range kNonNegative{0.0, false, kInf, true};

enum class Need { kRequired, kOptional };

class TableReader {
 public:
  // `path` is "" at the top level, else "lobes" or "modes[0]"; `known` lists every key the
  // table may hold.
  TableReader(Problems& problems, const toml::table& table, std::string path,
              std::initializer_list<std::string_view> known)
      : problems_(problems), table_(table), path_(std::move(path)), known_(known) {}

  std::string key_path(std::string_view key) const {
    return path_.empty() ? key_text(key) : path_ + "." + key_text(key);
  }
  const toml::node* get(std::string_view key) const { return table_.get(key); }
  bool has(std::string_view key) const { return table_.contains(key); }

  // A finite number (integer or float) in `range`, or a problem at `where`.
  std::optional<double> checked_number(const toml::node& node, const std::string& where,
                                       const Range& range) {
    double value = 0.0;
    if (const auto* i = node.as_integer()) {
      value = static_cast<double>(i->get());
    } else if (const auto* f = node.as_floating_point()) {
      value = f->get();
    } else {
      problems_.at(where, node,
                   std::string("wrong type: expected a number, got ") + type_name(node));
      return std::nullopt;
    }
    if (!std::isfinite(value)) {
      problems_.at(where, node, "must be a finite number");
      return std::nullopt;
    }
    if (!range.contains(value)) {
      problems_.at(where, node, range.rule());
      return std::nullopt;
    }
    return value;
  }

  std::optional<double> number(std::string_view key, const Range& range, Need need) {
    const toml::node* node = get(key);
    if (node == nullptr) {
      if (need == Need::kRequired) problems_.missing(key_path(key));
      return std::nullopt;
    }
    return checked_number(*node, key_path(key), range);
  }

  /// An array of numbers, each in `range`.
  std::optional<std::vector<double>> numbers(std::string_view key, const Range& range, Need need) {
    const toml::node* node = get(key);
    if (node == nullptr) {
      if (need == Need::kRequired) problems_.missing(key_path(key));
      return std::nullopt;
    }
    const toml::array* array = node->as_array();
    if (array == nullptr || array->empty()) {
      problems_.at(key_path(key), *node,
                   std::string("wrong type: expected a non-empty array of numbers, got ") +
                       type_name(*node));
      return std::nullopt;
    }
    std::vector<double> values;
    for (std::size_t i = 0; i < array->size(); ++i) {
      const auto v =
          checked_number(*array->get(i), key_path(key) + "[" + std::to_string(i) + "]", range);
      if (v) values.push_back(*v);
    }
    if (values.size() != array->size()) return std::nullopt;
    return values;
  }

  std::optional<std::string> text(std::string_view key, Need need) {
    const toml::node* node = get(key);
    if (node == nullptr) {
      if (need == Need::kRequired) problems_.missing(key_path(key));
      return std::nullopt;
    }
    const auto* s = node->as_string();
    if (s == nullptr) {
      problems_.at(key_path(key), *node,
                   std::string("wrong type: expected a string, got ") + type_name(*node));
      return std::nullopt;
    }
    return s->get();
  }

  std::optional<bool> boolean(std::string_view key) {
    const toml::node* node = get(key);
    if (node == nullptr) return std::nullopt;
    const auto* b = node->as_boolean();
    if (b == nullptr) {
      problems_.at(key_path(key), *node,
                   std::string("wrong type: expected true or false, got ") + type_name(*node));
      return std::nullopt;
    }
    return b->get();
  }

  /// A missing key whose need depends on others.
  void problem_missing(std::string_view key, std::string_view why) {
    problems_.missing(key_path(key), why);
  }

  /// A problem with the value of `key` (which is present).
  void problem(std::string_view key, std::string_view rule) {
    problems_.at(key_path(key), *get(key), rule);
  }

  std::optional<int> integer(std::string_view key, int lo, int hi, Need need) {
    const toml::node* node = get(key);
    if (node == nullptr) {
      if (need == Need::kRequired) problems_.missing(key_path(key));
      return std::nullopt;
    }
    const auto* i = node->as_integer();
    if (i == nullptr) {
      problems_.at(key_path(key), *node,
                   std::string("wrong type: expected an integer, got ") + type_name(*node));
      return std::nullopt;
    }
    const std::int64_t value = i->get();
    if (value < lo || value > hi) {
      problems_.at(key_path(key), *node,
                   "must be an integer from " + std::to_string(lo) + " to " + std::to_string(hi));
      return std::nullopt;
    }
    return static_cast<int>(value);
  }

  std::optional<std::string> choice(std::string_view key,
                                    std::initializer_list<std::string_view> options, Need need) {
    auto value = text(key, need);
    if (value && std::find(options.begin(), options.end(), *value) == options.end()) {
      problems_.at(key_path(key), *get(key), "must be one of " + join_quoted(options));
      return std::nullopt;
    }
    return value;
  }

  // "lobes.rpm_stepz: unknown key (did you mean rpm_steps?)" for every key not in `known`.
  void report_unknown() {
    for (auto&& [key, node] : table_) {
      const std::string_view name = key.str();
      if (std::find(known_.begin(), known_.end(), name) != known_.end()) continue;
      std::string problem =
          key_path(name) + (node.is_table() ? ": unknown table" : ": unknown key");
      std::string_view best;
      std::size_t best_distance = 3;
      for (std::string_view candidate : known_) {
        const std::size_t d = edit_distance(name, candidate);
        if (d < best_distance) {
          best_distance = d;
          best = candidate;
        }
      }
      if (!best.empty()) problem += " (did you mean " + std::string(best) + "?)";
      problems_.add(std::move(problem));
    }
  }

  // The sub-table `key`, or nullptr when absent or not a table (then a problem is recorded).
  const toml::table* section(std::string_view key) {
    const toml::node* node = get(key);
    if (node == nullptr) return nullptr;
    if (const toml::table* table = node->as_table()) return table;
    problems_.at(key_path(key), *node,
                 std::string("wrong type: expected a table ([") + std::string(key) + "]), got " +
                     type_name(*node));
    return nullptr;
  }

  Problems& problems() { return problems_; }

 private:
  Problems& problems_;
  const toml::table& table_;
  std::string path_;
  std::vector<std::string_view> known_;
};

using units::m_per_min_to_m_per_s;
using units::m_per_s_to_m_per_min;
using units::m_to_mm;
using units::m_to_um;
using units::mm_to_m;
using units::n_per_mm2_to_pa;
using units::pa_to_n_per_mm2;
using units::um_to_m;

// ---- sections ----------------------------------------------------------------------------

// Calls read(path, table) for every element of an array of tables ("name[i]"); an element
// that is not a table is a problem.
template <typename Read>
void for_each_table(Problems& problems, const toml::array& array, const std::string& name,
                    Read read) {
  for (std::size_t i = 0; i < array.size(); ++i) {
    const std::string path = name + "[" + std::to_string(i) + "]";
    const toml::node& element = *array.get(i);
    const toml::table* table = element.as_table();
    if (table == nullptr) {
      problems.at(path, element,
                  std::string("wrong type: expected a table, got ") + type_name(element));
      continue;
    }
    read(path, *table);
  }
}

void read_mode(TableReader& t, std::optional<Process> process, Case& c) {
  const auto direction = t.choice("direction", {"x", "y"}, Need::kRequired);
  const auto hz = t.number("natural_hz", kPositive, Need::kRequired);
  const auto zeta = t.number("damping_ratio", Range{0.0, false, 1.0, true}, Need::kRequired);
  const auto k = t.number("stiffness_n_per_m", kPositive, Need::kOptional);
  const auto m = t.number("mass_kg", kPositive, Need::kOptional);
  const toml::node* k_node = t.get("stiffness_n_per_m");
  const toml::node* m_node = t.get("mass_kg");
  Problems& problems = t.problems();
  if (k_node != nullptr && m_node != nullptr) {
    problems.add(t.key_path("stiffness_n_per_m") + problems.value_part(*k_node) + " and " +
                 t.key_path("mass_kg") + problems.value_part(*m_node) +
                 ": give either stiffness_n_per_m or mass_kg, not both");
  } else if (k_node == nullptr && m_node == nullptr) {
    problems.missing(t.key_path("stiffness_n_per_m"), "required unless mass_kg is given");
  }
  if (process == Process::kTurning && direction == "y") {
    problems.at(t.key_path("direction"), *t.get("direction"),
                "turning models the feed direction \"x\" only");
  }
  t.report_unknown();
  if (!direction || !hz || !zeta || (!k && !m) || (k && m)) return;
  const Direction dir = *direction == "x" ? Direction::kX : Direction::kY;
  const double w = units::hz_to_rad_per_s(*hz);
  c.modal.modes.push_back(k ? Mode{dir, w, *zeta, *k} : mode_from_mass(dir, w, *zeta, *m));
}

void read_modes(TableReader& top, std::optional<Process> process, Case& c) {
  Problems& problems = top.problems();
  const toml::node* node = top.get("modes");
  if (node == nullptr) {
    problems.missing("modes", "required: at least one [[modes]] table");
    return;
  }
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
  for_each_table(problems, *array, "modes", [&](const std::string& path, const toml::table& table) {
    TableReader t(problems, table, path,
                  {"direction", "natural_hz", "damping_ratio", "stiffness_n_per_m", "mass_kg"});
    read_mode(t, process, c);
  });
}

void read_drive(TableReader& t, Case& c) {
  FeedAxis axis;
  axis.name = "axis " + std::to_string(c.drives.size());
  if (auto v = t.choice("axis", {"x", "y", "z"}, Need::kOptional)) {
    axis.name = *v;
    for (int k = 0; k < 3; ++k) axis.direction[k] = k == (*v)[0] - 'x' ? 1.0 : 0.0;
  }
  if (auto v = t.numbers("direction", Range{}, Need::kOptional)) {
    const double norm = v->size() == 3 ? std::hypot((*v)[0], (*v)[1], (*v)[2]) : 0.0;
    if (t.has("axis")) {
      t.problem("direction", "give axis or direction, not both");
    } else if (v->size() != 3 || !(norm > 0.0)) {
      t.problem("direction", "must be three numbers (x, y, z), not all zero");
    } else {
      for (int k = 0; k < 3; ++k) axis.direction[k] = (*v)[static_cast<std::size_t>(k)] / norm;
    }
  }
  if (!t.has("axis") && !t.has("direction"))
    t.problem_missing("axis", "axis or direction is required");
  Transmission& tr = axis.drive.transmission;
  if (auto v = t.choice("transmission", {"ball-screw", "lever"}, Need::kRequired))
    tr.kind = *v == "lever" ? Transmission::Kind::kLeverArm : Transmission::Kind::kBallScrew;
  const Need screw = tr.kind == Transmission::Kind::kBallScrew ? Need::kRequired : Need::kOptional;
  const Need arm = tr.kind == Transmission::Kind::kLeverArm ? Need::kRequired : Need::kOptional;
  if (auto v = t.number("lead_mm", kPositive, screw)) tr.lead_m = mm_to_m(*v);
  if (auto v = t.number("efficiency", Range{0.0, true, 1.0, false}, Need::kOptional))
    tr.efficiency = *v;
  if (auto v = t.number("gear_ratio", kPositive, Need::kOptional)) tr.gear_ratio = *v;
  if (auto v = t.number("output_diameter_mm", kPositive, arm)) tr.output_diameter_m = mm_to_m(*v);
  if (auto v = t.number("ratio", kPositive, Need::kOptional)) tr.ratio = *v;
  if (auto v = t.number("idle_torque_nm", Range{}, Need::kOptional)) tr.idle_torque_nm = *v;
  FeedDrive& d = axis.drive;
  if (auto v = t.choice("model", {"static", "dynamic"}, Need::kOptional))
    d.model = *v == "dynamic" ? FeedDrive::Model::kDynamic : FeedDrive::Model::kStatic;
  const bool dynamic = d.model == FeedDrive::Model::kDynamic;
  if (auto v = t.number("stiffness_nm_s_per_rad", Range{},
                        dynamic ? Need::kOptional : Need::kRequired)) {
    if (*v == 0.0)
      t.problem("stiffness_nm_s_per_rad", "must not be 0 (|β|, the slope of the characteristic)");
    d.stiffness_nm_s_per_rad = *v;
  }
  const Need dyn = dynamic ? Need::kRequired : Need::kOptional;
  if (auto v = t.number("inertia_kg_m2", kPositive, dyn)) d.inertia_kg_m2 = *v;
  if (auto v = t.number("viscous_nm_s_per_rad", kNonNegative, Need::kOptional))
    d.viscous_nm_s_per_rad = *v;
  if (auto v = t.number("kp_nm_s_per_rad", kPositive, dyn)) d.kp_nm_s_per_rad = *v;
  if (auto v = t.number("ki_nm_per_rad", kNonNegative, dyn)) d.ki_nm_per_rad = *v;
  if (auto v = t.number("torque_limit_nm", kNonNegative, Need::kOptional)) d.torque_limit_nm = *v;
  // The motor, for phase currents: given by its torque constant.
  if (t.has("torque_constant_nm_per_a") || t.has("pole_pairs")) {
    PmsmMotor m;
    if (auto v = t.integer("pole_pairs", 1, 100, Need::kRequired)) m.pole_pairs = *v;
    if (auto v = t.number("torque_constant_nm_per_a", kPositive, Need::kRequired))
      m.torque_constant_nm_per_a = *v;
    if (auto v = t.choice("current_measure", {"rms", "space-vector"}, Need::kOptional))
      m.measure = *parse_current_measure(*v);
    if (auto v = t.number("current_noise_a", kNonNegative, Need::kOptional)) m.noise_a = *v;
    if (auto v = t.numbers("current_offset_a", Range{}, Need::kOptional)) {
      if (v->size() != 3)
        t.problem("current_offset_a", "must be three numbers (phases u, v, w)");
      else
        for (int k = 0; k < 3; ++k) m.offset_a[k] = (*v)[static_cast<std::size_t>(k)];
    }
    // The noise's seed; each axis draws its own stream of it (its index in [[drives]]).
    if (auto v = t.integer("seed", 0, 2147483647, Need::kOptional))
      m.seed = static_cast<unsigned>(*v);
    m.stream = static_cast<unsigned>(c.drives.size());
    axis.motor = m;
  } else {
    for (const char* key : {"current_measure", "current_noise_a", "current_offset_a", "seed"})
      if (t.has(key)) t.problem(key, "needs the motor: pole_pairs and torque_constant_nm_per_a");
  }
  t.report_unknown();
  c.drives.push_back(axis);
}

void read_drives(TableReader& top, Case& c) {
  Problems& problems = top.problems();
  const toml::node* node = top.get("drives");
  if (node == nullptr) return;
  const toml::array* array = node->as_array();
  if (array == nullptr || array->empty() || array->size() > 3) {
    problems.at("drives", *node, "must be one to three [[drives]] tables");
    return;
  }
  for_each_table(problems, *array, "drives",
                 [&](const std::string& path, const toml::table& table) {
                   TableReader t(problems, table, path,
                                 {"axis",
                                  "direction",
                                  "transmission",
                                  "lead_mm",
                                  "efficiency",
                                  "gear_ratio",
                                  "output_diameter_mm",
                                  "ratio",
                                  "idle_torque_nm",
                                  "model",
                                  "stiffness_nm_s_per_rad",
                                  "inertia_kg_m2",
                                  "viscous_nm_s_per_rad",
                                  "kp_nm_s_per_rad",
                                  "ki_nm_per_rad",
                                  "torque_limit_nm",
                                  "pole_pairs",
                                  "torque_constant_nm_per_a",
                                  "current_measure",
                                  "current_noise_a",
                                  "current_offset_a",
                                  "seed"});
                   read_drive(t, c);
                 });
}

void read_cutting(TableReader& t, Case& c) {
  CuttingSection& s = c.cutting;
  if (auto v = t.number("kt_n_per_mm2", kPositive, Need::kOptional)) s.kt_pa = n_per_mm2_to_pa(*v);
  if (auto v = t.number("kc_n_per_mm2", kPositive, Need::kOptional)) s.kc_pa = n_per_mm2_to_pa(*v);
  if (auto v = t.number("kr_n_per_mm2", kNonNegative, Need::kOptional)) {
    s.kr_pa = n_per_mm2_to_pa(*v);
  }
  if (auto v = t.number("speed_m_per_min", kPositive, Need::kOptional)) {
    s.speed_m_per_s = m_per_min_to_m_per_s(*v);
  }
  if (auto v = t.number("uncut_chip_thickness_mm", kPositive, Need::kOptional)) {
    s.uncut_chip_thickness_m = mm_to_m(*v);
  }
  if (auto v = t.number("width_mm", kPositive, Need::kOptional)) s.width_m = mm_to_m(*v);
  if (auto v = t.number("kte_n_per_mm", kNonNegative, Need::kOptional)) s.kte_n_per_m = 1e3 * *v;
  if (auto v = t.number("kre_n_per_mm", kNonNegative, Need::kOptional)) s.kre_n_per_m = 1e3 * *v;
  if (auto v = t.number("rake_deg", Range{-45.0, true, 45.0, true}, Need::kOptional))
    s.rake_rad = units::deg_to_rad(*v);
  if (auto v =
          t.number("workpiece_temperature_c", Range{-273.15, true, kInf, true}, Need::kOptional))
    s.workpiece_temperature_c = *v;
  t.report_unknown();
}

void read_tool(TableReader& t, Case& c) {
  ToolSection s;
  if (auto v = t.integer("teeth", 1, 200, Need::kRequired)) s.teeth = *v;
  if (auto v = t.number("diameter_mm", kPositive, Need::kRequired)) s.diameter_m = mm_to_m(*v);
  if (auto v = t.number("helix_deg", Range{0.0, false, 90.0, true}, Need::kOptional)) {
    s.helix_rad = units::deg_to_rad(*v);
  }
  if (auto v = t.numbers("pitch_deg", Range{0.0, true, 360.0, true}, Need::kOptional)) {
    double sum = 0.0;
    for (double p : *v) sum += p;
    if (static_cast<int>(v->size()) != s.teeth && s.teeth > 0) {
      t.problem("pitch_deg", "must give one angle per tooth (teeth = " + std::to_string(s.teeth) +
                                 "), got " + std::to_string(v->size()));
    } else if (std::abs(sum - 360.0) > 1e-6) {
      t.problem("pitch_deg", "the angles must add up to 360, they add up to " + format_value(sum));
    } else {
      for (double p : *v) s.pitch_rad.push_back(units::deg_to_rad(p));
      // Exactly one revolution, whatever the rounding of the degrees.
      const double scale = units::kTwoPi / [&] {
        double total = 0.0;
        for (double p : s.pitch_rad) total += p;
        return total;
      }();
      for (double& p : s.pitch_rad) p *= scale;
    }
  }
  t.report_unknown();
  c.tool = s;
}

void read_operation(TableReader& t, Case& c) {
  OperationSection s;
  if (auto v = t.number("radial_immersion", Range{0.0, true, 1.0, false}, Need::kOptional)) {
    s.radial_immersion = *v;
  }
  if (auto v = t.choice("direction", {"down", "up"}, Need::kOptional))
    s.down_milling = *v == "down";
  if (auto v = t.number("feed_per_tooth_mm", kPositive, Need::kOptional))
    s.feed_per_tooth_m = mm_to_m(*v);
  const Range half_turn{0.0, false, 180.0, false};
  const auto entry = t.number("entry_deg", half_turn, Need::kOptional);
  const auto exit = t.number("exit_deg", half_turn, Need::kOptional);
  if (entry.has_value() != exit.has_value()) {
    t.problem(entry ? "entry_deg" : "exit_deg", "give entry_deg and exit_deg together");
  } else if (entry && *entry >= *exit) {
    t.problem("exit_deg", "must be greater than entry_deg = " + format_value(*entry));
  } else if (entry) {
    s.entry_rad = units::deg_to_rad(*entry);
    s.exit_rad = units::deg_to_rad(*exit);
  }
  t.report_unknown();
  c.operation = s;
}

void read_vibration(TableReader& t, Case& c) {
  VibrationSection s;
  if (auto v = t.number("frequency_hz", kPositive, Need::kRequired)) s.frequency_hz = *v;
  if (auto v = t.number("amplitude_um", kPositive, Need::kOptional)) s.amplitude_m = um_to_m(*v);
  if (auto v = t.number("workpiece_diameter_mm", kPositive, Need::kOptional)) {
    s.workpiece_diameter_m = mm_to_m(*v);
  }
  if (auto v = t.number("duty_cycle", Range{0.0, true, 1.0, false}, Need::kOptional)) {
    s.duty_cycle = *v;
  }
  Problems& problems = t.problems();
  const toml::node* duty = t.get("duty_cycle");
  const toml::node* diameter = t.get("workpiece_diameter_mm");
  if (duty != nullptr && diameter != nullptr) {
    problems.add(t.key_path("duty_cycle") + problems.value_part(*duty) + " and " +
                 t.key_path("workpiece_diameter_mm") + problems.value_part(*diameter) +
                 ": give either duty_cycle (fixed) or workpiece_diameter_mm (duty cycle from the "
                 "cutting speed), not both");
  }
  if (duty == nullptr && !t.has("amplitude_um")) {
    problems.missing(t.key_path("amplitude_um"), "required unless duty_cycle is given");
  }
  t.report_unknown();
  c.vibration = s;
}

void read_lobes(TableReader& t, Case& c) {
  LobesSection& s = c.lobes;
  const LobesSection defaults;
  const auto rpm_min = t.number("rpm_min", kPositive, Need::kOptional);
  const auto rpm_max = t.number("rpm_max", kPositive, Need::kOptional);
  if (rpm_min) s.rpm_min = *rpm_min;
  if (rpm_max) s.rpm_max = *rpm_max;
  const toml::node* min_node = t.get("rpm_min");
  const toml::node* max_node = t.get("rpm_max");
  const bool min_ok = min_node == nullptr || rpm_min.has_value();
  const bool max_ok = max_node == nullptr || rpm_max.has_value();
  if (min_ok && max_ok && !(s.rpm_max > s.rpm_min)) {
    Problems& problems = t.problems();
    if (max_node != nullptr) {
      const std::string min_text = min_node != nullptr
                                       ? problems.written(*min_node)
                                       : format_value(defaults.rpm_min) + " (default)";
      problems.at(t.key_path("rpm_max"), *max_node,
                  "must be greater than " + t.key_path("rpm_min") + " = " + min_text);
    } else {
      problems.at(t.key_path("rpm_min"), *min_node,
                  "must be less than " + t.key_path("rpm_max") + " = " +
                      format_value(defaults.rpm_max) + " (default)");
    }
  }
  if (auto v = t.integer("rpm_steps", 2, 100000, Need::kOptional)) s.rpm_steps = *v;
  if (auto v = t.number("depth_max_mm", Range{0.0, true, 10000.0, false}, Need::kOptional)) {
    s.depth_max_m = mm_to_m(*v);
  }
  if (auto v = t.choice("method",
                        {"auto", "zero-order", "closed-form", "multi-frequency",
                         "full-discretization", "full-discretization-dense"},
                        Need::kOptional)) {
    s.method = *parse_stability_method(*v);
  }
  if (auto v = t.integer("harmonics", 0, 50, Need::kOptional)) s.harmonics = *v;
  if (auto v = t.integer("steps_per_period", 0, 100000, Need::kOptional)) s.steps_per_period = *v;
  if (auto v = t.boolean("refine")) s.refine = *v;
  t.report_unknown();
}

void read_simulate(TableReader& t, Case& c) {
  SimulateSection& s = c.simulate;
  if (auto v = t.number("rpm", kPositive, Need::kOptional)) s.rpm = *v;
  if (auto v = t.number("depth_mm", kPositive, Need::kOptional)) s.depth_m = mm_to_m(*v);
  if (auto v = t.number("duration_s", Range{0.0, true, 1000.0, false}, Need::kOptional)) {
    s.duration_s = *v;
  }
  if (auto v = t.number("initial_displacement_um", kPositive, Need::kOptional)) {
    s.initial_displacement_m = um_to_m(*v);
  }
  if (auto v = t.number("revolutions", Range{1.0, false, 1e6, false}, Need::kOptional))
    s.revolutions = *v;
  if (auto v = t.number("summary_revolutions", kPositive, Need::kOptional))
    s.summary_revolutions = *v;
  if (s.summary_revolutions > s.revolutions)
    t.problem("summary_revolutions",
              "must be at most revolutions = " + format_value(s.revolutions));
  if (auto v = t.boolean("regenerative")) s.regenerative = *v;
  if (auto v = t.integer("steps_per_tooth", 8, 100000, Need::kOptional)) s.steps_per_tooth = *v;
  if (auto v = t.integer("slices", 0, 10000, Need::kOptional)) s.slices = *v;
  if (auto v = t.boolean("closed_form_helix")) s.closed_form_helix = *v;
  t.report_unknown();
}

void read_force_law(TableReader& t, Case& c) {
  ForceLawSection s;
  if (auto v = t.number("c_n_per_mm", kNonNegative, Need::kRequired)) s.c_n_per_m = 1e3 * *v;
  if (auto v = t.number("t2_s", kNonNegative, Need::kOptional)) s.t2_s = *v;
  if (auto v = t.number("p0_n", kNonNegative, Need::kOptional)) s.p0_n = *v;
  if (auto v = t.number("t1_mm", kPositive, Need::kOptional)) s.t1_m = mm_to_m(*v);
  const Range angle{-90.0, false, 90.0, false};
  if (auto v = t.number("phi_rez_deg", angle, Need::kOptional))
    s.phi_rez_rad = units::deg_to_rad(*v);
  if (auto v = t.number("phi_skv_deg", angle, Need::kOptional))
    s.phi_skv_rad = units::deg_to_rad(*v);
  t.report_unknown();
  c.force_law = s;
}

void read_material(TableReader& t, Case& c) {
  Problems& problems = t.problems();
  WorkMaterial material;
  const auto name = t.text("name", Need::kOptional);
  const WorkMaterial* entry = name ? find_material(*name) : nullptr;
  const toml::table* jc_table = t.section("johnson_cook");
  const toml::table* th_table = t.section("thermal");
  if (name && !entry && (jc_table == nullptr || th_table == nullptr)) {
    std::string names;
    for (const WorkMaterial& m : material_library()) names += (names.empty() ? "" : ", ") + m.name;
    t.problem("name", "is not in the material library (" + names +
                          "); give it, or your own [material.johnson_cook] and "
                          "[material.thermal] tables");
    t.report_unknown();
    return;
  }
  if (!name && (jc_table == nullptr || th_table == nullptr)) {
    problems.missing(t.key_path("name"),
                     "give a library material, or both [material.johnson_cook] and "
                     "[material.thermal]");
    t.report_unknown();
    return;
  }
  if (entry) material = *entry;
  material.name = name.value_or("user material");
  if (!entry) material.reference = "given in the case";
  // Without a library entry every property is required; with one, each key overrides.
  const Need need = entry ? Need::kOptional : Need::kRequired;
  const std::size_t before = problems.size();
  const auto set = [&](TableReader& r, std::string_view key, const Range& range, Need n,
                       double scale, double& field) {
    if (auto v = r.number(key, range, n)) field = *v * scale;
  };
  if (jc_table != nullptr) {
    TableReader r(problems, *jc_table, t.key_path("johnson_cook"),
                  {"a_mpa", "b_mpa", "n", "c", "m", "reference_strain_rate_per_s",
                   "reference_temperature_c", "melting_temperature_c"});
    JohnsonCook& jc = material.flow;
    const Range celsius{-273.15, true, kInf, true};
    set(r, "a_mpa", kPositive, need, 1e6, jc.a_pa);
    set(r, "b_mpa", kNonNegative, need, 1e6, jc.b_pa);
    set(r, "n", Range{0.0, false, 1.0, true}, need, 1.0, jc.n);
    set(r, "c", Range{0.0, false, 1.0, true}, need, 1.0, jc.c);
    set(r, "m", Range{0.0, true, 10.0, false}, need, 1.0, jc.m);
    set(r, "reference_strain_rate_per_s", kPositive, Need::kOptional, 1.0,
        jc.reference_strain_rate_per_s);
    set(r, "reference_temperature_c", celsius, Need::kOptional, 1.0, jc.reference_temperature_c);
    set(r, "melting_temperature_c", celsius, need, 1.0, jc.melting_temperature_c);
    r.report_unknown();
  }
  if (th_table != nullptr) {
    TableReader r(
        problems, *th_table, t.key_path("thermal"),
        {"density_kg_per_m3", "specific_heat_j_per_kg_k", "specific_heat_slope_j_per_kg_k2",
         "conductivity_w_per_m_k", "conductivity_slope_w_per_m_k2"});
    ThermalProperties& th = material.thermal;
    const Range any{-kInf, true, kInf, true};
    set(r, "density_kg_per_m3", kPositive, need, 1.0, th.density_kg_per_m3);
    set(r, "specific_heat_j_per_kg_k", kPositive, need, 1.0, th.specific_heat_j_per_kg_k);
    set(r, "specific_heat_slope_j_per_kg_k2", any, Need::kOptional, 1.0,
        th.specific_heat_slope_j_per_kg_k2);
    set(r, "conductivity_w_per_m_k", kPositive, need, 1.0, th.conductivity_w_per_m_k);
    set(r, "conductivity_slope_w_per_m_k2", any, Need::kOptional, 1.0,
        th.conductivity_slope_w_per_m_k2);
    r.report_unknown();
  }
  t.report_unknown();
  if (problems.size() != before) return;
  // What only the whole material shows (Tm > Tr; S and K positive up to melting).
  Validator v;
  validate(material, v);
  for (const std::string& p : v.problems()) problems.add("material." + p);
  c.material = std::move(material);
}

void read_oxley(TableReader& t, Case& c) {
  OxleyOptions& o = c.oxley;
  if (auto v = t.number("c0_min", kPositive, Need::kOptional)) o.c0_min = *v;
  if (auto v = t.number("c0_max", kPositive, Need::kOptional)) o.c0_max = *v;
  if (auto v = t.number("delta_min", Range{0.0, true, 1.0, true}, Need::kOptional))
    o.delta_min = *v;
  if (auto v = t.number("delta_max", Range{0.0, true, 1.0, true}, Need::kOptional))
    o.delta_max = *v;
  if (auto v = t.number("eta", Range{0.0, true, 1.0, false}, Need::kOptional)) o.eta = *v;
  if (auto v = t.number("psi", Range{0.0, true, 1.0, false}, Need::kOptional)) o.psi = *v;
  t.report_unknown();
  if (o.c0_min >= o.c0_max)
    t.problems().add(t.key_path("c0_min") + " = " + format_value(o.c0_min) + " and " +
                     t.key_path("c0_max") + " = " + format_value(o.c0_max) +
                     ": c0_min must be less than c0_max");
  if (o.delta_min >= o.delta_max)
    t.problems().add(t.key_path("delta_min") + " = " + format_value(o.delta_min) + " and " +
                     t.key_path("delta_max") + " = " + format_value(o.delta_max) +
                     ": delta_min must be less than delta_max");
}

// ---- JSON --------------------------------------------------------------------------------

// A converted-back value, rounded to 15 significant digits so that the unit round trip
// prints what the file said (30, not 30.000000000000004); integral values print as integers.
nlohmann::json tidy(double value) {
  if (!std::isfinite(value)) return value;
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.15g", value);
  const double rounded = std::strtod(buffer, nullptr);
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

// A `cutdyn plan` case: [bore], [cutter] and the [process] table (models.md S2; product.md).
// A [process] TABLE marks it: TOML cannot hold both it and the `process = "..."` key of the
// dynamics cases (docs/case-files.md).
void read_bore_case(TableReader& top, Case& c) {
  Problems& problems = top.problems();
  c.process = Process::kBoreMilling;
  BoreMillingCase b;
  const Range angle{0.0, true, 90.0, false};
  if (const toml::table* t = top.section("bore")) {
    TableReader r(problems, *t, "bore", {"diameter_mm", "length_mm", "allowance_mm"});
    if (auto v = r.number("diameter_mm", kPositive, Need::kRequired))
      b.bore_diameter_m = mm_to_m(*v);
    if (auto v = r.number("length_mm", kPositive, Need::kRequired)) b.length_m = mm_to_m(*v);
    if (auto v = r.number("allowance_mm", kPositive, Need::kRequired)) b.allowance_m = mm_to_m(*v);
    if (b.bore_diameter_m > 0.0 && b.allowance_m >= 0.5 * b.bore_diameter_m)
      r.problem("allowance_mm", "must be less than the bore's radius");
    r.report_unknown();
  } else {
    problems.missing("bore", "required by a plan case: diameter_mm, length_mm, allowance_mm");
  }
  if (const toml::table* t = top.section("cutter")) {
    TableReader r(problems, *t, "cutter",
                  {"diameter_mm", "teeth", "offset_mm", "lead_angle_deg", "inclination_deg"});
    if (auto v = r.number("diameter_mm", kPositive, Need::kRequired))
      b.cutter_diameter_m = mm_to_m(*v);
    if (auto v = r.integer("teeth", 1, 500, Need::kRequired)) b.teeth = *v;
    if (auto v = r.number("offset_mm", Range{}, Need::kRequired)) b.offset_m = mm_to_m(*v);
    if (auto v = r.number("lead_angle_deg", angle, Need::kRequired))
      b.lead_angle_rad = units::deg_to_rad(*v);
    if (auto v = r.number("inclination_deg", Range{-90.0, true, 90.0, true}, Need::kOptional))
      b.inclination_rad = units::deg_to_rad(*v);
    if (b.cutter_diameter_m > 0.0 && b.bore_diameter_m > 0.0 &&
        b.cutter_diameter_m >= b.bore_diameter_m)
      r.problem("diameter_mm",
                "must be less than bore.diameter_mm = " + format_value(m_to_mm(b.bore_diameter_m)));
    r.report_unknown();
  } else {
    problems.missing("cutter",
                     "required by a plan case: diameter_mm, teeth, offset_mm, lead_angle_deg");
  }
  if (const toml::table* t = top.section("process")) {
    TableReader r(problems, *t, "process",
                  {"cutting_speed_m_per_min", "mean_chip_thickness_mm", "accuracy_coefficient",
                   "axial_feed_mm"});
    if (auto v = r.number("cutting_speed_m_per_min", kPositive, Need::kRequired))
      b.cutting_speed_m_per_s = *v / 60.0;
    if (auto v = r.number("mean_chip_thickness_mm", kPositive, Need::kRequired))
      b.mean_chip_thickness_m = mm_to_m(*v);
    if (auto v = r.number("accuracy_coefficient", Range{}, Need::kRequired)) {
      if (*v < kAccuracyCoefficientMin || *v > kAccuracyCoefficientMax)
        r.problem("accuracy_coefficient",
                  "must be from 0.005 (finishing) to 0.1 (roughing), the source's range of k");
      else
        b.accuracy_coefficient = *v;
    }
    if (auto v = r.number("axial_feed_mm", kPositive, Need::kOptional))
      c.axial_feed_m = mm_to_m(*v);
    r.report_unknown();
  }
  if (const toml::table* t = top.section("limits")) {
    TableReader r(
        problems, *t, "limits",
        {"offset_min_mm", "offset_max_mm", "cutting_speed_max_m_per_min", "cutter_rpm_max",
         "workpiece_rpm_max", "faceting_max_mm", "max_chip_thickness_mm"});
    BoreMillingLimits l;
    if (auto v = r.number("offset_min_mm", Range{}, Need::kRequired)) l.offset_min_m = mm_to_m(*v);
    if (auto v = r.number("offset_max_mm", Range{}, Need::kRequired)) l.offset_max_m = mm_to_m(*v);
    if (l.offset_max_m < l.offset_min_m)
      r.problem("offset_max_mm", "must be at least offset_min_mm");
    if (auto v = r.number("cutting_speed_max_m_per_min", kPositive, Need::kRequired))
      l.cutting_speed_max_m_per_s = *v / 60.0;
    if (auto v = r.number("cutter_rpm_max", kPositive, Need::kRequired))
      l.cutter_rev_per_s_max = *v / 60.0;
    if (auto v = r.number("workpiece_rpm_max", kPositive, Need::kRequired))
      l.workpiece_rev_per_s_max = *v / 60.0;
    if (auto v = r.number("faceting_max_mm", kPositive, Need::kRequired))
      l.faceting_max_m = mm_to_m(*v);
    if (auto v = r.number("max_chip_thickness_mm", kPositive, Need::kRequired))
      l.max_chip_thickness_m = mm_to_m(*v);
    r.report_unknown();
    c.bore_limits = l;
  }
  c.bore = b;
  top.report_unknown();
}

// ---- which process takes which key ----------------------------------------------------------

// The keys of a table that each process uses, and the tables a process does not take. A key
// or table that the case's process does not use is an error (it would be silently ignored):
// it is reported here and taken out before the tables are read, so it gets this one problem.
struct ProcessKeys {
  std::string_view table;
  std::initializer_list<std::string_view> turning, milling;
};

constexpr std::string_view kTurningCutting[] = {
    "kt_n_per_mm2", "kc_n_per_mm2", "speed_m_per_min",        "uncut_chip_thickness_mm",
    "width_mm",     "rake_deg",     "workpiece_temperature_c"};
constexpr std::string_view kMillingCutting[] = {"kt_n_per_mm2", "kr_n_per_mm2", "kte_n_per_mm",
                                                "kre_n_per_mm"};
constexpr std::string_view kTurningSimulate[] = {"rpm", "depth_mm", "duration_s",
                                                 "initial_displacement_um"};
constexpr std::string_view kMillingSimulate[] = {
    "rpm",          "depth_mm",        "revolutions", "summary_revolutions",
    "regenerative", "steps_per_tooth", "slices",      "closed_form_helix"};

template <std::size_t N>
bool listed(const std::string_view (&keys)[N], std::string_view key) {
  return std::find(std::begin(keys), std::end(keys), key) != std::end(keys);
}

template <std::size_t N>
std::string list_text(const std::string_view (&keys)[N]) {
  std::string text;
  for (std::string_view k : keys) text += (text.empty() ? "" : ", ") + std::string(k);
  return text;
}

// Takes out of `root` every key and table that `process` does not use, with a problem for
// each (docs/case-files.md, "Which process takes which key").
void remove_unused(toml::table& root, Process process, Problems& problems) {
  const bool milling = process == Process::kMilling;
  const char* name = milling ? "milling" : "turning";
  // Whole tables of the other process.
  const auto drop_table = [&](std::string_view table, std::string_view why) {
    if (const toml::node* node = root.get(table)) {
      problems.at(std::string(table), *node, why);
      root.erase(table);
    }
  };
  if (milling) {
    drop_table("vibration",
               "not used in a milling case (vibration-assisted cutting is modelled for turning)");
  } else {
    for (std::string_view t : {"tool", "operation", "force_law"})
      drop_table(t, "not used in a turning case (" + std::string(t) +
                        " is a milling table: tool, operation, force_law)");
    drop_table("drives",
               "not used in a turning case (`cutdyn drive` takes milling cases: the feed drives "
               "under the milling force)");
  }
  if (!root.contains("material"))
    drop_table("oxley", "used only with a [material] (the settings of Oxley's theory)");
  // Keys of the other process in the shared tables.
  const auto drop_keys = [&](std::string_view table, auto&& used, const std::string& takes) {
    toml::table* t = root[table].as_table();
    if (t == nullptr) return;
    std::vector<std::string> unused;
    for (auto&& [key, node] : *t)
      if (!used(key.str())) unused.emplace_back(key.str());
    for (const std::string& key : unused) {
      // Unknown to every process: left for the reader's "unknown key" with its suggestion.
      if (!listed(kTurningCutting, key) && !listed(kMillingCutting, key) &&
          !listed(kTurningSimulate, key) && !listed(kMillingSimulate, key))
        continue;
      problems.at(std::string(table) + "." + key_text(key), *t->get(key),
                  "not used in a " + std::string(name) + " case (" + std::string(name) + " takes " +
                      takes + ")");
      t->erase(key);
    }
  };
  if (milling) {
    drop_keys(
        "cutting", [](std::string_view k) { return listed(kMillingCutting, k); },
        list_text(kMillingCutting));
    drop_keys(
        "simulate", [](std::string_view k) { return listed(kMillingSimulate, k); },
        list_text(kMillingSimulate) + "; --duration-s on the command line sets revolutions");
  } else {
    drop_keys(
        "cutting", [](std::string_view k) { return listed(kTurningCutting, k); },
        list_text(kTurningCutting));
    drop_keys(
        "simulate", [](std::string_view k) { return listed(kTurningSimulate, k); },
        list_text(kTurningSimulate));
  }
  // Keys that only one model of the process reads.
  toml::table* cutting = root["cutting"].as_table();
  if (cutting == nullptr) return;
  const auto drop_key = [&](std::string_view key, std::string_view why) {
    if (const toml::node* node = cutting->get(key)) {
      problems.at("cutting." + std::string(key), *node, why);
      cutting->erase(key);
    }
  };
  if (!milling && !root.contains("material")) {
    for (std::string_view key : {"rake_deg", "workpiece_temperature_c"})
      drop_key(key,
               "used only with a [material] (Oxley's theory predicts the force coefficients "
               "from it)");
  }
  if (milling && root.contains("force_law")) {
    for (std::string_view key : {"kte_n_per_mm", "kre_n_per_mm"})
      drop_key(key,
               "not used with [force_law] (the simulation then takes the S1 law of "
               "[force_law]; the stability lobes take no edge forces)");
  }
}

Case parse_case(std::string_view toml_text, std::string_view source) {
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
  Problems problems(text);
  Case c;
  c.source = std::string(source);
  c.text = std::string(toml_text);

  if (const toml::node* p = root.get("process"); p != nullptr && p->is_table()) {
    TableReader top(problems, root, "", {"process", "bore", "cutter", "limits"});
    read_bore_case(top, c);
    if (!problems.empty()) throw InvalidInput(problems.take(), std::string(source));
    return c;
  }
  TableReader top(problems, root, "",
                  {"process", "modes", "cutting", "tool", "operation", "vibration", "lobes",
                   "simulate", "force_law", "drives", "material", "oxley"});
  std::optional<Process> process;
  if (auto v = top.choice("process", {"turning", "milling"}, Need::kRequired)) {
    process = *v == "turning" ? Process::kTurning : Process::kMilling;
    c.process = *process;
    remove_unused(root, *process, problems);
  }
  read_modes(top, process, c);
  read_drives(top, c);
  if (const toml::table* t = top.section("cutting")) {
    TableReader r(problems, *t, "cutting",
                  {"kt_n_per_mm2", "kc_n_per_mm2", "kr_n_per_mm2", "speed_m_per_min",
                   "uncut_chip_thickness_mm", "width_mm", "kte_n_per_mm", "kre_n_per_mm",
                   "rake_deg", "workpiece_temperature_c"});
    read_cutting(r, c);
  }
  if (const toml::table* t = top.section("tool")) {
    TableReader r(problems, *t, "tool", {"teeth", "diameter_mm", "helix_deg", "pitch_deg"});
    read_tool(r, c);
  }
  if (const toml::table* t = top.section("operation")) {
    TableReader r(problems, *t, "operation",
                  {"radial_immersion", "direction", "feed_per_tooth_mm", "entry_deg", "exit_deg"});
    read_operation(r, c);
  }
  if (const toml::table* t = top.section("vibration")) {
    TableReader r(problems, *t, "vibration",
                  {"frequency_hz", "amplitude_um", "workpiece_diameter_mm", "duty_cycle"});
    read_vibration(r, c);
  }
  if (const toml::table* t = top.section("lobes")) {
    TableReader r(problems, *t, "lobes",
                  {"rpm_min", "rpm_max", "rpm_steps", "depth_max_mm", "method", "harmonics",
                   "steps_per_period", "refine"});
    read_lobes(r, c);
  }
  if (const toml::table* t = top.section("simulate")) {
    TableReader r(
        problems, *t, "simulate",
        {"rpm", "depth_mm", "duration_s", "initial_displacement_um", "revolutions",
         "summary_revolutions", "regenerative", "steps_per_tooth", "slices", "closed_form_helix"});
    read_simulate(r, c);
  }
  if (const toml::table* t = top.section("force_law")) {
    TableReader r(problems, *t, "force_law",
                  {"c_n_per_mm", "t2_s", "p0_n", "t1_mm", "phi_rez_deg", "phi_skv_deg"});
    read_force_law(r, c);
  }
  if (const toml::table* t = top.section("material")) {
    TableReader r(problems, *t, "material", {"name", "johnson_cook", "thermal"});
    read_material(r, c);
  }
  if (const toml::table* t = top.section("oxley")) {
    TableReader r(problems, *t, "oxley",
                  {"c0_min", "c0_max", "delta_min", "delta_max", "eta", "psi"});
    read_oxley(r, c);
  }
  if (c.material && problems.empty()) {
    if (c.process == Process::kMilling)
      problems.add(
          "material: Oxley's theory is orthogonal cutting, used by the turning commands; for "
          "milling give cutting.kt_n_per_mm2 and cutting.kr_n_per_mm2");
    for (const char* key : {"kc_n_per_mm2", "kt_n_per_mm2"})
      if (const toml::table* t = root["cutting"].as_table(); t && t->contains(key))
        problems.add(std::string("cutting.") + key +
                     " and [material]: give the force coefficients or the material to "
                     "predict them from, not both");
  }
  top.report_unknown();

  if (!problems.empty()) throw InvalidInput(problems.take(), std::string(source));
  return c;
}

Case with_value(const Case& c, std::string_view dotted_key, double value) {
  const std::string key(dotted_key);
  const std::string label = key + " = " + format_value(value);
  toml::table root;
  try {
    root = toml::parse(c.text, c.source);
  } catch (const toml::parse_error&) {
    throw InvalidInput({label + ": the case text does not parse"}, c.source);
  }
  const auto dot = key.find('.');
  const std::string table = dot == std::string::npos ? "" : key.substr(0, dot);
  const std::string name = dot == std::string::npos ? key : key.substr(dot + 1);
  if (name.empty() || name.find('.') != std::string::npos ||
      (dot != std::string::npos && table.empty()))
    throw InvalidInput({label + ": the key must be \"table.key\" or \"key\""}, c.source);
  toml::table* target = &root;
  if (!table.empty()) {
    toml::node* node = root.get(table);
    if (node == nullptr) {
      root.insert(table, toml::table{});
      node = root.get(table);
    }
    target = node->as_table();
    if (target == nullptr) throw InvalidInput({label + ": " + table + " is not a table"}, c.source);
  }
  if (std::isfinite(value) && value == std::round(value) && std::abs(value) < 9e15)
    target->insert_or_assign(name, static_cast<std::int64_t>(value));
  else
    target->insert_or_assign(name, value);
  std::ostringstream text;
  text << root;
  return parse_case(text.str(), c.source + " with " + label);
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
  json j;
  if (c.bore) {
    const BoreMillingCase& b = *c.bore;
    j["bore"] = {{"diameter_mm", tidy(m_to_mm(b.bore_diameter_m))},
                 {"length_mm", tidy(m_to_mm(b.length_m))},
                 {"allowance_mm", tidy(m_to_mm(b.allowance_m))}};
    j["cutter"] = {{"diameter_mm", tidy(m_to_mm(b.cutter_diameter_m))},
                   {"teeth", b.teeth},
                   {"offset_mm", tidy(m_to_mm(b.offset_m))},
                   {"lead_angle_deg", tidy(units::rad_to_deg(b.lead_angle_rad))},
                   {"inclination_deg", tidy(units::rad_to_deg(b.inclination_rad))}};
    j["process"] = {{"cutting_speed_m_per_min", tidy(60.0 * b.cutting_speed_m_per_s)},
                    {"mean_chip_thickness_mm", tidy(m_to_mm(b.mean_chip_thickness_m))},
                    {"accuracy_coefficient", tidy(b.accuracy_coefficient)}};
    if (c.axial_feed_m) j["process"]["axial_feed_mm"] = tidy(m_to_mm(*c.axial_feed_m));
    if (c.bore_limits) {
      const BoreMillingLimits& l = *c.bore_limits;
      j["limits"] = {{"offset_min_mm", tidy(m_to_mm(l.offset_min_m))},
                     {"offset_max_mm", tidy(m_to_mm(l.offset_max_m))},
                     {"cutting_speed_max_m_per_min", tidy(60.0 * l.cutting_speed_max_m_per_s)},
                     {"cutter_rpm_max", tidy(60.0 * l.cutter_rev_per_s_max)},
                     {"workpiece_rpm_max", tidy(60.0 * l.workpiece_rev_per_s_max)},
                     {"faceting_max_mm", tidy(m_to_mm(l.faceting_max_m))},
                     {"max_chip_thickness_mm", tidy(m_to_mm(l.max_chip_thickness_m))}};
    }
    return j;
  }
  j["process"] = to_string(c.process);

  json modes = json::array();
  for (const Mode& m : c.modal.modes) {
    modes.push_back({{"direction", cutdyn::to_string(m.direction)},
                     {"natural_hz", tidy(units::rad_per_s_to_hz(m.natural_rad_s))},
                     {"damping_ratio", tidy(m.damping_ratio)},
                     {"stiffness_n_per_m", tidy(m.stiffness_n_per_m)}});
  }
  j["modes"] = std::move(modes);

  json cutting = json::object();
  const CuttingSection& cs = c.cutting;
  if (cs.kt_pa) cutting["kt_n_per_mm2"] = tidy(pa_to_n_per_mm2(*cs.kt_pa));
  if (cs.kc_pa) cutting["kc_n_per_mm2"] = tidy(pa_to_n_per_mm2(*cs.kc_pa));
  if (cs.kr_pa) cutting["kr_n_per_mm2"] = tidy(pa_to_n_per_mm2(*cs.kr_pa));
  if (cs.speed_m_per_s) cutting["speed_m_per_min"] = tidy(m_per_s_to_m_per_min(*cs.speed_m_per_s));
  if (cs.uncut_chip_thickness_m) {
    cutting["uncut_chip_thickness_mm"] = tidy(m_to_mm(*cs.uncut_chip_thickness_m));
  }
  if (cs.width_m) cutting["width_mm"] = tidy(m_to_mm(*cs.width_m));
  if (cs.kte_n_per_m) cutting["kte_n_per_mm"] = tidy(1e-3 * *cs.kte_n_per_m);
  if (cs.kre_n_per_m) cutting["kre_n_per_mm"] = tidy(1e-3 * *cs.kre_n_per_m);
  if (cs.rake_rad) cutting["rake_deg"] = tidy(units::rad_to_deg(*cs.rake_rad));
  if (cs.workpiece_temperature_c)
    cutting["workpiece_temperature_c"] = tidy(*cs.workpiece_temperature_c);
  if (!cutting.empty()) j["cutting"] = std::move(cutting);

  if (c.material) {
    const WorkMaterial& m = *c.material;
    const JohnsonCook& jc = m.flow;
    const ThermalProperties& th = m.thermal;
    j["material"] = {
        {"name", m.name},
        {"johnson_cook",
         {{"a_mpa", tidy(jc.a_pa / 1e6)},
          {"b_mpa", tidy(jc.b_pa / 1e6)},
          {"n", tidy(jc.n)},
          {"c", tidy(jc.c)},
          {"m", tidy(jc.m)},
          {"reference_strain_rate_per_s", tidy(jc.reference_strain_rate_per_s)},
          {"reference_temperature_c", tidy(jc.reference_temperature_c)},
          {"melting_temperature_c", tidy(jc.melting_temperature_c)}}},
        {"thermal",
         {{"density_kg_per_m3", tidy(th.density_kg_per_m3)},
          {"specific_heat_j_per_kg_k", tidy(th.specific_heat_j_per_kg_k)},
          {"specific_heat_slope_j_per_kg_k2", tidy(th.specific_heat_slope_j_per_kg_k2)},
          {"conductivity_w_per_m_k", tidy(th.conductivity_w_per_m_k)},
          {"conductivity_slope_w_per_m_k2", tidy(th.conductivity_slope_w_per_m_k2)}}}};
    const OxleyOptions& o = c.oxley;
    j["oxley"] = {{"c0_min", tidy(o.c0_min)},
                  {"c0_max", tidy(o.c0_max)},
                  {"delta_min", tidy(o.delta_min)},
                  {"delta_max", tidy(o.delta_max)},
                  {"eta", tidy(o.eta)},
                  {"psi", tidy(o.psi)}};
  }
  if (c.tool) {
    j["tool"] = {{"teeth", c.tool->teeth},
                 {"diameter_mm", tidy(m_to_mm(c.tool->diameter_m))},
                 {"helix_deg", tidy(units::rad_to_deg(c.tool->helix_rad))}};
    if (!c.tool->pitch_rad.empty()) {
      nlohmann::json pitch = nlohmann::json::array();
      for (double p : c.tool->pitch_rad) pitch.push_back(tidy(units::rad_to_deg(p)));
      j["tool"]["pitch_deg"] = pitch;
    }
  }
  if (c.operation) {
    const OperationSection& op = *c.operation;
    j["operation"] = {{"radial_immersion", tidy(op.radial_immersion)},
                      {"direction", op.down_milling ? "down" : "up"}};
    if (op.feed_per_tooth_m)
      j["operation"]["feed_per_tooth_mm"] = tidy(m_to_mm(*op.feed_per_tooth_m));
    if (op.entry_rad) {
      j["operation"]["entry_deg"] = tidy(units::rad_to_deg(*op.entry_rad));
      j["operation"]["exit_deg"] = tidy(units::rad_to_deg(*op.exit_rad));
    }
  }
  if (!c.drives.empty()) {
    json drives = json::array();
    for (const FeedAxis& a : c.drives) {
      const FeedDrive& d = a.drive;
      const Transmission& tr = d.transmission;
      json j_axis{
          {"direction", {tidy(a.direction[0]), tidy(a.direction[1]), tidy(a.direction[2])}},
          {"transmission", tr.kind == Transmission::Kind::kLeverArm ? "lever" : "ball-screw"},
          {"idle_torque_nm", tidy(tr.idle_torque_nm)},
          {"model", d.model == FeedDrive::Model::kDynamic ? "dynamic" : "static"}};
      if (tr.kind == Transmission::Kind::kLeverArm) {
        j_axis["output_diameter_mm"] = tidy(m_to_mm(tr.output_diameter_m));
        j_axis["ratio"] = tidy(tr.ratio);
      } else {
        j_axis["lead_mm"] = tidy(m_to_mm(tr.lead_m));
        j_axis["efficiency"] = tidy(tr.efficiency);
        j_axis["gear_ratio"] = tidy(tr.gear_ratio);
      }
      if (d.model == FeedDrive::Model::kStatic) {
        j_axis["stiffness_nm_s_per_rad"] = tidy(d.stiffness_nm_s_per_rad);
      } else {
        j_axis["inertia_kg_m2"] = tidy(d.inertia_kg_m2);
        j_axis["viscous_nm_s_per_rad"] = tidy(d.viscous_nm_s_per_rad);
        j_axis["kp_nm_s_per_rad"] = tidy(d.kp_nm_s_per_rad);
        j_axis["ki_nm_per_rad"] = tidy(d.ki_nm_per_rad);
        j_axis["torque_limit_nm"] = tidy(d.torque_limit_nm);
      }
      if (a.motor) {
        j_axis["pole_pairs"] = a.motor->pole_pairs;
        j_axis["torque_constant_nm_per_a"] = tidy(a.motor->torque_constant_nm_per_a);
        j_axis["current_measure"] = std::string(to_string(a.motor->measure));
        j_axis["current_noise_a"] = tidy(a.motor->noise_a);
        j_axis["current_offset_a"] = {tidy(a.motor->offset_a[0]), tidy(a.motor->offset_a[1]),
                                      tidy(a.motor->offset_a[2])};
        j_axis["seed"] = a.motor->seed;
      }
      drives.push_back(std::move(j_axis));
    }
    j["drives"] = std::move(drives);
  }
  if (c.force_law) {
    const ForceLawSection& f = *c.force_law;
    j["force_law"] = {{"c_n_per_mm", tidy(1e-3 * f.c_n_per_m)},
                      {"t2_s", tidy(f.t2_s)},
                      {"p0_n", tidy(f.p0_n)},
                      {"t1_mm", tidy(m_to_mm(f.t1_m))},
                      {"phi_rez_deg", tidy(units::rad_to_deg(f.phi_rez_rad))},
                      {"phi_skv_deg", tidy(units::rad_to_deg(f.phi_skv_rad))}};
  }
  if (c.vibration) {
    const VibrationSection& v = *c.vibration;
    json vib = {{"frequency_hz", tidy(v.frequency_hz)}};
    if (v.amplitude_m) vib["amplitude_um"] = tidy(m_to_um(*v.amplitude_m));
    if (v.workpiece_diameter_m)
      vib["workpiece_diameter_mm"] = tidy(m_to_mm(*v.workpiece_diameter_m));
    if (v.duty_cycle) vib["duty_cycle"] = tidy(*v.duty_cycle);
    j["vibration"] = std::move(vib);
  }

  const LobesSection& l = c.lobes;
  j["lobes"] = {{"rpm_min", tidy(l.rpm_min)},
                {"rpm_max", tidy(l.rpm_max)},
                {"rpm_steps", l.rpm_steps},
                {"depth_max_mm", tidy(m_to_mm(l.depth_max_m))},
                {"method", to_string(l.method)},
                {"harmonics", l.harmonics},
                {"steps_per_period", l.steps_per_period},
                {"refine", l.refine}};

  const SimulateSection& s = c.simulate;
  // The keys of the case's process only (a milling case takes no duration_s, a turning case
  // no revolutions), so that the echo reads back.
  json sim = json::object();
  if (c.process != Process::kMilling) {
    sim["duration_s"] = tidy(s.duration_s);
    sim["initial_displacement_um"] = tidy(m_to_um(s.initial_displacement_m));
  }
  if (s.rpm) sim["rpm"] = tidy(*s.rpm);
  if (s.depth_m) sim["depth_mm"] = tidy(m_to_mm(*s.depth_m));
  if (c.process == Process::kMilling) {
    sim["revolutions"] = tidy(s.revolutions);
    sim["summary_revolutions"] = tidy(s.summary_revolutions);
    sim["regenerative"] = s.regenerative;
    sim["steps_per_tooth"] = s.steps_per_tooth;
    sim["slices"] = s.slices;
    sim["closed_form_helix"] = s.closed_form_helix;
  }
  j["simulate"] = std::move(sim);
  return j;
}

}  // namespace cutdyn::io
