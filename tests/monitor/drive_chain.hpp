// Current logs from the drive library for the monitor tests: a simulated milling cut
// (docs/models/milling-simulation.md), the feed drive of one axis under it (PI speed loop), and the
// motor's phase currents (motor_currents), with the electrical rotor angle the currents were made
// with.
#pragma once

#include <cmath>
#include <random>
#include <vector>

#include "cutdyn/core/units.hpp"
#include "cutdyn/drive/feed_drive.hpp"
#include "cutdyn/drive/motor_currents.hpp"
#include "cutdyn/monitor/calibration.hpp"
#include "cutdyn/simulate/milling_simulation.hpp"

namespace cutdyn::testing {

struct DriveAxisParameters {
  double inertia_kg_m2 = 0.017, viscous = 0.2103, friction_nm = 15.60, force_gain_m = 0.00632,
         torque_constant = 1.621;
  CurrentMeasure measure = CurrentMeasure::kRms;
  double loop_hz = 500.0;  // PI speed loop: Kp = 2π·loop_hz·J, Ki = Kp·2π·loop_hz/4
  double noise_a = 0.0;    // per phase
  unsigned seed = 1;
};

/// A light axis like ermolaev2020's x: Tnzm 0.05 N·m, X 0.002 N·m·s/rad, KBlf 2 mm, J 0.001
/// kg·m², KT 1.621 N·m/A (rms): idle its current (0.03–0.04 A) is at or below the noise.
inline DriveAxisParameters light_axis() {
  DriveAxisParameters p;
  p.inertia_kg_m2 = 0.001;
  p.viscous = 0.002;
  p.friction_nm = 0.05;
  p.force_gain_m = 0.002;
  return p;
}

inline FeedAxis drive_axis(const DriveAxisParameters& p) {
  FeedAxis a;
  a.name = "x";
  Transmission& t = a.drive.transmission;
  t.kind = Transmission::Kind::kLeverArm;
  t.output_diameter_m = 2 * p.force_gain_m / 0.1;
  t.ratio = 0.1;
  t.idle_torque_nm = p.friction_nm;
  a.drive.model = FeedDrive::Model::kDynamic;
  a.drive.inertia_kg_m2 = p.inertia_kg_m2;
  a.drive.viscous_nm_s_per_rad = p.viscous;
  a.drive.kp_nm_s_per_rad = units::kTwoPi * p.loop_hz * p.inertia_kg_m2;
  a.drive.ki_nm_per_rad = a.drive.kp_nm_s_per_rad * units::kTwoPi * p.loop_hz / 4.0;
  PmsmMotor m;
  m.pole_pairs = 4;
  m.torque_constant_nm_per_a = p.torque_constant;
  m.measure = p.measure;
  m.noise_a = p.noise_a;
  m.seed = p.seed;
  a.motor = m;
  return a;
}

inline AxisModel drive_axis_model(const DriveAxisParameters& p) {
  return {p.inertia_kg_m2, p.torque_constant, p.viscous, p.friction_nm, p.force_gain_m, p.measure};
}

/// 4 teeth, Ø50 mm, 30° helix, a/D = 0.5, 0.25 mm/tooth, B = 4 mm, Kt = 2000 N/mm², Kr = 600
/// N/mm²; up-milling (entry 0, exit 90°) or down-milling (entry 90°, exit 180°).
inline MillingSimulationResult milling_cut(double rpm, bool down, int revolutions,
                                           double& feed_m_per_s) {
  MillingCut cut;
  cut.process.tool.teeth = 4;
  cut.process.tool.diameter_m = 0.05;
  cut.process.tool.helix_rad = units::deg_to_rad(30.0);
  cut.process.engagement.entry_rad = down ? 0.5 * units::kPi : 0.0;
  cut.process.engagement.exit_rad = down ? units::kPi : 0.5 * units::kPi;
  cut.spindle_rad_s = units::rpm_to_rad_per_s(rpm);
  cut.feed_per_tooth_m = 0.25e-3;
  cut.width_m = 4e-3;
  cut.process.cutting = MechanisticForceLaw{2e9, 6e8, 0.0, 0.0};
  cut.regenerative = false;
  MillingSimulationOptions so;
  so.revolutions = revolutions;
  so.summary_revolutions = 1;
  so.steps_per_tooth = 50;
  so.max_recorded_samples = 1000000;
  feed_m_per_s = cut.feed_per_tooth_m * cut.process.tool.teeth * cut.spindle_rad_s / units::kTwoPi;
  return simulate_milling(cut, so);
}

/// The log of the drive under the cut's x force: phase currents (with the motor's noise),
/// the true speed, the axis force Fn (resistance to the +x feed) as force_n, and the
/// electrical angle θe = p·θm, θm the trapezoidal integral of the speed from 0 (as
/// motor_currents makes it).
inline AxisRun drive_log(const DriveAxisParameters& p, const MillingSimulationResult& sim,
                         double feed_m_per_s) {
  const FeedAxis axis = drive_axis(p);
  const std::vector<double> zero(sim.fx_n.size(), 0.0);
  const FeedDriveResult d =
      simulate_feed_drive(axis, sim.time_s, sim.fx_n, zero, zero, feed_m_per_s);
  const PhaseCurrents c = motor_currents(*axis.motor, sim.time_s, d.motor_torque_nm, d.speed_rad_s);
  AxisRun run;
  double angle = 0.0;
  for (std::size_t i = 0; i < sim.time_s.size(); ++i) {
    if (i > 0)
      angle +=
          0.5 * (d.speed_rad_s[i] + d.speed_rad_s[i - 1]) * (sim.time_s[i] - sim.time_s[i - 1]);
    AxisSample s;
    s.time_s = sim.time_s[i];
    s.iu_a = c.iu_a[i];
    s.iv_a = c.iv_a[i];
    s.iw_a = c.iw_a[i];
    s.speed_rad_s = d.speed_rad_s[i];
    s.force_n = -sim.fx_n[i];
    s.has_rotor_angle = true;
    s.rotor_angle_rad = std::fmod(4.0 * angle, units::kTwoPi);
    run.push_back(s);
  }
  return run;
}

/// The drive's traces under an axis force trace Fn(t) (resistance to the motion) at motor
/// speed `omega` (either sign: a negative speed runs the mirror image of the axis, as
/// tests/drive/end_to_end_test.cpp does), before noise.
struct DriveTraces {
  std::vector<double> time_s, torque_nm, speed_rad_s, force_n;
};
inline DriveTraces drive_traces(const DriveAxisParameters& p, const std::vector<double>& t,
                                const std::vector<double>& fn, double omega) {
  FeedAxis axis = drive_axis(p);
  double v = omega * p.force_gain_m;
  if (omega < 0) {
    for (double& d : axis.direction) d = -d;
    v = -v;
  }
  std::vector<double> fx(fn.size()), zero(fn.size(), 0.0);
  for (std::size_t i = 0; i < fn.size(); ++i) fx[i] = omega < 0 ? fn[i] : -fn[i];
  const FeedDriveResult d = simulate_feed_drive(axis, t, fx, zero, zero, v);
  DriveTraces out{t, d.motor_torque_nm, d.speed_rad_s, fn};
  if (omega < 0)
    for (double& w : out.speed_rad_s) w = -w;
  return out;
}

/// A noisy log of the traces: phase currents (noise σ per phase, `seed`) with the magnitude
/// of the torque (no rotor angle in the log), the speed with white noise σ_ω.
inline AxisRun noisy_log(const DriveAxisParameters& p, const DriveTraces& d, double speed_noise,
                         unsigned seed) {
  FeedAxis axis = drive_axis(p);
  PmsmMotor m = *axis.motor;
  m.seed = seed;
  std::vector<double> speed_abs(d.speed_rad_s.size());
  for (std::size_t i = 0; i < speed_abs.size(); ++i) speed_abs[i] = std::abs(d.speed_rad_s[i]);
  const PhaseCurrents c = motor_currents(m, d.time_s, d.torque_nm, speed_abs);
  std::mt19937_64 rng(seed * 7919u + 13u);
  std::normal_distribution<double> g(0.0, 1.0);
  AxisRun run;
  for (std::size_t i = 0; i < d.time_s.size(); ++i) {
    AxisSample s;
    s.time_s = d.time_s[i];
    s.iu_a = c.iu_a[i];
    s.iv_a = c.iv_a[i];
    s.iw_a = c.iw_a[i];
    s.speed_rad_s = d.speed_rad_s[i] + speed_noise * g(rng);
    s.force_n = d.force_n[i];
    run.push_back(s);
  }
  return run;
}

}  // namespace cutdyn::testing
