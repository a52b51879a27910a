#include "cutdyn/drive/equivalent_current.hpp"

#include <algorithm>
#include <cmath>

namespace cutdyn {

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

namespace {

constexpr double kSqrt2OverPi = 0.79788456080286535588;  // sqrt(2/π)

// M(ν) of magnitude_mean, for ν >= 0.
double chi3_mean(double nu) {
  if (nu < 1e-8) return 2.0 * kSqrt2OverPi;
  return kSqrt2OverPi * std::exp(-0.5 * nu * nu) + (nu + 1.0 / nu) * std::erf(nu * M_SQRT1_2);
}

}  // namespace

double magnitude_mean(double true_a, double sigma_a) {
  if (!(sigma_a > 0.0)) return std::abs(true_a);
  return sigma_a * chi3_mean(std::abs(true_a) / sigma_a);
}

double magnitude_variance(double true_a, double sigma_a) {
  if (!(sigma_a > 0.0)) return 0.0;
  const double nu = std::abs(true_a) / sigma_a;
  // Beyond ν = 8 erf(ν/√2) = 1 and exp(−ν²/2) = 0 in double, M = ν + 1/ν exactly and the
  // difference 3 + ν² − M² = 1 − 1/ν² (computed as the difference it would cancel).
  if (nu > 8.0) return sigma_a * sigma_a * (1.0 - 1.0 / (nu * nu));
  const double m = chi3_mean(nu);
  return sigma_a * sigma_a * std::max(3.0 + nu * nu - m * m, 0.0);
}

double magnitude_from_mean(double mean_a, double sigma_a) {
  if (!(sigma_a > 0.0)) return std::max(mean_a, 0.0);
  const double target = mean_a / sigma_a;
  if (!(target > chi3_mean(0.0))) return 0.0;
  // M is increasing with ν <= M(ν) <= ν + M(0): the root lies in [target − M(0), target].
  double lo = std::max(target - chi3_mean(0.0), 0.0), hi = target;
  for (int i = 0; i < 200 && hi - lo > 1e-14 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (chi3_mean(mid) < target ? lo : hi) = mid;
  }
  return sigma_a * 0.5 * (lo + hi);
}

MagnitudeBias magnitude_bias(double mean_a, double sigma_a) {
  MagnitudeBias out;
  if (!(sigma_a > 0.0)) return out;
  const double a = magnitude_from_mean(mean_a, sigma_a);
  out.bias_a = mean_a - a;
  if (!(a > 0.0)) {
    out.d_mean = 1.0;
    return out;
  }
  const double nu = a / sigma_a;
  if (nu > 8.0) {  // M = ν + 1/ν, M' = 1 − 1/ν² exactly in double (see magnitude_variance)
    out.d_mean = -1.0 / (nu * nu - 1.0);
    out.d_sigma = 2.0 * nu / (nu * nu - 1.0);
    return out;
  }
  const double dm = (1.0 - 1.0 / (nu * nu)) * std::erf(nu * M_SQRT1_2) +
                    kSqrt2OverPi * std::exp(-0.5 * nu * nu) / nu;  // M'(ν) > 0
  out.d_mean = 1.0 - 1.0 / dm;
  out.d_sigma = chi3_mean(nu) / dm - nu;
  return out;
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
