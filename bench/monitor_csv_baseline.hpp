// Today's CSV path of `cutdyn monitor estimate` before the fast reader (the parser and the
// row writer of src/monitor/current_csv.cpp as of 2026-11-24, comments before the header
// skipped rather than kept): the baseline that bench_monitor measures the current reader
// against in the same run. Not used anywhere else.
#pragma once

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "cutdyn/core/error.hpp"
#include "cutdyn/monitor/current_csv.hpp"

namespace cutdyn::bench::baseline {

constexpr int kTime = 0, kAxis = 1, kExtra = 6;

inline std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

inline bool blank(std::string_view s) { return trim(s).empty(); }

// Shortens a field for a message.
inline std::string quoted(std::string_view s) {
  std::string text(s.substr(0, 40));
  if (s.size() > 40) text += "...";
  return "\"" + text + "\"";
}

class BaselineCsvParser {
 public:
  explicit BaselineCsvParser(std::string source, std::string extra_column = {})
      : source_(std::move(source)), extra_column_(std::move(extra_column)) {}
  bool feed(std::string_view chunk, std::vector<CurrentRow>& rows,
            std::vector<CsvLineError>& errors, bool stop_at_error);
  bool finish(std::vector<CurrentRow>& rows, std::vector<CsvLineError>& errors, bool stop_at_error);
  const std::vector<std::string>& axes() const { return axes_; }

 private:
  bool parse_line(std::string_view line, std::vector<CurrentRow>& rows,
                  std::vector<CsvLineError>& errors);
  void parse_header(std::string_view line);
  int axis_index(std::string_view name);

  std::string source_, extra_column_;
  std::string pending_;
  std::size_t line_ = 0;
  bool header_done_ = false;
  std::size_t data_lines_ = 0, good_ = 0;
  static constexpr int kAngleSlot = 7;
  int index_[8] = {-1, -1, -1, -1, -1, -1, -1, -1};
  std::vector<int> slot_of_field_;
  int needed_fields_ = 0, header_fields_ = 0;
  std::vector<std::string> header_names_;
  std::vector<std::string> axes_;
  std::vector<double> last_time_;
  std::vector<std::size_t> last_line_;
};

inline void BaselineCsvParser::parse_header(std::string_view line) {
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

inline int BaselineCsvParser::axis_index(std::string_view name) {
  for (std::size_t i = 0; i < axes_.size(); ++i)
    if (axes_[i] == name) return static_cast<int>(i);
  axes_.emplace_back(name);
  last_time_.push_back(0.0);
  last_line_.push_back(0);
  return static_cast<int>(axes_.size() - 1);
}

inline bool BaselineCsvParser::parse_line(std::string_view line, std::vector<CurrentRow>& rows,
                                          std::vector<CsvLineError>& errors) {
  if (blank(line)) return true;
  if (!header_done_) {
    if (trim(line).front() != '#') parse_header(line);  // comments: not kept here
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

inline bool BaselineCsvParser::feed(std::string_view chunk, std::vector<CurrentRow>& rows,
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

inline bool BaselineCsvParser::finish(std::vector<CurrentRow>& rows,
                                      std::vector<CsvLineError>& errors, bool stop_at_error) {
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

inline void append_number(std::string& out, double value, int digits = 0) {
  char buffer[40];
  const auto r = digits > 0 ? std::to_chars(buffer, buffer + sizeof buffer, value,
                                            std::chars_format::general, digits)
                            : std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, r.ptr);
}

inline void append_estimate_row(std::string& out, double time_s, std::string_view axis,
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

}  // namespace cutdyn::bench::baseline
