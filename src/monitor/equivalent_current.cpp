#include "cutdyn/monitor/equivalent_current.hpp"

#include <cmath>

namespace cutdyn {

double equivalent_current(double iu, double iv, double iw, CurrentMeasure measure) {
  const double sum = iu * iu + iv * iv + iw * iw;
  // [Zheng2012, eq. 1]; the space vector is sqrt(2) times the RMS.
  return measure == CurrentMeasure::kRms ? std::sqrt(sum / 3.0) : std::sqrt(sum * (2.0 / 3.0));
}

double signed_equivalent_current(double iu, double iv, double iw, double theta,
                                 CurrentMeasure measure) {
  constexpr double third = 2.0943951023931954923;  // 2π/3
  const double peak = -(2.0 / 3.0) * (iu * std::sin(theta) + iv * std::sin(theta - third) +
                                      iw * std::sin(theta + third));
  return measure == CurrentMeasure::kRms ? peak * std::sqrt(0.5) : peak;
}

double equivalent_current_sigma(double phase_sigma_a, CurrentMeasure measure) {
  // d Id / d i_k = c²·i_k/Id with c² = 1/3 or 2/3, so var = c⁴·σ²·Σi²/Id² = c²·σ².
  return phase_sigma_a *
         (measure == CurrentMeasure::kRms ? std::sqrt(1.0 / 3.0) : std::sqrt(2.0 / 3.0));
}

std::string_view to_string(CurrentMeasure measure) {
  return measure == CurrentMeasure::kRms ? "rms" : "space-vector";
}

std::optional<CurrentMeasure> parse_current_measure(std::string_view name) {
  if (name == "rms") return CurrentMeasure::kRms;
  if (name == "space-vector") return CurrentMeasure::kSpaceVector;
  return std::nullopt;
}

}  // namespace cutdyn
