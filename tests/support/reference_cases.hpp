// Reference problems with known answers, shared by the tests.
#pragma once

#include <algorithm>
#include <cmath>

#include "cutdyn/core/units.hpp"
#include "cutdyn/modal/modal_model.hpp"
#include "cutdyn/simulate/milling_simulation.hpp"
#include "cutdyn/stability/full_discretization.hpp"
#include "cutdyn/stability/milling.hpp"
#include "cutdyn/stability/turning.hpp"

namespace cutdyn::testing {

/// The grid on which a search with `fd` (FdOptions::refinements > 0) confirmed a boundary at
/// `depth_m`: sized by the cut at that depth, the step halved. A test that checks the answer
/// is a crossing (stable just below, unstable just above) checks it there.
inline FdOptions confirming_grid(FdOptions fd, double depth_m) {
  fd.cutting_depth_m = std::max(fd.cutting_depth_m, depth_m);
  fd.max_step_fraction *= 0.5;
  fd.window_steps *= 2;
  fd.refinements = 0;
  return fd;
}

// [Chikishev2018, table 2]: one tool mode in the feed direction.
inline constexpr double kTable2NaturalHz = 228.8;
inline constexpr double kTable2Stiffness = 2.26e8;  // N/m
inline constexpr double kTable2Damping = 0.01;
inline constexpr double kTable2Kt = 850e6;  // N/m²
inline constexpr double kTable2DutyCycle = 0.6;

inline TurningProcess table2_conventional() {
  TurningProcess m;
  m.modal.modes.push_back(Mode{Direction::kX, units::hz_to_rad_per_s(kTable2NaturalHz),
                               kTable2Damping, kTable2Stiffness});
  m.kf_pa = kTable2Kt;
  return m;
}

/// The same with ultrasonic vibration at `frequency_hz` and the fixed duty cycle r = 0.6.
inline TurningProcess table2_vibration(double frequency_hz = 20000.0) {
  TurningProcess m = table2_conventional();
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

// The Insperger–Stépán milling benchmark [Insperger & Stépán 2004; Ding et al. 2010]: two
// straight teeth, Kt = 6e8 N/m², Kr = 2e8 N/m², one mode of 922 Hz, ζ = 0.011, modal mass
// 0.03993 kg in x (and in y unless one_direction), diameter 20 mm.
inline constexpr double kInspergerHz = 922.0;
inline constexpr double kInspergerDamping = 0.011;
inline constexpr double kInspergerMassKg = 0.03993;

inline MillingProcess insperger_benchmark(double immersion, bool both_directions = true,
                                          bool down_milling = true) {
  MillingProcess m;
  const double wn = units::hz_to_rad_per_s(kInspergerHz);
  m.modal.modes.push_back(mode_from_mass(Direction::kX, wn, kInspergerDamping, kInspergerMassKg));
  if (both_directions)
    m.modal.modes.push_back(mode_from_mass(Direction::kY, wn, kInspergerDamping, kInspergerMassKg));
  m.cutting.kt_pa = 6e8;
  m.cutting.kr_pa = 2e8;
  m.tool.teeth = 2;
  m.tool.diameter_m = 0.02;
  m.engagement.radial_immersion = immersion;
  m.engagement.down_milling = down_milling;
  return m;
}

// A four-mode milling structure (two modes per direction, the upper ones well above the
// tooth-passing frequencies of 2000–16 000 rpm): Kt = 1300 N/mm², Kr = 780 N/mm², two straight
// teeth, D 30 mm, a_e/D = 0.5, down-milling. With a fixed window of 5 harmonics the
// multi-frequency method did not see the upper modes at low speed.
inline MillingProcess four_mode_milling(double immersion = 0.5, bool down_milling = true) {
  MillingProcess m;
  const auto mode = [](Direction d, double hz, double zeta, double k) {
    return Mode{d, units::hz_to_rad_per_s(hz), zeta, k};
  };
  m.modal.modes = {
      mode(Direction::kX, 480.0, 0.09, 8.0e6), mode(Direction::kX, 1500.0, 0.02, 1.5e7),
      mode(Direction::kY, 530.0, 0.03, 9.0e6), mode(Direction::kY, 1420.0, 0.03, 1.2e7)};
  m.cutting.kt_pa = 1300e6;
  m.cutting.kr_pa = 780e6;
  m.tool.teeth = 2;
  m.tool.diameter_m = 0.03;
  m.engagement.radial_immersion = immersion;
  m.engagement.down_milling = down_milling;
  return m;
}

// H(t) straight from the force model: Σ over teeth in cut of −(Kt/2)·A(φj), tooth j at
// Ωs·t + 2πj/z (even pitch), or trailing tooth 0 by pitch_1 + ... + pitch_j, all lagging by
// `lag_rad` (a slice of a helical flute).
inline Eigen::Matrix2d direct_milling_h(const MillingProcess& m, double rpm, double t,
                                        double lag_rad = 0.0) {
  const double spindle = units::rpm_to_rad_per_s(rpm);
  const std::vector<double> pitch = m.tool.pitch_angles();
  Eigen::Matrix2d h = Eigen::Matrix2d::Zero();
  double behind = 0.0;
  for (int j = 0; j < m.tool.teeth; ++j) {
    if (j > 0) behind += pitch[static_cast<std::size_t>(j)];
    double phi = std::fmod(spindle * t - behind - lag_rad, units::kTwoPi);
    if (phi < 0.0) phi += units::kTwoPi;
    if (phi > m.engagement.entry_angle() && phi < m.engagement.exit_angle())
      h += -0.5 * m.cutting.kt_pa *
           milling_directional_matrix(phi, m.cutting.kr_pa / m.cutting.kt_pa);
  }
  return h;
}

// The time-domain simulation of the cut `m` at `rpm` and depth `width_m` (0.05 mm per tooth,
// the mechanistic law of the model without edge terms): the stability model's cut, integrated.
inline MillingSimulationResult simulate_model(const MillingProcess& m, double rpm, double width_m,
                                              const MillingSimulationOptions& options = {}) {
  MillingCut c;
  c.process = m;
  c.process.cutting.kte_n_per_m = c.process.cutting.kre_n_per_m = 0.0;
  c.spindle_rad_s = units::rpm_to_rad_per_s(rpm);
  c.feed_per_tooth_m = 0.05e-3;
  c.width_m = width_m;
  return simulate_milling(c, options);
}

}  // namespace cutdyn::testing
