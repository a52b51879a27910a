// Reference problems with known answers, shared by the tests.
#pragma once

#include <cmath>

#include "cutdyn/core/units.hpp"
#include "cutdyn/modal/modal_model.hpp"
#include "cutdyn/stability/turning.hpp"

namespace cutdyn::testing {

// [Chikishev2018, table 2]: one tool mode in the feed direction.
inline constexpr double kTable2NaturalHz = 228.8;
inline constexpr double kTable2Stiffness = 2.26e8;  // N/m
inline constexpr double kTable2Damping = 0.01;
inline constexpr double kTable2Kt = 850e6;  // N/m²
inline constexpr double kTable2DutyCycle = 0.6;

inline TurningModel table2_conventional() {
  TurningModel m;
  m.modal.modes.push_back(Mode{Direction::kX, units::hz_to_rad_per_s(kTable2NaturalHz),
                               kTable2Damping, kTable2Stiffness});
  m.kt_pa = kTable2Kt;
  return m;
}

/// The same with ultrasonic vibration at `frequency_hz` and the fixed duty cycle r = 0.6.
inline TurningModel table2_vibration(double frequency_hz = 20000.0) {
  TurningModel m = table2_conventional();
  VibrationAssist v;
  v.frequency_hz = frequency_hz;
  v.duty_cycle = kTable2DutyCycle;
  m.vibration = v;
  return m;
}

/// Smallest critical depth of a one-mode structure over all speeds (closed form):
/// a_min = 2ζ(1 + ζ)k / Kt, at chatter frequency ωn·sqrt(1 + 2ζ) [Altintas2012, eq. 3.40].
inline double table2_absolute_minimum_depth(double kt = kTable2Kt) {
  return 2.0 * kTable2Damping * (1.0 + kTable2Damping) * kTable2Stiffness / kt;
}

}  // namespace cutdyn::testing
