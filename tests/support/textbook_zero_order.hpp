// The zero-order (averaged) milling lobes the way the literature computes them from an FRF
// [Altintas1995]: a sweep of the chatter frequency over the measured table's points, each
// giving one (speed, depth) point per lobe; the lowest lobe at each speed by interpolation.
// A second method for the scan of stability/multi_frequency (tests and bench/).
#pragma once

#include <Eigen/Eigenvalues>
#include <cmath>
#include <complex>
#include <limits>
#include <vector>

#include "cutdyn/core/units.hpp"
#include "cutdyn/stability/milling.hpp"

namespace cutdyn::testing {

// Depth (m) at each of `rpm` (infinity where no lobe reaches), for a process with a measured
// x table (its frequencies are the sweep's) and even pitch, straight teeth.
// The textbook sweep. The averaged system is det(I + a·(1 − e^(−iωτ))·G(ω)·H0) = 0 with H0
// the mean of H over a tooth period (per unit depth); for an eigenvalue λ of G(ωc)·H0,
// μ = −1/λ = a·(1 − e^(−iθ)) gives cot(θ/2) = Im μ / Re μ and a = |μ|²/(2 Re μ) (Re μ > 0),
// and τ = (θ + 2πk)/ωc for lobe k.
inline std::vector<double> textbook_zero_order_lobes(const MillingProcess& p,
                                                     const std::vector<double>& rpm) {
  const DelayedSystem s = milling_system(p, 10000.0);
  const Eigen::Matrix2cd h0 = s.H.fourier(0);
  const std::vector<double>& frequencies = p.measured->xx->frequency_hz;
  const int z = p.tool.teeth;
  std::vector<double> best(rpm.size(), std::numeric_limits<double>::infinity());
  // Per lobe, consecutive frequency points give a segment of the curve (rpm, a): the grid
  // speeds inside it take the interpolated depth.
  for (int k = 0; k < 40; ++k) {
    double prev_rpm = 0.0, prev_a = 0.0;
    bool have_prev = false;
    for (std::size_t i = 0; i < frequencies.size(); ++i) {
      const double f = frequencies[i];
      const double w = units::hz_to_rad_per_s(f);
      const Eigen::Matrix2cd g = s.frequency_response(w);
      const Eigen::Vector2cd lambda = (g * h0).eigenvalues();
      double a = std::numeric_limits<double>::infinity(), speed = 0.0;
      for (Eigen::Index j = 0; j < 2; ++j) {
        const std::complex<double> mu = -1.0 / lambda(j);
        if (!(mu.real() > 0.0)) continue;
        const double depth = std::norm(mu) / (2.0 * mu.real());
        if (depth >= a) continue;
        // μ = a·(1 − e^(−iθ)) = 2a·sin(θ/2)·(sin(θ/2) + i·cos(θ/2)), θ/2 in (0, π).
        const double theta = 2.0 * std::atan2(mu.real(), mu.imag());
        a = depth;
        speed = 60.0 / (z * (theta + units::kTwoPi * k) / w);
      }
      const bool have = std::isfinite(a);
      if (have && have_prev) {
        const double lo = std::min(prev_rpm, speed), hi = std::max(prev_rpm, speed);
        for (std::size_t n = 0; n < rpm.size(); ++n) {
          if (rpm[n] < lo || rpm[n] > hi || hi == lo) continue;
          const double t = (rpm[n] - prev_rpm) / (speed - prev_rpm);
          best[n] = std::min(best[n], prev_a + t * (a - prev_a));
        }
      }
      prev_rpm = speed;
      prev_a = a;
      have_prev = have;
    }
  }
  return best;
}

}  // namespace cutdyn::testing
