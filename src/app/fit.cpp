#include "cutdyn/app/fit.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"

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
  // The fit's model is a direct receptance (docs/frf-files.md, "Is it a receptance?").
  if (const std::string problem = direct_receptance_problem(r.read.frf, r.read.quantity);
      !problem.empty())
    throw InvalidInput({problem}, r.source);
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
      "{:.3g} %;\n# these modes alone (residue phases kept, no residual terms): {:.3g} %.\n",
      r.source, r.fit.lo_hz, r.fit.hi_hz, r.fit.points, r.fit.modes.size(),
      r.fit.automatic ? " chosen from the stabilisation diagram" : "",
      100.0 * r.fit.rms_relative_error, 100.0 * r.fit.model_rms_relative_error);
  // model.modes[i] is modes[i] as a Mode (same order).
  for (std::size_t i = 0; i < r.fit.model.modes.size(); ++i) {
    const Mode& m = r.fit.model.modes[i];
    const FittedMode& fm = r.fit.modes[i];
    out += fmt::format(
        "\n[[modes]]\ndirection = \"{}\"\nnatural_hz = {:.17g}\ndamping_ratio = {:.17g}\n"
        "stiffness_n_per_m = {:.17g}\n",
        to_string(m.direction), units::rad_per_s_to_hz(m.natural_rad_s), m.damping_ratio,
        m.stiffness_n_per_m);
    // A complex residue is part of the mode (docs/models/modal-fitting.md §10).
    if (m.residue_phase_rad != 0.0)
      out += fmt::format("residue_phase_deg = {:.17g}\n", units::rad_to_deg(m.residue_phase_rad));
    // The fit's uncertainty, as comments (§4.2): standard deviations and correlations.
    const auto& c = fm.covariance;
    const auto corr = [&](int a, int b) {
      const double d = std::sqrt(c[a][a] * c[b][b]);
      return d > 0.0 ? c[a][b] / d : 0.0;
    };
    out += fmt::format(
        "# 1σ: natural_hz {:.3g}, damping_ratio {:.3g}, stiffness_n_per_m {:.3g}; correlations "
        "f–ζ {:.2f}, f–k {:.2f}, ζ–k {:.2f}\n",
        fm.natural_hz_sigma, fm.damping_ratio_sigma, fm.stiffness_sigma_n_per_m, corr(0, 1),
        corr(0, 2), corr(1, 2));
  }
  return out;
}

}  // namespace cutdyn::app
