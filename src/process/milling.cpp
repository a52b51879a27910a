#include "cutdyn/process/milling.hpp"

#include <algorithm>
#include <cmath>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn {

using units::kPi;
using units::kTwoPi;

EngagementWindow engagement_window(double radial_immersion, bool down_milling) {
  if (down_milling) return {std::acos(2.0 * radial_immersion - 1.0), kPi};
  return {0.0, std::acos(1.0 - 2.0 * radial_immersion)};
}

std::vector<std::string> MillingTool::validate() const {
  Validator v("tool");
  v.require(teeth >= 1 && teeth <= 200, "teeth", teeth, "", "must be 1 to 200");
  v.require(helix_rad >= 0.0 && helix_rad < 0.5 * kPi, "helix_rad", helix_rad, "rad",
            "must be at least 0 and less than π/2");
  if (helix_rad > 0.0) v.require_positive("diameter_m", diameter_m, "m (needed with a helix)");
  if (!pitch_rad.empty()) {
    v.require(static_cast<int>(pitch_rad.size()) == teeth, "pitch_rad",
              static_cast<double>(pitch_rad.size()), "angles",
              "must give one angle per tooth (" + std::to_string(teeth) + ")");
    double sum = 0.0;
    for (std::size_t j = 0; j < pitch_rad.size(); ++j) {
      v.require(pitch_rad[j] > 0.0, "pitch_rad[" + std::to_string(j) + "]", pitch_rad[j], "rad",
                "must be positive");
      sum += pitch_rad[j];
    }
    v.require(std::abs(sum - kTwoPi) <= 1e-9 * kTwoPi, "pitch_rad (sum)", sum, "rad",
              "the pitch angles must add up to one revolution (2π)");
  }
  return v.problems();
}

std::vector<double> MillingTool::pitch_angles() const {
  if (!pitch_rad.empty()) return pitch_rad;
  return std::vector<double>(static_cast<std::size_t>(teeth), kTwoPi / teeth);
}

double MillingTool::lag_angle(double depth_m) const {
  return helix_rad == 0.0 ? 0.0 : 2.0 * depth_m * std::tan(helix_rad) / diameter_m;
}

int MillingTool::slices(double depth_m) const {
  constexpr double kMaxSliceLag = kPi / 360.0;  // 0.5°
  return std::clamp(static_cast<int>(std::ceil(lag_angle(depth_m) / kMaxSliceLag)), 1, 2000);
}

std::vector<std::string> MillingEngagement::validate() const {
  Validator v("engagement");
  if (entry_rad.has_value() != exit_rad.has_value()) {
    v.add("engagement.entry_rad, engagement.exit_rad: give both or neither");
  } else if (entry_rad) {
    v.require(*entry_rad >= 0.0 && *entry_rad < kPi, "entry_rad", *entry_rad, "rad",
              "must be at least 0 and less than π");
    v.require(*exit_rad > *entry_rad && *exit_rad <= kPi, "exit_rad", *exit_rad, "rad",
              "must be greater than entry_rad and at most π");
  } else {
    v.require(radial_immersion > 0.0 && radial_immersion <= 1.0, "radial_immersion",
              radial_immersion, "", "must be greater than 0 and at most 1");
  }
  return v.problems();
}

EngagementWindow MillingEngagement::window() const {
  if (entry_rad && exit_rad) return {*entry_rad, *exit_rad};
  return engagement_window(radial_immersion, down_milling);
}

double MillingEngagement::engaged_immersion() const {
  const EngagementWindow w = window();
  return 0.5 * (std::cos(w.entry_rad) - std::cos(w.exit_rad));
}

std::vector<std::string> MechanisticForceLaw::validate() const {
  Validator v("cutting");
  v.require(kt_pa >= 0.0, "kt_pa", kt_pa, "N/m²", "must not be negative");
  v.require(kr_pa >= 0.0, "kr_pa", kr_pa, "N/m²", "must not be negative");
  v.require(kte_n_per_m >= 0.0, "kte_n_per_m", kte_n_per_m, "N/m", "must not be negative");
  v.require(kre_n_per_m >= 0.0, "kre_n_per_m", kre_n_per_m, "N/m", "must not be negative");
  return v.problems();
}

std::vector<std::string> ErmolaevForceLaw::validate() const {
  Validator v("s1_law");
  v.require(c_n_per_m >= 0.0, "c_n_per_m", c_n_per_m, "N/m", "must not be negative");
  v.require(t2_s >= 0.0, "t2_s", t2_s, "s", "must not be negative");
  if (t2_angle_rad) {
    v.require(*t2_angle_rad >= 0.0 && std::isfinite(*t2_angle_rad), "t2_angle_rad", *t2_angle_rad,
              "rad", "must be finite and not negative");
    v.require(t2_s == 0.0, "t2_angle_rad", *t2_angle_rad, "rad",
              "and t2_s are two ways to give T2: give one");
  }
  v.require(p0_n >= 0.0, "p0_n", p0_n, "N", "must not be negative");
  v.require_positive("t1_m", t1_m, "m");
  v.require(std::isfinite(phi_rez_rad), "phi_rez_rad", phi_rez_rad, "rad", "must be finite");
  v.require(std::isfinite(phi_skv_rad), "phi_skv_rad", phi_skv_rad, "rad", "must be finite");
  return v.problems();
}

std::vector<std::string> MillingProcess::validate() const {
  Validator v;
  if (!modal.modes.empty()) v.merge(modal.validate());
  v.merge(tool.validate());
  v.merge(engagement.validate());
  v.merge(cutting.validate());
  if (s1_law) v.merge(s1_law->validate());
  return v.problems();
}

ModalModel MillingProcess::structure_modes() const { return with_fitted_modes(modal, measured); }

std::vector<std::string> MillingProcess::validate_for_stability() const {
  Validator v;
  v.merge(validate());
  if (modal.modes.empty() && !measured)
    v.add("modes: at least one mode (or a measured FRF) is required");
  if (measured && measured->fitted.modes.empty())
    v.add("measured: no modes fitted to the measured FRFs (the time-domain methods need them)");
  for (std::size_t i = 0; i < modal.modes.size(); ++i) {
    v.require(modal.modes[i].damping_ratio > 0.0, "modes[" + std::to_string(i) + "].damping_ratio",
              modal.modes[i].damping_ratio, "", "must be positive for a stability analysis");
  }
  v.require_positive("cutting.kt_pa", cutting.kt_pa, "N/m²");
  return v.problems();
}

}  // namespace cutdyn
