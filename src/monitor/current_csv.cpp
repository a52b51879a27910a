#include "cutdyn/monitor/current_csv.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>

#include "cutdyn/core/error.hpp"

namespace cutdyn {
namespace {

constexpr int kTime = 0, kAxis = 1, kExtra = 6;

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

bool blank(std::string_view s) { return trim(s).empty(); }

// Shortens a field for a message.
std::string quoted(std::string_view s) {
  std::string text(s.substr(0, 40));
  if (s.size() > 40) text += "...";
  return "\"" + text + "\"";
}

}  // namespace

const std::string* CsvComment::find(std::string_view key) const {
  for (const auto& [k, v] : fields)
    if (k == key) return &v;
  return nullptr;
}

void CurrentCsvParser::parse_comment(std::string_view line) {
  // `# key = value, key = value, ...`; a comment without any '=' is free text (ignored).
  std::string_view body = trim(line);
  body.remove_prefix(1);
  body = trim(body);
  if (body.find('=') == std::string_view::npos) return;
  CsvComment c;
  c.line = line_;
  const auto malformed = [&](std::string_view item, const char* why) {
    throw InvalidInput(
        {"line " + std::to_string(line_) + ": comment item " + quoted(trim(item)) + ": " + why +
         " (a comment before the header is `# key = value, key = "
         "value, ...`)"},
        source_);
  };
  for (std::size_t at = 0;;) {
    const std::size_t comma = body.find(',', at);
    const std::string_view item =
        body.substr(at, comma == std::string_view::npos ? body.npos : comma - at);
    const std::size_t eq = item.find('=');
    if (eq == std::string_view::npos) malformed(item, "no '='");
    if (item.find('=', eq + 1) != std::string_view::npos) malformed(item, "more than one '='");
    const std::string_view key = trim(item.substr(0, eq)), value = trim(item.substr(eq + 1));
    if (key.empty()) malformed(item, "empty key");
    if (value.empty()) malformed(item, "empty value");
    if (c.find(key)) malformed(item, "the key appears twice");
    c.fields.emplace_back(std::string(key), std::string(value));
    if (comma == std::string_view::npos) break;
    at = comma + 1;
  }
  if (const std::string* m = c.find("measure"); m && !parse_current_measure(*m))
    throw InvalidInput({"line " + std::to_string(line_) + ": measure = " + quoted(*m) +
                        ": must be rms or space-vector"},
                       source_);
  comments_.push_back(std::move(c));
}

std::optional<std::pair<CurrentMeasure, std::size_t>> CurrentCsvParser::recorded_measure(
    const std::string& axis) const {
  std::optional<std::pair<CurrentMeasure, std::size_t>> general;
  for (const CsvComment& c : comments_) {
    const std::string* m = c.find("measure");
    if (!m) continue;
    const std::string* a = c.find("axis");
    const std::pair<CurrentMeasure, std::size_t> found{*parse_current_measure(*m), c.line};
    if (a && *a == axis) return found;
    if (!a && !general) general = found;
  }
  return general;
}

std::string CsvLineError::text() const { return "line " + std::to_string(line) + ": " + what; }

CurrentCsvParser::CurrentCsvParser(std::string source, std::string extra_column)
    : source_(std::move(source)), extra_column_(std::move(extra_column)) {}

void CurrentCsvParser::parse_header(std::string_view line) {
  std::vector<std::string_view> fields;
  for (std::size_t at = 0;;) {
    const std::size_t comma = line.find(',', at);
    fields.push_back(
        trim(line.substr(at, comma == std::string_view::npos ? line.npos : comma - at)));
    if (comma == std::string_view::npos) break;
    at = comma + 1;
  }
  std::vector<std::string> names(std::begin(kCurrentColumns), std::end(kCurrentColumns));
  if (!extra_column_.empty()) names.push_back(extra_column_);
  Validator v;
  slot_of_field_.assign(fields.size(), -1);
  for (std::size_t f = 0; f < fields.size(); ++f) {
    header_names_.emplace_back(fields[f]);
    for (std::size_t s = 0; s < names.size(); ++s) {
      if (fields[f] != names[s]) continue;
      if (index_[s] >= 0) {
        v.add("line " + std::to_string(line_) + ": column " + names[s] + " appears twice");
        continue;
      }
      index_[s] = static_cast<int>(f);
      slot_of_field_[f] = static_cast<int>(s);
    }
  }
  for (std::size_t f = 0; f < fields.size(); ++f) {
    if (fields[f] != kRotorAngleColumn) continue;
    if (index_[kAngleSlot] >= 0) {
      v.add("line " + std::to_string(line_) + ": column " + kRotorAngleColumn + " appears twice");
      continue;
    }
    index_[kAngleSlot] = static_cast<int>(f);
    slot_of_field_[f] = kAngleSlot;
  }
  std::string missing;
  for (std::size_t s = 0; s < names.size(); ++s)
    if (index_[s] < 0) missing += (missing.empty() ? "" : ", ") + names[s];
  if (!missing.empty()) {
    std::string header(trim(line).substr(0, 200));
    v.add("line " + std::to_string(line_) + ": missing column" +
          (missing.find(',') != std::string::npos ? "s " : " ") + missing + " (the header is \"" +
          header + "\"; required: time_s,axis,iu_a,iv_a,iw_a,speed_rad_s" +
          (extra_column_.empty() ? "" : "," + extra_column_) + ")");
  }
  v.throw_if_any(source_);
  header_fields_ = static_cast<int>(fields.size());
  for (std::size_t s = 0; s < names.size(); ++s)
    needed_fields_ = std::max(needed_fields_, index_[s] + 1);
  needed_fields_ = std::max(needed_fields_, index_[kAngleSlot] + 1);
  header_done_ = true;
}

int CurrentCsvParser::axis_index(std::string_view name) {
  for (std::size_t i = 0; i < axes_.size(); ++i)
    if (axes_[i] == name) return static_cast<int>(i);
  axes_.emplace_back(name);
  last_time_.push_back(0.0);
  last_line_.push_back(0);
  return static_cast<int>(axes_.size() - 1);
}

bool CurrentCsvParser::parse_line(std::string_view line, std::vector<CurrentRow>& rows,
                                  std::vector<CsvLineError>& errors) {
  if (blank(line)) return true;
  if (!header_done_) {
    if (trim(line).front() == '#')
      parse_comment(line);
    else
      parse_header(line);
    return true;
  }
  ++data_lines_;
  std::string_view field[8];
  int f = 0;
  const char* p = line.data();
  const char* end = p + line.size();
  bool more = true;  // fields after the last one read
  while (f < needed_fields_) {
    const char* comma =
        static_cast<const char*>(std::memchr(p, ',', static_cast<std::size_t>(end - p)));
    const char* stop = comma ? comma : end;
    const int slot = slot_of_field_[static_cast<std::size_t>(f)];
    if (slot >= 0) field[slot] = std::string_view(p, static_cast<std::size_t>(stop - p));
    ++f;
    if (!comma) {
      more = false;
      break;
    }
    p = comma + 1;
  }
  const auto bad = [&](std::string what) {
    errors.push_back({line_, std::move(what)});
    return false;
  };
  // A line with more fields than the header is not a line of this log (two lines run
  // together, a shifted column): refused, so that its time cannot stand for the axis'.
  if (more && f == needed_fields_) {
    const int total = f + 1 + static_cast<int>(std::count(p, end, ','));
    if (total > header_fields_)
      return bad("the line has " + std::to_string(total) + " fields, the header " +
                 std::to_string(header_fields_));
  }
  if (f < needed_fields_) {
    // Name the first required column the line does not reach.
    std::string missing;
    for (int s = 0; s < 8; ++s)
      if (index_[s] >= f)
        missing +=
            (missing.empty() ? "" : ", ") + header_names_[static_cast<std::size_t>(index_[s])];
    return bad("missing column " + missing + " (the line has " + std::to_string(f) +
               " fields, the header " + std::to_string(header_fields_) + ")");
  }
  CurrentRow row;
  row.line = line_;
  double* target[8] = {&row.time_s, nullptr,          &row.iu_a,  &row.iv_a,
                       &row.iw_a,   &row.speed_rad_s, &row.extra, &row.rotor_angle_rad};
  for (int s = 0; s < 8; ++s) {
    if (s == kAxis || index_[s] < 0) continue;
    std::string_view text = field[s];
    // Blanks around a number are allowed; nothing else.
    while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
    while (!text.empty() && (text.back() == ' ' || text.back() == '\t' || text.back() == '\r'))
      text.remove_suffix(1);
    const std::string& name = header_names_[static_cast<std::size_t>(index_[s])];
    if (text.empty()) return bad(name + " is empty");
    std::string_view digits = text;
    if (digits.front() == '+') digits.remove_prefix(1);
    double value = 0.0;
    const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (ec != std::errc{} || ptr != digits.data() + digits.size()) {
      if (ec == std::errc::result_out_of_range)
        return bad(name + " = " + quoted(text) + ": out of the range of a double");
      return bad(name + " = " + quoted(text) + ": not a number");
    }
    if (!std::isfinite(value))
      return bad(name + " = " + quoted(text) + ": must be a finite number");
    *target[s] = value;
  }
  const std::string_view axis = trim(field[kAxis]);
  if (axis.empty()) return bad("axis is empty");
  if (axis.find('"') != std::string_view::npos)
    return bad("axis = " + quoted(axis) + ": quotes are not allowed");
  row.axis = axis_index(axis);
  const auto a = static_cast<std::size_t>(row.axis);
  if (last_line_[a] != 0 && !(row.time_s > last_time_[a]))
    return bad("time_s = " + format_value(row.time_s) + " s on axis " + std::string(axis) +
               (row.time_s == last_time_[a] ? " repeats" : " goes backwards from") + " line " +
               std::to_string(last_line_[a]) + " (" + format_value(last_time_[a]) +
               " s): time must increase on each axis");
  last_time_[a] = row.time_s;
  last_line_[a] = line_;
  rows.push_back(row);
  ++good_;
  return true;
}

bool CurrentCsvParser::feed(std::string_view chunk, std::vector<CurrentRow>& rows,
                            std::vector<CsvLineError>& errors, bool stop_at_error) {
  // Complete the unfinished line of the previous chunk first.
  if (!pending_.empty()) {
    const std::size_t nl = chunk.find('\n');
    if (nl == std::string_view::npos) {
      pending_.append(chunk);
      return true;
    }
    pending_.append(chunk.substr(0, nl));
    chunk.remove_prefix(nl + 1);
    ++line_;
    const std::string line = std::move(pending_);
    pending_.clear();
    if (!parse_line(line, rows, errors) && stop_at_error) return false;
  }
  const char* p = chunk.data();
  const char* end = p + chunk.size();
  while (p < end) {
    const char* nl =
        static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
    if (!nl) {
      pending_.assign(p, static_cast<std::size_t>(end - p));
      break;
    }
    ++line_;
    if (!parse_line(std::string_view(p, static_cast<std::size_t>(nl - p)), rows, errors) &&
        stop_at_error)
      return false;
    p = nl + 1;
  }
  return true;
}

bool CurrentCsvParser::finish(std::vector<CurrentRow>& rows, std::vector<CsvLineError>& errors,
                              bool stop_at_error) {
  bool ok = true;
  if (!pending_.empty()) {
    ++line_;
    const std::string line = std::move(pending_);
    pending_.clear();
    ok = parse_line(line, rows, errors) || !stop_at_error;
  }
  if (!header_done_)
    throw InvalidInput({"line 1: empty input: expected a header line with the columns "
                        "time_s,axis,iu_a,iv_a,iw_a,speed_rad_s" +
                        (extra_column_.empty() ? std::string() : "," + extra_column_)},
                       source_);
  if (data_lines_ == 0)
    throw InvalidInput(
        {"line " + std::to_string(line_ + 1) +
         ": no data after the header (the input ends at line " + std::to_string(line_) + ")"},
        source_);
  return ok;
}

void append_number(std::string& out, double value, int digits) {
  char buffer[40];
  const auto r = digits > 0 ? std::to_chars(buffer, buffer + sizeof buffer, value,
                                            std::chars_format::general, digits)
                            : std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, r.ptr);
}

void append_estimate_row(std::string& out, double time_s, std::string_view axis,
                         const ForceEstimate& e) {
  append_number(out, time_s);
  out += ',';
  out += axis;
  out += ',';
  append_number(out, e.force_n, 7);
  out += ',';
  if (e.sigma_known) append_number(out, e.force_sigma_n, 7);  // else empty: unknown
  out += ',';
  append_number(out, e.speed_rad_s, 7);
  out += ',';
  append_number(out, e.accel_rad_s2, 7);
}

}  // namespace cutdyn
