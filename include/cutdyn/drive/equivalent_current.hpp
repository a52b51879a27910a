// Equivalent current of a three-phase servo motor [Zheng2012, eq. 1]; docs/models/monitor.md §1.
// The drive owns it (the motor's currents are made for a measure, motor_currents.hpp); the
// monitor, which builds on the drive, reads the currents through it.
#pragma once

#include <cmath>
#include <optional>
#include <string_view>

namespace cutdyn {

/// Which scalar stands for the three phase currents. The motor's torque constant KT must be
/// given for the same measure.
enum class CurrentMeasure {
  kRms,          // sqrt((iu² + iv² + iw²)/3), the source's eq. 1
  kSpaceVector,  // sqrt(2/3·(iu² + iv² + iw²)): the peak of balanced sinusoidal currents
};

/// [Zheng2012, eq. 1] kRms: sqrt((iu²+iv²+iw²)/3); kSpaceVector: sqrt(2/3·(iu²+iv²+iw²))
/// (= the peak of balanced sinusoidal currents, = |i_q| of a field-oriented PMSM). Amperes.
/// Inline: it runs once per sample in the estimator.
inline double equivalent_current(double iu, double iv, double iw, CurrentMeasure measure) {
  const double sum = iu * iu + iv * iv + iw * iw;
  return std::sqrt(sum * (measure == CurrentMeasure::kRms ? 1.0 / 3.0 : 2.0 / 3.0));
}

/// The SIGNED equivalent current from the phase currents and the electrical rotor angle θe
/// (rad), for the convention of the drive library (cutdyn/drive/motor_currents.hpp):
///   iu = −Î·sin θe,  iv = −Î·sin(θe − 2π/3),  iw = −Î·sin(θe + 2π/3),  Î signed like the torque.
/// The Park transform's q component Î = −(2/3)·(iu·sin θe + iv·sin(θe − 2π/3) + iw·sin(θe + 2π/3)),
/// returned as I = Î (kSpaceVector) or Î/√2 (kRms): for balanced currents |I| equals
/// equivalent_current(), and its sign is the torque's. White noise σ per phase scatters it by
/// equivalent_current_sigma(σ) (exactly, for any angle), with no bias.
double signed_equivalent_current(double iu, double iv, double iw, double rotor_angle_rad,
                                 CurrentMeasure measure);

/// Standard deviation of the equivalent current caused by independent white noise of standard
/// deviation `phase_sigma_a` on each phase (first order): σ/√3 (kRms), σ·√(2/3) (kSpaceVector).
double equivalent_current_sigma(double phase_sigma_a, CurrentMeasure measure);

/// The mean of a magnitude under noise: with independent white noise on each of the three
/// phases, the equivalent current of a true (constant) current `true_a` scatters as σ times
/// a noncentral χ with 3 degrees of freedom, σ = equivalent_current_sigma() (docs/models/
/// monitor.md §1), so its mean is σ·M(a/σ) with
///   M(ν) = sqrt(2/π)·exp(−ν²/2) + (ν + 1/ν)·erf(ν/√2),   M(0) = 2·sqrt(2/π) ≈ 1.596,
/// M(ν) ≈ ν + 1/ν for large ν. Amperes; σ = 0 gives `true_a`.
double magnitude_mean(double true_a, double sigma_a);
/// The variance of that magnitude: σ²·(3 + ν² − M(ν)²) (3 − 8/π at ν = 0, → σ² for large ν).
double magnitude_variance(double true_a, double sigma_a);
/// The inverse of magnitude_mean: the true current whose noisy magnitude has mean `mean_a`;
/// 0 where `mean_a` <= σ·M(0) (a mean no larger than the noise alone gives). Amperes.
double magnitude_from_mean(double mean_a, double sigma_a);

/// The noise bias b = m − magnitude_from_mean(m, σ) of a mean magnitude m, and its
/// derivatives: ∂b/∂m = 1 − 1/M'(ν) and ∂b/∂σ = M(ν)/M'(ν) − ν at ν = magnitude_from_mean/σ
/// (b = m, ∂b/∂m = 1, ∂b/∂σ = 0 where m <= σ·M(0)); b ≈ σ²/a for a large ν.
struct MagnitudeBias {
  double bias_a = 0.0, d_mean = 0.0, d_sigma = 0.0;
};
MagnitudeBias magnitude_bias(double mean_a, double sigma_a);

/// "rms" or "space-vector".
std::string_view to_string(CurrentMeasure measure);
/// The measure named "rms" or "space-vector"; nullopt for anything else.
std::optional<CurrentMeasure> parse_current_measure(std::string_view name);

}  // namespace cutdyn
