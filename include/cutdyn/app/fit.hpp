// The job of `cutdyn fit`: modes fitted to a measured FRF file (docs/models/modal-fitting.md),
// ready to paste into a case as [[modes]] tables.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "cutdyn/io/frf_file.hpp"
#include "cutdyn/modal/frf_fit.hpp"

namespace cutdyn::app {

struct FitRequest {
  std::filesystem::path file;
  FrfFileOptions file_options;
  /// The direction the fitted modes act in; nullopt: a UFF file's response direction (record
  /// 6: ±1 = x, ±2 = y, when every FRF of the file has the same), else x.
  std::optional<Direction> direction;
  FrfFitOptions fit;  // modes (0: automatic), band
};

struct FitJobReport {
  std::string source;  // the file as given
  FrfReadResult read;  // the table, its format and units, the reader's warnings
  FrfFit fit;
  MeasuredFrf fitted;                 // the fitted model at the table's frequencies inside the band
  std::vector<std::string> warnings;  // the reader's and the fit's
};

/// Reads the file and fits. Throws cutdyn::InvalidInput naming the file and line for a bad
/// file, and the band or number of modes for bad options.
FitJobReport run_fit(const FitRequest& request);

/// The fitted modes as [[modes]] tables of a case file, with the fit's provenance as
/// comments; parse_case reads them back to the fitted values.
std::string modes_toml(const FitJobReport& report);

}  // namespace cutdyn::app
