// Frequency-domain stability of the periodic delayed system (delayed_system.hpp): the
// multi-frequency (Hill) solution and, with no harmonics, the averaged (zero-order) one
// [Budak & Altintas 1998; Merdol & Altintas 2004]; docs/models/turning.md §4.
//
// A solution on the boundary is y(t) = Σp Yp·exp(i(ω + pΩ)t), Ω = 2π/T. Substituting in the
// system gives, for the harmonics p, q = −P..P,
//     Yp = w · G(ω + pΩ) · Σq H(p−q) · (exp(−i(ω + qΩ)τ) − 1) · Yq,
// so w = 1/λ for every real positive eigenvalue λ of the r(2P+1)-square matrix
//     K(ω) = [ G(ω + pΩ) · H(p−q) · (exp(−i(ω + qΩ)τ) − 1) ]pq .
// P = 0 keeps only the mean coefficient H0 (the averaged theory: for vibration-assisted
// cutting K_t → r·K_t). Chatter frequencies are scanned over [0, Ω/2] (every other
// frequency is a shift or a mirror of these) or, with P = 0 or a constant coefficient, over
// every frequency at which the structure can respond enough to reach the depth limit.
#pragma once

#include <string>
#include <vector>

#include "cutdyn/stability/critical_depth.hpp"
#include "cutdyn/stability/delayed_system.hpp"

namespace cutdyn {

struct MultiFrequencyOptions {
  int harmonics = 5;             // P; 0 = averaged
  double depth_max_m = 0.03;     // search limit
  double samples_per_turn = 16;  // frequency samples per 2π of delay phase

  std::vector<std::string> validate() const;
};

/// Throws cutdyn::InvalidInput if the system or the options are invalid.

CriticalDepth multi_frequency_critical_depth(const DelayedSystem& system,
                                             const MultiFrequencyOptions& options);

/// Frequency above which no eigenvalue of K can reach 1/depth_max: the structure's response
/// times twice the largest coefficient is too small there.
double response_limit_rad_s(const DelayedSystem& system, double coefficient_norm,
                            double depth_max_m);

/// Throws cutdyn::InvalidInput (where = "stability analysis") listing the system's and the
/// options' problems, if any.
void require_valid(const DelayedSystem& system, const std::vector<std::string>& option_problems);

/// min over the structure's poles of −Re(pole): the half-bandwidth of the sharpest
/// resonance (rad/s), which sets how finely a frequency or multiplier grid must sample.
double sharpest_half_bandwidth(const DelayedSystem& system);

}  // namespace cutdyn
