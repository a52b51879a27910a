// Equivalent current of a three-phase servo motor [Zheng2012, eq. 1]; docs/models/monitor.md §1.
#pragma once

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
double equivalent_current(double iu, double iv, double iw, CurrentMeasure measure);

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

/// "rms" or "space-vector".
std::string_view to_string(CurrentMeasure measure);
/// The measure named "rms" or "space-vector"; nullopt for anything else.
std::optional<CurrentMeasure> parse_current_measure(std::string_view name);

}  // namespace cutdyn
