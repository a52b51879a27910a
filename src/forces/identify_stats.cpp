// Student's t quantile for the identification's confidence intervals.
#include <cassert>
#include <cmath>

#include "cutdyn/core/detail/roots.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/forces/identify.hpp"

namespace cutdyn {
namespace {

// A(t|ν) = P(|T| < t) as a function of θ = atan(t/√ν), for whole ν >= 1 [Abramowitz1964,
// 26.7.3 (ν odd) and 26.7.4 (ν even)]:
//   ν odd:  A = (2/π)·(θ + sinθ·(cosθ + (2/3)cos³θ + … + (2·4···(ν−3))/(1·3···(ν−2))·cos^(ν−2)θ)),
//           the sum empty for ν = 1;
//   ν even: A = sinθ·(1 + (1/2)cos²θ + (1·3)/(2·4)cos⁴θ + … +
//   (1·3···(ν−3))/(2·4···(ν−2))·cos^(ν−2)θ).
double two_sided_probability(double theta, int dof) {
  const double s = std::sin(theta), c = std::cos(theta), c2 = c * c;
  if (dof % 2 == 1) {
    double sum = 0.0, term = c;
    for (int j = 0; 2 * j + 1 <= dof - 2; ++j) {
      if (j > 0) term *= c2 * (2.0 * j) / (2.0 * j + 1.0);
      sum += term;
    }
    return 2.0 / units::kPi * (theta + s * sum);
  }
  double sum = 0.0, term = 1.0;
  for (int j = 0; 2 * j <= dof - 2; ++j) {
    if (j > 0) term *= c2 * (2.0 * j - 1.0) / (2.0 * j);
    sum += term;
  }
  return s * sum;
}

}  // namespace

double student_t_quantile(double p, int dof) {
  assert(dof >= 1 && p > 0.0 && p < 1.0);
  if (p == 0.5) return 0.0;
  const double target = std::abs(2.0 * p - 1.0);  // A(|t|)
  // A rises from 0 at θ = 0 to 1 at θ = π/2: one root.
  const auto r =
      brent_root([&](double theta) { return two_sided_probability(theta, dof) - target; }, 0.0,
                 -target, 0.5 * units::kPi, 1.0 - target, 1e-15, 400);
  assert(r);
  const double t = std::sqrt(static_cast<double>(dof)) * std::tan(r->x);
  return p > 0.5 ? t : -t;
}

}  // namespace cutdyn
