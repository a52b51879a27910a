// Force files for the identification; docs/models/identification.md, "Force files".
#include "cutdyn/io/force_file.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>
#include <system_error>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/io/inputs.hpp"

namespace cutdyn::io {
namespace {

constexpr std::size_t kMaxProblems = 20;

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split(std::string_view line, char separator) {
  std::vector<std::string_view> fields;
  for (std::size_t at = 0;;) {
    const std::size_t next = line.find(separator, at);
    fields.push_back(trim(line.substr(at, next == std::string_view::npos ? line.npos : next - at)));
    if (next == std::string_view::npos) return fields;
    at = next + 1;
  }
}

std::string quoted(std::string_view s) {
  std::string text(s.substr(0, 40));
  if (s.size() > 40) text += "...";
  return "\"" + text + "\"";
}

std::string at_line(std::size_t line) { return "line " + std::to_string(line); }

// Problems of one file, capped (the first kMaxProblems and a count of the rest).
class Problems {
 public:
  void add(std::string p) {
    if (list_.size() < kMaxProblems)
      list_.push_back(std::move(p));
    else
      ++dropped_;
  }
  bool empty() const { return list_.empty(); }
  void throw_if_any(const std::string& source) {
    if (list_.empty()) return;
    if (dropped_ > 0) list_.push_back("… and " + std::to_string(dropped_) + " more problem(s)");
    throw InvalidInput(list_, source);
  }

 private:
  std::vector<std::string> list_;
  std::size_t dropped_ = 0;
};

// A number: blanks around it allowed, nothing else; finite.
std::optional<double> parse_number(std::string_view text, std::string& why) {
  text = trim(text);
  if (text.empty()) {
    why = "is empty";
    return std::nullopt;
  }
  std::string_view digits = text;
  if (digits.front() == '+') digits.remove_prefix(1);
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (ec == std::errc::result_out_of_range) {
    why = quoted(text) + " is out of the range of a double";
    return std::nullopt;
  }
  if (ec != std::errc{} || ptr != digits.data() + digits.size()) {
    why = quoted(text) + " is not a number";
    return std::nullopt;
  }
  if (!std::isfinite(value)) {
    why = quoted(text) + " must be a finite number";
    return std::nullopt;
  }
  return value;
}

struct Line {
  std::size_t number = 0;
  std::string_view text;  // trimmed
};

// The file cut into comment lines before the header, the header and the data lines.
struct Table {
  std::vector<Line> leading_comments;
  Line header;
  std::vector<std::string_view> columns;
  std::vector<Line> rows;
};

Table tabulate(std::string_view text, const std::string& source) {
  Table t;
  bool have_header = false;
  std::size_t number = 0;
  for (std::size_t at = 0; at <= text.size();) {
    const std::size_t nl = text.find('\n', at);
    const std::string_view raw =
        text.substr(at, nl == std::string_view::npos ? text.npos : nl - at);
    at = nl == std::string_view::npos ? text.size() + 1 : nl + 1;
    ++number;
    const Line line{number, trim(raw)};
    if (line.text.empty()) continue;
    if (line.text.front() == '#') {
      if (!have_header) t.leading_comments.push_back(line);
      continue;
    }
    if (have_header) {
      t.rows.push_back(line);
    } else {
      t.header = line;
      t.columns = split(line.text, ',');
      have_header = true;
    }
  }
  if (!have_header)
    throw InvalidInput({"no header line: expected feed_per_tooth_mm,depth_mm,fx_n,fy_n[,fz_n] "
                        "(mean forces) or time_s,fx_n,fy_n[,fz_n] (a force record)"},
                       source);
  if (t.rows.empty())
    throw InvalidInput({at_line(t.header.number) + ": no data after the header"}, source);
  return t;
}

bool has(const Table& t, std::string_view name) {
  return std::find(t.columns.begin(), t.columns.end(), name) != t.columns.end();
}

// Index of each of `names` in the header (-1: absent); problems for unknown, repeated and
// missing required columns.
std::vector<int> column_indices(const Table& t, const std::vector<std::string_view>& names,
                                std::size_t required, const std::string& source) {
  Problems p;
  std::vector<int> index(names.size(), -1);
  std::string known;
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (k > 0) known += ',';
    known += names[k];
    if (k >= required) known += " (optional)";
  }
  for (std::size_t c = 0; c < t.columns.size(); ++c) {
    const auto it = std::find(names.begin(), names.end(), t.columns[c]);
    const std::string where = at_line(t.header.number) + ", column " + std::to_string(c + 1);
    if (it == names.end()) {
      p.add(where + ": unknown column " + quoted(t.columns[c]) + " (the columns are " + known +
            ")");
      continue;
    }
    int& slot = index[static_cast<std::size_t>(it - names.begin())];
    if (slot >= 0)
      p.add(where + ": column " + std::string(*it) + " appears twice");
    else
      slot = static_cast<int>(c);
  }
  for (std::size_t k = 0; k < required; ++k)
    if (index[k] < 0)
      p.add(at_line(t.header.number) + ": missing column " + std::string(names[k]) +
            " (the columns are " + known + ")");
  p.throw_if_any(source);
  return index;
}

// The numbers of one data line in the order of `names` (NaN where the column is absent).
// Returns false (with problems added) for a bad line.
bool parse_row(const Table& t, const Line& line, const std::vector<std::string_view>& names,
               const std::vector<int>& index, std::vector<double>& values, Problems& p) {
  const std::vector<std::string_view> fields = split(line.text, ',');
  if (fields.size() != t.columns.size()) {
    p.add(at_line(line.number) + ": " + std::to_string(fields.size()) + " fields, the header (" +
          at_line(t.header.number) + ") has " + std::to_string(t.columns.size()));
    return false;
  }
  bool ok = true;
  values.assign(names.size(), std::nan(""));
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (index[k] < 0) continue;
    std::string why;
    const auto v = parse_number(fields[static_cast<std::size_t>(index[k])], why);
    if (!v) {
      p.add(at_line(line.number) + ", column " + std::string(names[k]) + ": " + why);
      ok = false;
    } else {
      values[k] = *v;
    }
  }
  return ok;
}

void require_positive(double value, const Line& line, std::string_view column, Problems& p) {
  if (!(value > 0.0))
    p.add(at_line(line.number) + ", column " + std::string(column) + ": " + format_value(value) +
          " must be positive");
}

}  // namespace

ForceFileKind force_file_kind(std::string_view text, const std::string& source) {
  const Table t = tabulate(text, source);
  if (has(t, "time_s") && has(t, "axis")) return ForceFileKind::kMonitorEstimate;
  if (has(t, "time_s")) return ForceFileKind::kTimeSeries;
  if (has(t, "feed_per_tooth_mm")) return ForceFileKind::kMeanForces;
  throw InvalidInput({at_line(t.header.number) + ": the header " + quoted(t.header.text) +
                      " names neither the mean-force columns feed_per_tooth_mm,depth_mm,fx_n,"
                      "fy_n[,fz_n] nor a force record's time_s,fx_n,fy_n[,fz_n]"},
                     source);
}

std::vector<MeanForce> parse_mean_force_csv(std::string_view text, const std::string& source) {
  const Table t = tabulate(text, source);
  const std::vector<std::string_view> names = {"feed_per_tooth_mm", "depth_mm", "fx_n", "fy_n",
                                               "fz_n"};
  const std::vector<int> index = column_indices(t, names, 4, source);
  const bool axial = index[4] >= 0;
  Problems p;
  std::vector<MeanForce> out;
  std::vector<double> v;
  for (const Line& line : t.rows) {
    if (!parse_row(t, line, names, index, v, p)) continue;
    require_positive(v[0], line, names[0], p);
    require_positive(v[1], line, names[1], p);
    MeanForce m;
    m.feed_per_tooth_m = units::mm_to_m(v[0]);
    m.depth_m = units::mm_to_m(v[1]);
    m.fx_n = v[2];
    m.fy_n = v[3];
    if (axial) m.fz_n = v[4];
    m.label = source + ":" + std::to_string(line.number);
    out.push_back(m);
  }
  p.throw_if_any(source);
  return out;
}

namespace {

// `# key = value[, key = value ...]` lines before the header: the cut of a force record.
void read_record_keys(const Table& t, ForceSeries& s, Problems& p) {
  const std::vector<std::string_view> keys = {"feed_per_tooth_mm", "depth_mm", "rpm"};
  std::vector<std::optional<double>> value(keys.size());
  std::vector<std::size_t> where(keys.size(), 0);
  for (const Line& c : t.leading_comments) {
    const std::string_view body = trim(c.text.substr(1));
    if (body.find('=') == std::string_view::npos) continue;  // free text
    for (const std::string_view item : split(body, ',')) {
      const std::size_t eq = item.find('=');
      if (eq == std::string_view::npos) continue;
      const std::string_view key = trim(item.substr(0, eq));
      const auto it = std::find(keys.begin(), keys.end(), key);
      if (it == keys.end()) continue;  // other notes are allowed
      const auto k = static_cast<std::size_t>(it - keys.begin());
      const std::string here = at_line(c.number) + ", " + std::string(key);
      if (where[k] != 0) {
        p.add(here + ": given twice (first on " + at_line(where[k]) + ")");
        continue;
      }
      std::string why;
      value[k] = parse_number(item.substr(eq + 1), why);
      where[k] = c.number;
      if (!value[k])
        p.add(here + ": " + why);
      else if (!(*value[k] > 0.0))
        p.add(here + ": " + format_value(*value[k]) + " must be positive");
    }
  }
  std::string missing;
  for (std::size_t k = 0; k < keys.size(); ++k)
    if (!where[k]) missing += (missing.empty() ? "" : ", ") + std::string(keys[k]);
  if (!missing.empty())
    p.add("missing " + missing +
          ": a force record states its cut in comment lines before the "
          "header (line " +
          std::to_string(t.header.number) +
          "), `# feed_per_tooth_mm = 0.05`, `# depth_mm = 2`, `# rpm = 3000`");
  if (value[0]) s.feed_per_tooth_m = units::mm_to_m(*value[0]);
  if (value[1]) s.depth_m = units::mm_to_m(*value[1]);
  if (value[2]) s.rpm = *value[2];
}

}  // namespace

ForceSeries parse_force_series_csv(std::string_view text, const std::string& source) {
  const Table t = tabulate(text, source);
  const std::vector<std::string_view> names = {"time_s", "fx_n", "fy_n", "fz_n"};
  const std::vector<int> index = column_indices(t, names, 3, source);
  const bool axial = index[3] >= 0;
  Problems p;
  ForceSeries s;
  s.label = source;
  read_record_keys(t, s, p);
  std::vector<double> v;
  std::size_t last_line = 0;
  for (const Line& line : t.rows) {
    if (!parse_row(t, line, names, index, v, p)) continue;
    if (!s.time_s.empty() && !(v[0] > s.time_s.back()))
      p.add(at_line(line.number) + ", column time_s: " + format_value(v[0]) +
            " s does not increase over " + at_line(last_line) + " (" +
            format_value(s.time_s.back()) + " s)");
    s.time_s.push_back(v[0]);
    s.fx_n.push_back(v[1]);
    s.fy_n.push_back(v[2]);
    if (axial) s.fz_n.push_back(v[3]);
    last_line = line.number;
  }
  p.throw_if_any(source);
  return s;
}

ForceSeries parse_monitor_force_csv(std::string_view text, const std::string& source) {
  const Table t = tabulate(text, source);
  Problems p;
  int time_col = -1, axis_col = -1, force_col = -1;
  for (std::size_t c = 0; c < t.columns.size(); ++c) {
    if (t.columns[c] == "time_s") time_col = static_cast<int>(c);
    if (t.columns[c] == "axis") axis_col = static_cast<int>(c);
    if (t.columns[c] == "force_n") force_col = static_cast<int>(c);
  }
  if (force_col < 0) p.add(at_line(t.header.number) + ": missing column force_n");
  p.throw_if_any(source);
  ForceSeries s;
  s.label = source;
  read_record_keys(t, s, p);
  // One instant: the force of each axis (NaN: not given), and the line it began on.
  std::array<double, 3> f{};
  std::size_t first_line = 0;
  bool axial = false;
  const auto flush = [&](double time) {
    if (first_line == 0) return;
    if (std::isnan(f[0]) || std::isnan(f[1])) {
      p.add(at_line(first_line) + ": at " + format_value(time) + " s the file gives " +
            (std::isnan(f[0]) ? "no axis x" : "no axis y") +
            " (identification needs the force in x and y at every instant)");
      return;
    }
    s.time_s.push_back(time);
    s.fx_n.push_back(-f[0]);  // the force on the cutter: −(the force resisting the axis)
    s.fy_n.push_back(-f[1]);
    if (!std::isnan(f[2])) {
      s.fz_n.push_back(-f[2]);
      axial = true;
    }
  };
  double time = 0.0;
  for (const Line& line : t.rows) {
    const std::vector<std::string_view> fields = split(line.text, ',');
    if (fields.size() != t.columns.size()) {
      p.add(at_line(line.number) + ": " + std::to_string(fields.size()) + " fields, the header (" +
            at_line(t.header.number) + ") has " + std::to_string(t.columns.size()));
      continue;
    }
    std::string why;
    const auto tv = parse_number(fields[static_cast<std::size_t>(time_col)], why);
    const auto fv = parse_number(fields[static_cast<std::size_t>(force_col)], why);
    const std::string_view axis = trim(fields[static_cast<std::size_t>(axis_col)]);
    const int a = axis == "x" ? 0 : axis == "y" ? 1 : axis == "z" ? 2 : -1;
    if (!tv || !fv || a < 0) {
      p.add(at_line(line.number) + ": " +
            (a < 0 ? "axis " + quoted(axis) + " is not x, y or z" : why));
      continue;
    }
    if (first_line == 0 || *tv != time) {
      if (first_line != 0 && !(*tv > time))
        p.add(at_line(line.number) + ", column time_s: " + format_value(*tv) +
              " s does not increase");
      flush(time);
      f.fill(std::nan(""));
      time = *tv;
      first_line = line.number;
    }
    if (!std::isnan(f[static_cast<std::size_t>(a)]))
      p.add(at_line(line.number) + ": axis " + std::string(axis) + " twice at " +
            format_value(time) + " s");
    f[static_cast<std::size_t>(a)] = *fv;
  }
  flush(time);
  if (axial && s.fz_n.size() != s.time_s.size())
    p.add("axis z: given at some instants only (all or none)");
  p.throw_if_any(source);
  return s;
}

std::vector<MeanForce> parse_force_file(std::string_view text, const std::string& source) {
  const ForceFileKind kind = force_file_kind(text, source);
  if (kind == ForceFileKind::kMeanForces) return parse_mean_force_csv(text, source);
  if (kind == ForceFileKind::kMonitorEstimate)
    return {mean_over_revolutions(parse_monitor_force_csv(text, source))};
  return {mean_over_revolutions(parse_force_series_csv(text, source))};
}

std::vector<MeanForce> read_force_files(const std::vector<std::filesystem::path>& paths) {
  std::vector<MeanForce> out;
  for (const std::filesystem::path& path : paths) {
    const std::string where = path.string();
    const auto fail = [&](int error) {
      throw InvalidInput({"cannot read the file: " + std::generic_category().message(error)},
                         where);
    };
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) fail(EISDIR);
    errno = 0;
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(errno != 0 ? errno : ENOENT);
    std::ostringstream content;
    content << in.rdbuf();
    if (in.bad()) fail(errno != 0 ? errno : EIO);
    note_input(path);
    const std::vector<MeanForce> samples = parse_force_file(content.str(), where);
    out.insert(out.end(), samples.begin(), samples.end());
  }
  return out;
}

}  // namespace cutdyn::io
