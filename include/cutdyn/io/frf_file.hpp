// FRF files: a measured receptance read from, and written to, the files that impact-test
// systems and machining-dynamics tools exchange; docs/frf-files.md.
//
// Three formats, detected from the content (the extension only sharpens an error message):
//   * CutPro-style text (.frf): columns frequency Hz, real m/N, imaginary m/N, separated by
//     blanks or tabs; `%`, `#` and `;` start comment lines.
//   * CSV with a header naming the columns: frequency_hz and one pair of real/imaginary
//     columns of receptance (m/N), mobility (m/s/N) or accelerance (m/s²/N).
//   * Universal File Format dataset 58, function at nodal DOF, as ASCII or as its binary
//     variant 58b [Sdrc1999]; the units of dataset 164 are applied [Sdrc1999].
// Mobility Y and accelerance A are converted to receptance G (m/N) at ω = 2πf (rad/s):
// G = Y/(iω) and G = A/(−ω²).
#pragma once

#include <complex>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cutdyn/modal/measured_frf.hpp"

namespace cutdyn {

enum class FrfFormat { kCutPro, kCsv, kUff };

/// "frf", "csv", "uff".
const char* to_string(FrfFormat format);
/// The inverse of to_string (also "unv" for kUff); nullopt for any other name.
std::optional<FrfFormat> parse_frf_format(std::string_view name);

/// What the file's ordinate is: displacement, velocity or acceleration per force.
enum class FrfQuantity { kReceptance, kMobility, kAccelerance };

/// "receptance", "mobility", "accelerance".
const char* to_string(FrfQuantity quantity);

struct FrfFileOptions {
  /// The format to read; nullopt: detected from the content.
  std::optional<FrfFormat> format;
  /// UFF: 0-based index of the dataset to read among the file's datasets 58 (and 58b);
  /// nullopt: the first one that is a frequency response function.
  std::optional<int> dataset;
  /// CutPro text: the file's units, taking the place of any its header states: an FRF unit
  /// ("mm/N", "(m/s)/N", "g/N"), optionally with a frequency unit before it ("kHz, mm/N").
  /// nullopt: from the header, else Hz and m/N. Refused for CSV and UFF (they state theirs).
  std::optional<std::string> units;
};

/// One dataset 58 of a universal file (all of them are listed, whichever is read).
struct UffDatasetInfo {
  int index = 0;            // among the datasets 58 of the file, from 0
  std::size_t line = 0;     // of its `-1` start line
  bool binary = false;      // 58b
  int function_type = 0;    // record 6 field 1; 4 = frequency response function
  std::string description;  // ID line 1, trimmed
  int response_node = 0, response_direction = 0;    // direction 1 = +X, 2 = +Y, 3 = +Z, ...
  int reference_node = 0, reference_direction = 0;  // 0 when not given
};

struct FrfReadResult {
  MeasuredFrf frf;  // receptance in m/N at increasing frequencies in Hz, valid
  FrfFormat format = FrfFormat::kCutPro;
  FrfQuantity quantity = FrfQuantity::kReceptance;  // as stored, before conversion
  std::string units;                         // the file's units as understood, e.g. "Hz, mm/N"
  std::string description;                   // UFF: ID line 1 of the dataset read; empty otherwise
  std::vector<UffDatasetInfo> uff_datasets;  // UFF: every dataset 58 of the file
  std::vector<std::string> warnings;         // assumptions made, e.g. units not stated
};

/// Reads one measured FRF. Throws InvalidInput with where() = the file's path and one
/// problem per fault found, each naming its line ("line 17: frequency 120 Hz is not greater
/// than the one before (120 Hz)"), for a missing, unreadable, empty or non-text file, a
/// malformed number, NaN or infinity, missing columns, fewer than 3 points, frequencies that
/// do not increase, a dataset that is not an FRF or a conversion at 0 Hz.
FrfReadResult read_frf_file(const std::filesystem::path& file, const FrfFileOptions& options = {});

/// read_frf_file(...).frf: the warnings are dropped (use read_frf_file to report them).
MeasuredFrf read_frf(const std::filesystem::path& file, FrfFileOptions options = {});

/// Reads the content of a file already in memory; `source` names it in the errors and
/// `extension` (".frf", ".csv", ".uff", ...) is the hint read_frf_file takes from the name.
FrfReadResult parse_frf(std::string_view content, const std::string& source,
                        const FrfFileOptions& options = {}, std::string_view extension = {});

/// UFF abscissa: even spacing stores the first frequency and the increment (6 significant
/// digits, E13.5), uneven stores every frequency (also E13.5); automatic takes even when the
/// frequencies are evenly spaced to within 1e-9 of the increment once so stored.
enum class UffSpacing { kAutomatic, kEven, kUneven };

struct FrfWriteOptions {
  std::string description;  // a comment line (frf, csv) or UFF ID line 1; "NONE" if empty
  UffSpacing uff_spacing = UffSpacing::kAutomatic;
  bool uff_single_precision = false;  // ordinate data type 5 (E13.5) instead of 6 (E20.12)
  bool uff_binary = false;            // dataset 58b, little-endian IEEE 754
  int uff_response_node = 1, uff_response_direction = 1;  // record 6; 1 = +X, 2 = +Y
  int uff_reference_node = 1, uff_reference_direction = 1;
};

struct FrfText {
  std::string text;                   // the file's content (binary for a 58b)
  std::vector<std::string> warnings;  // e.g. UFF frequencies rounded to 6 digits
};

/// The file content of `frf` (receptance) in `format`: numbers in shortest round-trip form
/// (frf, csv) or E20.12 (UFF double precision, relative rounding ≤ 5e-13). Throws
/// InvalidInput for an invalid `frf`, or when UFF's 6-digit abscissa would make two
/// frequencies equal, or when kEven is asked for frequencies that are not evenly spaced.
FrfText format_frf(const MeasuredFrf& frf, FrfFormat format, const FrfWriteOptions& options = {});

/// Writes format_frf(...) to `file`; returns its warnings. Throws InvalidInput (where = the
/// path) as format_frf does, and when the file cannot be written.
std::vector<std::string> write_frf(const std::filesystem::path& file, const MeasuredFrf& frf,
                                   FrfFormat format, const FrfWriteOptions& options = {});

/// The receptance G (m/N) of a `quantity` value at f_hz: Y/(iω) or A/(−ω²) with ω = 2πf.
/// Precondition: f_hz > 0 unless quantity is kReceptance.
std::complex<double> to_receptance(FrfQuantity quantity, std::complex<double> value, double f_hz);

/// The share of a receptance's imaginary part that is negative, by its square:
/// Σ_{Im G < 0} (Im G)² / Σ (Im G)² over the points above 0 Hz (1 for a table with Im G = 0
/// throughout). A direct receptance of a passive structure has Im G ≤ 0 at every frequency.
double negative_imaginary_share(const MeasuredFrf& receptance);

/// The mean of −Im G/|G| (the sine of the lag behind the force) at the local maxima of |G|
/// that reach 30 % of the highest one, weighted by |G|²: near 1 for a direct receptance (it
/// lags by 90° at a resonance), 0 for a mobility, −1 for an accelerance; 1 without a peak.
double peak_quadrature(const MeasuredFrf& receptance);

/// Why `receptance` (read from a file that stored `stored`, and converted) cannot be a direct
/// receptance, with the evidence: its imaginary part is positive over more than a quarter of
/// the response (negative_imaginary_share < 0.75) or its peaks lag the force by less than 30°
/// (peak_quadrature < 0.5), and, where the stored values would pass both as another quantity
/// (a receptance, mobility or accelerance), which one. Empty when plausible (docs/frf-files.md,
/// "Is it a receptance?").
std::string direct_receptance_problem(const MeasuredFrf& receptance, FrfQuantity stored);

}  // namespace cutdyn
