#include "cutdyn/app/fit.hpp"

#include <fmt/format.h>

#include <cstdlib>

#include "cutdyn/core/error.hpp"

namespace cutdyn::app {

namespace {

// The response direction every FRF dataset of a UFF file names, if they agree on x or y.
Direction file_direction(const FrfReadResult& read) {
  std::optional<int> common;
  for (const UffDatasetInfo& d : read.uff_datasets) {
    if (d.function_type != 4) continue;
    const int dir = std::abs(d.response_direction);
    if (common && *common != dir) return Direction::kX;
    common = dir;
  }
  return common == 2 ? Direction::kY : Direction::kX;
}

}  // namespace

FitJobReport run_fit(const FitRequest& request) {
  FitJobReport r;
  r.source = request.file.string();
  r.read = read_frf_file(request.file, request.file_options);
  const Direction direction = request.direction ? *request.direction : file_direction(r.read);
  rethrow_as(r.source, "fit", [&] { r.fit = fit_modes(r.read.frf, direction, request.fit); });
  std::vector<double> band;
  for (double f : r.read.frf.frequency_hz)
    if (f >= r.fit.lo_hz && f <= r.fit.hi_hz) band.push_back(f);
  r.fitted = fitted_frf(r.fit, band);
  r.warnings = r.read.warnings;
  r.warnings.insert(r.warnings.end(), r.fit.warnings.begin(), r.fit.warnings.end());
  return r;
}

std::string modes_toml(const FitJobReport& r) {
  std::string out = fmt::format(
      "# Modes fitted to {} over {:.6g}–{:.6g} Hz ({} points, {} modes{}), RMS relative error "
      "{:.3g} %.\n",
      r.source, r.fit.lo_hz, r.fit.hi_hz, r.fit.points, r.fit.modes.size(),
      r.fit.automatic ? " chosen from the stabilisation diagram" : "",
      100.0 * r.fit.rms_relative_error);
  for (const FittedMode& m : r.fit.modes) {
    out += fmt::format(
        "\n[[modes]]\ndirection = \"{}\"\nnatural_hz = {:.17g}\ndamping_ratio = {:.17g}\n"
        "stiffness_n_per_m = {:.17g}\n",
        to_string(r.fit.direction), m.natural_hz, m.damping_ratio, m.stiffness_n_per_m);
    if (std::abs(m.residue_phase_deg) > 10.0)
      out += fmt::format(
          "# complex residue ({:.3g}° from a real mode): stiffness from its magnitude\n",
          m.residue_phase_deg);
  }
  return out;
}

}  // namespace cutdyn::app
