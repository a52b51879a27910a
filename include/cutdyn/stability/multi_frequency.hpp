// Frequency-domain stability of the periodic delayed system (delayed_system.hpp): the
// multi-frequency (Hill) solution and, with no harmonics, the averaged (zero-order) one
// [Budak1998; Merdol2004]; docs/models/milling-stability.md.
//
// A solution on the boundary is y(t) = Σp Yp·exp(i(ω + pΩ)t), Ω = 2π/T. Substituting in the
// system gives, for the harmonics p, q of a window,
//     Yp = w · G(ω + pΩ) · Σq H(p−q) · (exp(−i(ω + qΩ)τ) − 1) · Yq,
// so w = 1/λ for every real positive eigenvalue λ of the matrix
//     K(ω) = [ G(ω + pΩ) · H(p−q) · (exp(−i(ω + qΩ)τ) − 1) ]pq .
// P = 0 keeps only the mean coefficient H0 (the averaged theory: for vibration-assisted
// cutting K_t → r·K_t). Otherwise chatter frequencies ω are scanned over [0, Ω/2] (every
// other frequency is a shift or a mirror of these) with the window p = −P−1..P, which at
// ω = Ω/2 is symmetric about zero frequency: there K is similar to its complex conjugate and
// a flip (period-doubling) boundary is a real eigenvalue at the end of the scan, taken
// directly. The window must reach every frequency at which the structure responds — a mode
// outside it is simply not seen, and the method then calls unstable speeds stable — so P is
// raised from the requested value until the window covers the response band
// and, beyond it, the spread of the shortest contact pulse's spectrum
// (multi_frequency_harmonics). With a constant
// coefficient the scan covers every frequency at which the structure can respond enough to reach
// the depth limit.
#pragma once

#include <string>
#include <vector>

#include "cutdyn/stability/critical_depth.hpp"
#include "cutdyn/stability/delayed_system.hpp"
#include "cutdyn/stability/method.hpp"

namespace cutdyn {

struct MultiFrequencyOptions {
  /// P, harmonics of Ω = 2π/T kept each side. 0: the averaged (zero-order) solution.
  /// Otherwise the least P: more are used where the structure responds beyond (P + ½)·Ω,
  /// unless `exact_harmonics` (for truncation studies).
  int harmonics = 5;
  bool exact_harmonics = false;
  /// Upper bound on the raised P (the matrix has r·(2P + 2) rows). Where the response band
  /// needs more, the result is marked CriticalDepth::truncated.
  int max_harmonics = 150;
  double depth_max_m = 0.03;     // search limit
  double samples_per_turn = 16;  // frequency samples per 2π of delay phase
  /// Every eigenvalue of K by the dense Schur decomposition (the method before 2026-12-02, for
  /// comparisons), not only those that can reach 1/depth_max by Arnoldi's method.
  bool dense_eigenvalues = false;
  /// Frequency samples at equal steps set by the sharpest mode everywhere (the method before
  /// 2026-12-02 evening, for comparisons), instead of steps that widen away from the resonances.
  bool uniform_step = false;

  std::vector<std::string> validate() const;
};

/// Throws cutdyn::InvalidInput if the system or the options are invalid.

CriticalDepth multi_frequency_critical_depth(const DelayedSystem& system,
                                             const MultiFrequencyOptions& options);

/// The harmonics P the method uses for `system`: `harmonics`, raised (unless exact) to the
/// harmonics that reach response_band_rad_s plus 1.5 times the period over the shortest
/// contact pulse or gap of H(t) (the spread of the pulse's spectrum); at most max_harmonics. 0 for
/// a constant coefficient. `truncated` (if given) is set when the band needs more than
/// max_harmonics.
int multi_frequency_harmonics(const DelayedSystem& system, const MultiFrequencyOptions& options,
                              bool* truncated = nullptr);

/// The band a harmonic window must cover (rad/s): up to the frequency at which every mode's
/// response has fallen to 5 % of its resonance peak, ωn·sqrt(1 + 40ζ) for the highest.
double response_band_rad_s(const DelayedSystem& system);

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
