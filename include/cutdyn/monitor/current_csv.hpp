// The monitor's CSV streams: the current/speed log it reads and the estimate it writes;
// docs/models/monitor.md §6. Plain text in, plain text out, no io dependency, so that
// estimation from a stream runs (and is benchmarked) at the speed of the library.
//
// Input: a header line naming the columns, then one sample per line. Required columns, in
// any order, more allowed: time_s,axis,iu_a,iv_a,iw_a,speed_rad_s (and a reference force
// column for calibration step 2). Fields are separated by commas, surrounding blanks are
// ignored, no quoting; blank lines are ignored. A line ends at LF, CR LF or a lone CR (any
// mix); a UTF-8 byte order mark before the first line is skipped. A line longer than
// kMaxCurrentLineBytes, or with a control byte (NUL, ...; a tab is a blank), is a bad line,
// and the parser holds at most that many bytes of a line, however long it is.
#pragma once

#include <array>
#include <charconv>
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

/// The longest line the reader takes, in bytes without its line end (1 MiB): a longer one is a
/// bad line (before the header: an error), read past without being held in memory.
inline constexpr std::size_t kMaxCurrentLineBytes = std::size_t{1} << 20;

/// std::from_chars(first, last, value) (chars_format::general), the same result and the same
/// end for every input, faster for plain decimals of at most 19 digits and a small exponent
/// (Clinger's exact fast path: the significand and the power of ten are exact doubles, so one
/// correctly rounded multiplication or division gives the correctly rounded value).
std::from_chars_result parse_double(const char* first, const char* last, double& value);

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
/// Errors of the input as a whole (no header, a missing column, no data line; a line before
/// the header that is too long or not text) throw InvalidInput naming the line and `source`;
/// errors of one data line are returned. A data line is bad if a required field is missing or
/// empty, is not a number, is NaN or infinite, if its time does not increase over the previous
/// good line of the same axis, if it has more fields than the header, if it is longer than
/// kMaxCurrentLineBytes, if it has a control byte (binary data), or if its axis is not UTF-8.
/// No allocation per line: good lines take a fast path (plain numbers, no blanks), the rest
/// the general one, which gives the same rows.
class CurrentCsvParser {
 public:
  /// `extra_column`: one more required numeric column (e.g. "force_n"), or empty.
  explicit CurrentCsvParser(std::string source, std::string extra_column = {});

  /// Parses the complete lines in `chunk` (joined to the unfinished line of the previous
  /// chunk), appending good rows to `rows` and bad lines to `errors`. With `stop_at_error`
  /// it stops at the first bad line and returns false; the parser must not be fed again.
  /// A line that grows past kMaxCurrentLineBytes is reported as soon as it does with
  /// `stop_at_error`, else at its end with its length.
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
  // The lines in [begin, end), ended by lone CRs and by `end`; line_ is the first's number.
  bool lines_with_cr(const char* begin, const char* end, bool stop_at_error,
                     std::vector<CurrentRow>& rows, std::vector<CsvLineError>& errors);
  // The line at `begin` if it is a good data line of plain fields ended by LF or CR LF before
  // `end`: appended to `rows` (line_ counts it), and the position after its line end; else
  // nullptr, nothing changed.
  const char* fast_line(const char* begin, const char* end, std::vector<CurrentRow>& rows);
  // The lines from `begin` on, as many as are good data lines of the standard layout of at most
  // 63 bytes with their line end (and 96 before `end`), taken as fast_line takes them: the
  // separators of a line found at once, so that its numbers are read independently of one another.
  // Returns where it stopped: the first line it did not take.
  const char* separated_lines(const char* begin, const char* end, std::vector<CurrentRow>& rows);
  // The end of a fast line: the row of `value` (time_s in slot 0, ...) on axis `name` appended,
  // if the axis is known and its time goes forward; else false, nothing changed.
  bool keep_row(const double* value, std::string_view name, std::vector<CurrentRow>& rows);
  // The general path: every check and message.
  bool take_line(std::string_view line, std::vector<CurrentRow>& rows,
                 std::vector<CsvLineError>& errors);
  bool parse_line(std::string_view line, std::vector<CurrentRow>& rows,
                  std::vector<CsvLineError>& errors);
  // Line `number` is past kMaxCurrentLineBytes: `bytes` long, or more if not `ended`.
  bool too_long(std::size_t number, std::size_t bytes, bool ended,
                std::vector<CsvLineError>& errors);
  // The unfinished line grows by [begin, end).
  bool hold(const char* begin, const char* end, bool stop_at_error,
            std::vector<CsvLineError>& errors);
  void parse_header(std::string_view line);
  void parse_comment(std::string_view line);
  int axis_index(std::string_view name);

  std::string source_, extra_column_;
  // The unfinished line (no line end seen yet), at most kMaxCurrentLineBytes; once it is
  // longer only its length is kept (held_bytes_, long_line_).
  std::string pending_;
  std::size_t held_bytes_ = 0;
  bool long_line_ = false;
  bool after_cr_ = false;  // the last chunk ended with a CR: an LF first in the next is its end
  std::size_t line_ = 0;
  bool header_done_ = false;
  std::size_t data_lines_ = 0, good_ = 0;
  // Field index of time_s, axis, iu_a, iv_a, iw_a, speed_rad_s, extra, rotor_angle_rad; and
  // the fields a line needs at least.
  static constexpr int kAngleSlot = 7;
  int index_[8] = {-1, -1, -1, -1, -1, -1, -1, -1};
  std::vector<int> slot_of_field_;  // per field of a line: its slot in index_, or -1
  int needed_fields_ = 0, header_fields_ = 0;
  bool standard_layout_ = false;  // time_s,axis,iu_a,iv_a,iw_a,speed_rad_s[,rotor_angle_rad] first
  std::vector<std::string> header_names_;
  std::vector<std::string> axes_;
  std::vector<CsvComment> comments_;
  std::vector<double> last_time_;
  std::vector<std::size_t> last_line_;
  std::array<int, 256> one_byte_axis_;  // the index of the axis named by one byte, or -1
};

/// Appends a number in the form the monitor writes: shortest round-trip (`digits` = 0) or
/// `digits` significant digits; the same text as std::to_chars(value) and std::to_chars(value,
/// chars_format::general, digits), with fast paths for the shortest form of at most 15 digits
/// and for 7 digits.
void append_number(std::string& out, double value, int digits = 0);

/// The room write_number needs at p.
inline constexpr std::size_t kNumberRoom = 48;

/// append_number's text written at p (kNumberRoom bytes of room; bytes past the returned end
/// may be overwritten): for output assembled in place, without a copy per number.
char* write_number(char* p, double value, int digits = 0);

/// The estimate's columns: time_s,axis,force_n,force_sigma_n,speed_rad_s,accel_rad_s2.
inline constexpr const char* kEstimateHeader =
    "time_s,axis,force_n,force_sigma_n,speed_rad_s,accel_rad_s2";

/// Appends one estimate line without its line end: time as read (shortest round-trip), the
/// rest to 7 significant digits; force_sigma_n is left empty when the estimate's uncertainty
/// is unknown (ForceEstimate::sigma_known false), never NaN.
void append_estimate_row(std::string& out, double time_s, std::string_view axis,
                         const ForceEstimate& e);

/// The room write_estimate_row needs at p besides the axis name's bytes.
inline constexpr std::size_t kEstimateRowRoom = 192;

/// append_estimate_row's line written at p (kEstimateRowRoom + axis.size() bytes of room;
/// bytes past the returned end may be overwritten): for rows assembled in place, without a copy
/// per row.
char* write_estimate_row(char* p, double time_s, std::string_view axis, const ForceEstimate& e);

}  // namespace cutdyn
