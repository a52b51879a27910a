// Force files for the identification of cutting coefficients (forces/identify.hpp);
// docs/models/identification.md, "Force files".
//
// Two CSV forms, told apart by their header (the first line that is neither blank nor a
// comment). Columns are found by name, in any order; an unknown column is an error (a
// misspelt optional column would otherwise be dropped in silence). Lines starting with `#` are
// comments; blank lines are skipped; CRLF line ends are accepted; no quoting.
//
// * Mean forces, one row per test cut: feed_per_tooth_mm,depth_mm,fx_n,fy_n[,fz_n].
// * A force record of one test cut: time_s,fx_n,fy_n[,fz_n], the cut stated in comment lines
//   before the header, `# key = value` (several items may share a line, separated by commas):
//       # feed_per_tooth_mm = 0.05
//       # depth_mm = 2
//       # rpm = 3000
//   Several records (one per feed) are several files.
// * The force `cutdyn monitor estimate` wrote from the motor currents of the feed axes:
//   time_s,axis,force_n[,…] (its other columns ignored), one row per axis and instant, axes
//   named x, y (and z), with the cut in `# key = value` comment lines as for a record. The
//   monitor's force resists the axis' motion (docs/models/feed-drive.md: Fn = −F·n): the force
//   on the cutter is fx = −force_n of axis x, fy = −force_n of axis y (decision: the axes move
//   the cutter along the case's +x, the feed, and +y). Every instant needs x and y.
//
// Forces are those on the cutter (x the feed direction, y as in stability/milling.hpp), N.
// Errors throw cutdyn::InvalidInput with where = the file and problems naming the line and
// the column, e.g. "line 7, column fy_n: \"abc\" is not a number".
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "cutdyn/forces/identify.hpp"

namespace cutdyn::io {

enum class ForceFileKind { kMeanForces, kTimeSeries, kMonitorEstimate };

/// The form of `text` from its header. Throws InvalidInput (where = source) when there is no
/// header or it names neither form's columns.
ForceFileKind force_file_kind(std::string_view text, const std::string& source);

/// The rows of a mean-force file in SI, labelled "source:line".
std::vector<MeanForce> parse_mean_force_csv(std::string_view text, const std::string& source);

/// A force record, labelled `source`, in SI.
ForceSeries parse_force_series_csv(std::string_view text, const std::string& source);

/// A record from `cutdyn monitor estimate`'s output (the axes paired by instant), in SI.
ForceSeries parse_monitor_force_csv(std::string_view text, const std::string& source);

/// Any form as mean forces: the rows, or the record's mean over whole revolutions
/// (mean_over_revolutions).
std::vector<MeanForce> parse_force_file(std::string_view text, const std::string& source);

/// parse_force_file of every file, the samples in order. Throws InvalidInput (where = the
/// file) for the first file that cannot be read or has problems.
std::vector<MeanForce> read_force_files(const std::vector<std::filesystem::path>& paths);

}  // namespace cutdyn::io
