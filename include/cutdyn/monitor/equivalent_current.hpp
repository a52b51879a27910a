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

/// Standard deviation of the equivalent current caused by independent white noise of standard
/// deviation `phase_sigma_a` on each phase (first order): σ/√3 (kRms), σ·√(2/3) (kSpaceVector).
double equivalent_current_sigma(double phase_sigma_a, CurrentMeasure measure);

/// "rms" or "space-vector".
std::string_view to_string(CurrentMeasure measure);
/// The measure named "rms" or "space-vector"; nullopt for anything else.
std::optional<CurrentMeasure> parse_current_measure(std::string_view name);

}  // namespace cutdyn
