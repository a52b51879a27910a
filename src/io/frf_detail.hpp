// Shared pieces of the FRF file readers and writers (frf_*.cpp): lines, numbers, unit names
// and the checks every table goes through; docs/frf-files.md.
#pragma once

#include <complex>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cutdyn/core/error.hpp"
#include "cutdyn/io/frf_file.hpp"

namespace cutdyn::io::detail {

/// One line of a text, without its line end (LF or CRLF), numbered from 1.
struct TextLine {
  std::string_view text;
  std::size_t number = 0;
};

std::vector<TextLine> split_lines(std::string_view content);
std::string_view trim(std::string_view s);
/// Fields separated by blanks and tabs.
std::vector<std::string_view> split_blanks(std::string_view s);
/// A number as C, Fortran (1.5D+03) and spreadsheets write it; "nan" and "inf" are returned
/// as such (the caller says they are not finite); nullopt if `token` is not a whole number.
std::optional<double> parse_number(std::string_view token);
/// A short quoted excerpt for messages: "abc".
std::string excerpt(std::string_view s);
std::string lower(std::string_view s);
/// The first byte that is neither text nor a line end (a control character other than tab,
/// CR, LF, FF), or npos.
std::size_t first_binary_byte(std::string_view s);
/// "line N: " + what.
std::string at_line(std::size_t line, std::string_view what);

/// A unit of the ordinate: value_in_SI = value · scale (SI: m/N, m/s/N, m/s²/N).
struct OrdinateUnit {
  FrfQuantity quantity = FrfQuantity::kReceptance;
  double scale = 1.0;
  std::string name;  // as understood, e.g. "mm/N"
};

/// A response unit alone: "m", "mm", "um", "in" (displacement), "m/s", "mm/s", "in/s"
/// (velocity), "m/s^2" (also m/s2, m/s**2, m/s²), "mm/s^2", "in/s^2", "g" (acceleration).
std::optional<OrdinateUnit> parse_response_unit(std::string_view text);
/// A force unit: "N", "kN", "lbf" (also "lb"); the factor to newtons.
std::optional<double> parse_force_unit(std::string_view text);
/// A response per force: "m/N", "(m/s)/N", "m/s/N", "g/N", "mm/lbf", ...
std::optional<OrdinateUnit> parse_ordinate_unit(std::string_view text);
/// "Hz", "kHz", "rad/s", "1/s": the factor to Hz.
std::optional<double> parse_frequency_unit(std::string_view text);

/// A point as read: frequency and value in the file's units, and the line it came from.
struct RawPoint {
  double frequency = 0.0;
  std::complex<double> value;
  std::size_t line = 0;
  std::optional<double> coherence;  // γ², where the file gives it (for every point or none)
};

/// The receptance table of `points` (frequency · frequency_scale in Hz, value ·
/// unit.scale converted from unit.quantity), after the checks every format shares: finite
/// numbers, frequencies at least 0 and increasing, at least 3 points, no conversion at 0 Hz,
/// coherences (where given) from 0 to 1.
/// Throws InvalidInput(problems, source) naming the lines.
MeasuredFrf finish_table(const std::vector<RawPoint>& points, const OrdinateUnit& unit,
                         double frequency_scale, const std::string& source);

/// Throws InvalidInput({at_line(line, what)}, source).
[[noreturn]] void fail_at(const std::string& source, std::size_t line, std::string what);

/// The units given for a file from outside (FrfFileOptions::units): the frequency factor to Hz
/// (1 unless stated) and the ordinate's unit. Throws InvalidInput naming `units` otherwise.
struct GivenUnits {
  double frequency_scale = 1.0;
  std::string frequency_name = "Hz";
  OrdinateUnit ordinate;
};
GivenUnits parse_given_units(std::string_view text, const std::string& source);

FrfReadResult read_cutpro_text(std::string_view content, const std::string& source,
                               const std::optional<GivenUnits>& given = std::nullopt);
FrfReadResult read_csv_text(std::string_view content, const std::string& source);
FrfReadResult read_uff_text(std::string_view content, const std::string& source,
                            const FrfFileOptions& options);

std::string format_cutpro(const MeasuredFrf& frf, const FrfWriteOptions& options);
std::string format_csv(const MeasuredFrf& frf, const FrfWriteOptions& options);
FrfText format_uff(const MeasuredFrf& frf, const FrfWriteOptions& options);

/// Appends `value` in its shortest round-trip form.
void append_shortest(std::string& out, double value);

}  // namespace cutdyn::io::detail
