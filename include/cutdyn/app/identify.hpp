// The identify job: the cutting and edge coefficients of milling from the mean forces of test
// cuts (the average-force method of [Altintas2012, ch. 2]; docs/models/identification.md).
// The case gives the cutter (teeth) and its engagement (the window [φst, φex]); force files
// (io/force_file.hpp) give the test cuts; the fit (forces/identify.hpp) gives the
// coefficients with their 95 % intervals, the residuals and R². The report also writes the
// coefficients back as a case file's [cutting] table.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "cutdyn/app/request.hpp"
#include "cutdyn/forces/identify.hpp"
#include "cutdyn/io/case_file.hpp"

namespace cutdyn::app {

struct IdentifyRequest {
  std::vector<std::filesystem::path> force_files;  // as given; read in order
  RequestNames names;                              // names.where: the front end's name for them
};

/// One identified coefficient in the case file's unit.
struct IdentifiedValue {
  std::string name;  // "Kt", "Kr", "Kte", "Kre", "Ka", "Kae"
  /// The name of its key: a case file's [cutting] key for Kt, Kr, Kte, Kre
  /// ("kt_n_per_mm2"), the same pattern for the axial pair, which has no case key
  /// ("ka_n_per_mm2", "kae_n_per_mm").
  std::string key;
  bool case_key = false;             // a [cutting] key exists (not for Ka, Kae)
  std::string unit;                  // "N/mm²" or "N/mm"
  IdentifiedCoefficient value;       // value, standard error and interval in `unit`
  std::optional<double> case_value;  // the case's own [cutting] value, in `unit`
};

/// One test cut: what was measured, what the fitted coefficients give, and the difference.
struct IdentifiedSample {
  MeanForce measured;
  double fitted_fx_n = 0.0, fitted_fy_n = 0.0;
  std::optional<double> fitted_fz_n;
  SampleResidual residual;  // measured − fitted (N)
};

struct IdentifyJobReport {
  IdentifyCut cut;  // teeth and window from the case's [tool] and [operation]
  std::vector<std::string> force_files;
  CoefficientFit fit;                     // SI
  std::vector<IdentifiedValue> values;    // Kt, Kr, Kte, Kre[, Ka, Kae] in N/mm², N/mm
  std::vector<IdentifiedSample> samples;  // in the order read
  /// What the identification did not use, and why that is right (uneven pitch, helix), and
  /// how the [cutting] table can be used in this case.
  std::vector<std::string> notes;
  std::vector<std::string> warnings;  // the fit's
};

/// Needs a milling case with [tool] and [operation] ([[modes]] and [cutting] are not used) and
/// at least one force file. Throws cutdyn::InvalidInput naming the case and each missing
/// table, the request (names.where) without force files, a force file (its line and column)
/// that cannot be read, or the samples (file:line) the fit refuses.
IdentifyJobReport run_identify(const io::Case& c, const IdentifyRequest& request);

/// The coefficients as a case file's [cutting] table: kt_n_per_mm2, kr_n_per_mm2,
/// kte_n_per_mm, kre_n_per_mm in shortest round-trip form, each with its 95 % interval as a
/// comment. A value the case file would refuse (Kt <= 0, Kr, Kte or Kre < 0; the edge pair
/// when the case has a [force_law]) and the axial pair (no case key) are written as comments,
/// so that the table always loads.
std::string cutting_table_toml(const io::Case& c, const IdentifyJobReport& report);

}  // namespace cutdyn::app
