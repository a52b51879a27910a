// The monitor's CSV streams: the current/speed log it reads and the estimate it writes;
// docs/models/monitor.md §6. Plain text in, plain text out, no io dependency, so that
// estimation from a stream runs (and is benchmarked) at the speed of the library.
//
// Input: a header line naming the columns, then one sample per line. Required columns, in
// any order, more allowed: time_s,axis,iu_a,iv_a,iw_a,speed_rad_s (and a reference force
// column for calibration step 2). Fields are separated by commas, surrounding blanks are
// ignored, no quoting; blank lines are ignored; CRLF line ends are accepted.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "cutdyn/monitor/force_estimator.hpp"

namespace cutdyn {

/// The columns every current log has.
inline constexpr const char* kCurrentColumns[] = {"time_s", "axis", "iu_a",
                                                  "iv_a",   "iw_a", "speed_rad_s"};

/// The optional column of the electrical rotor angle θe (rad): where the header has it, every
/// line must give it and the monitor uses the signed torque current (Park transform,
/// signed_equivalent_current) instead of the magnitude.
inline constexpr const char* kRotorAngleColumn = "rotor_angle_rad";

/// A comment line before the header, `# key = value, key = value, ...` (docs/models/monitor.md
/// §6): e.g. `# axis = x, measure = space-vector, torque_constant_nm_per_a = 1.25, pole_pairs = 4`
/// as `cutdyn drive --currents` writes one per axis. Keys and values are trimmed.
struct CsvComment {
  std::size_t line = 0;
  std::vector<std::pair<std::string, std::string>> fields;
  /// The value of `key`, or nullptr.
  const std::string* find(std::string_view key) const;
};

/// One good data line.
struct CurrentRow {
  std::size_t line = 0;  // 1-based line number in the input
  int axis = 0;          // index into CurrentCsvParser::axes()
  double time_s = 0.0, iu_a = 0.0, iv_a = 0.0, iw_a = 0.0, speed_rad_s = 0.0;
  double extra = 0.0;            // the extra column, if one was asked for
  double rotor_angle_rad = 0.0;  // θe, if the header has rotor_angle_rad (has_rotor_angle())
};

/// A bad data line: its number and what is wrong, e.g. `iu_a = "abc": not a number`.
struct CsvLineError {
  std::size_t line = 0;
  std::string what;
  std::string text() const;  // "line N: what"
};

/// Push parser: feed it chunks of any size (as they arrive from a pipe), then finish().
/// Errors of the input as a whole (no header, a missing column, no data line) throw
/// InvalidInput naming the line and `source`; errors of one data line are returned.
/// A data line is bad if a required field is missing or empty, is not a number, is NaN or
/// infinite, or if its time does not increase over the previous good line of the same axis.
class CurrentCsvParser {
 public:
  /// `extra_column`: one more required numeric column (e.g. "force_n"), or empty.
  explicit CurrentCsvParser(std::string source, std::string extra_column = {});

  /// Parses the complete lines in `chunk` (joined to the unfinished line of the previous
  /// chunk), appending good rows to `rows` and bad lines to `errors`. With `stop_at_error`
  /// it stops at the first bad line and returns false; the parser must not be fed again.
  bool feed(std::string_view chunk, std::vector<CurrentRow>& rows,
            std::vector<CsvLineError>& errors, bool stop_at_error);
  /// End of input: parses a last line without a line end; throws for an empty input or one
  /// with no data line after the header. Returns false as feed() does.
  bool finish(std::vector<CurrentRow>& rows, std::vector<CsvLineError>& errors, bool stop_at_error);

  /// Axis names in order of first appearance.
  const std::vector<std::string>& axes() const { return axes_; }
  const std::string& source() const { return source_; }
  /// The `# key = value, ...` lines before the header, in order.
  const std::vector<CsvComment>& comments() const { return comments_; }
  /// The current measure the comments record for `axis` (a comment with `axis = <axis>`, or
  /// one without an axis key, which is for every axis), and the line that says so; nullopt
  /// if none does.
  std::optional<std::pair<CurrentMeasure, std::size_t>> recorded_measure(
      const std::string& axis) const;
  /// Whether the header has the column rotor_angle_rad (known once the header is read).
  bool has_rotor_angle() const { return index_[kAngleSlot] >= 0; }
  std::size_t good_rows() const { return good_; }

 private:
  bool parse_line(std::string_view line, std::vector<CurrentRow>& rows,
                  std::vector<CsvLineError>& errors);
  void parse_header(std::string_view line);
  void parse_comment(std::string_view line);
  int axis_index(std::string_view name);

  std::string source_, extra_column_;
  std::string pending_;
  std::size_t line_ = 0;
  bool header_done_ = false;
  std::size_t data_lines_ = 0, good_ = 0;
  // Field index of time_s, axis, iu_a, iv_a, iw_a, speed_rad_s, extra, rotor_angle_rad; and
  // the fields a line needs at least.
  static constexpr int kAngleSlot = 7;
  int index_[8] = {-1, -1, -1, -1, -1, -1, -1, -1};
  std::vector<int> slot_of_field_;  // per field of a line: its slot in index_, or -1
  int needed_fields_ = 0, header_fields_ = 0;
  std::vector<std::string> header_names_;
  std::vector<std::string> axes_;
  std::vector<CsvComment> comments_;
  std::vector<double> last_time_;
  std::vector<std::size_t> last_line_;
};

/// Appends a number in the form the monitor writes: shortest round-trip (`digits` = 0) or
/// `digits` significant digits.
void append_number(std::string& out, double value, int digits = 0);

/// The estimate's columns: time_s,axis,force_n,force_sigma_n,speed_rad_s,accel_rad_s2.
inline constexpr const char* kEstimateHeader =
    "time_s,axis,force_n,force_sigma_n,speed_rad_s,accel_rad_s2";

/// Appends one estimate line without its line end: time as read (shortest round-trip), the
/// rest to 7 significant digits; force_sigma_n is left empty when the estimate's uncertainty
/// is unknown (ForceEstimate::sigma_known false), never NaN.
void append_estimate_row(std::string& out, double time_s, std::string_view axis,
                         const ForceEstimate& e);

}  // namespace cutdyn
