// Calibration steps 1 and 2 [Zheng2012, eq. 5] on synthetic logs with known parameters.
#include "cutdyn/monitor/calibration.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "monitor/synthetic_logs.hpp"

namespace cutdyn {
namespace {

using testing::idle_profile;
using testing::loaded_profile;
using testing::LogNoise;
using testing::servo_run;
using testing::synthetic_run;

TEST(MonitorCalibration, RecoversPresetFromNoiseFreeLogs) {
  // Required: within 1 %. Noise-free, steady windows are exact, so ask for 1e-6.
  for (char axis : {'x', 'y', 'z'}) {
    const AxisModel truth = zheng2012_axis(axis);
    AxisModel given = truth;  // J, KT and the measure are given; the rest is fitted
    given.friction_nm = given.viscous_nm_s_per_rad = given.force_gain_m = 0.0;
    const IdleFit idle = fit_idle(given, {synthetic_run(truth, idle_profile())});
    ASSERT_EQ(idle.report.status, CalibrationStatus::kSuccess) << idle.report.message;
    EXPECT_NEAR(idle.friction_nm / truth.friction_nm, 1.0, 1e-6) << axis;
    EXPECT_NEAR(idle.viscous_nm_s_per_rad / truth.viscous_nm_s_per_rad, 1.0, 1e-6) << axis;
    EXPECT_EQ(idle.report.distinct_speeds, 5);
    EXPECT_GT(idle.report.windows_rejected, 5);  // the ramps and their edges
    EXPECT_GT(idle.report.r_squared, 1.0 - 1e-12);

    AxisCalibration cal;
    cal.model = given;
    cal.model.friction_nm = idle.friction_nm;
    cal.model.viscous_nm_s_per_rad = idle.viscous_nm_s_per_rad;
    const LoadFit load = fit_load(cal, {synthetic_run(truth, loaded_profile())});
    ASSERT_EQ(load.report.status, CalibrationStatus::kSuccess) << load.report.message;
    EXPECT_NEAR(load.force_gain_m / truth.force_gain_m, 1.0, 1e-6) << axis;
  }
}

TEST(MonitorCalibration, SpaceVectorMeasure) {
  AxisModel truth = zheng2012_axis('x');
  truth.measure = CurrentMeasure::kSpaceVector;
  truth.torque_constant_nm_per_a = 1.621 / std::sqrt(2.0);
  const IdleFit idle = fit_idle(truth, {synthetic_run(truth, idle_profile())});
  EXPECT_NEAR(idle.friction_nm, truth.friction_nm, 1e-6 * truth.friction_nm);
  // The same logs read with the wrong measure give a friction off by √2.
  AxisModel wrong = truth;
  wrong.measure = CurrentMeasure::kRms;
  const IdleFit off = fit_idle(wrong, {synthetic_run(truth, idle_profile())});
  EXPECT_NEAR(off.friction_nm / truth.friction_nm, 1.0 / std::sqrt(2.0), 1e-6);
}

struct NoisyFit {
  IdleFit idle;
  LoadFit load;
};

NoisyFit noisy_fit(const AxisModel& truth, double hold_s, unsigned seed) {
  const LogNoise noise{0.1, 0.2};  // 0.1 A per phase (1 % of ~10 A), 0.2 rad/s
  NoisyFit f;
  f.idle = fit_idle(truth, {synthetic_run(truth, idle_profile(hold_s), 1e-3, noise, seed)});
  AxisCalibration cal;
  cal.model = truth;
  cal.model.friction_nm = f.idle.friction_nm;
  cal.model.viscous_nm_s_per_rad = f.idle.viscous_nm_s_per_rad;
  cal.sigma.friction_nm = f.idle.friction_sigma_nm;
  cal.sigma.viscous_nm_s_per_rad = f.idle.viscous_sigma;
  cal.sigma.friction_viscous_covariance = f.idle.covariance;
  f.load = fit_load(cal, {synthetic_run(truth, loaded_profile(hold_s), 1e-3, noise, seed + 1000)});
  return f;
}

TEST(MonitorCalibration, UncertaintyIsHonestWithNoise) {
  // Over 40 noisy repetitions the errors, in units of the reported σ, have an RMS near 1
  // (0.7–1.35 allows for the sampling of 40) and none exceeds 4; the noise estimates match
  // what was put in; four times the data halves σ (0.4–0.6).
  const AxisModel truth = zheng2012_axis('x');
  double z2_t = 0, z2_x = 0, z2_k = 0, worst = 0, sigma_short = 0, sigma_long = 0;
  const int n = 40;
  for (int i = 0; i < n; ++i) {
    const NoisyFit f = noisy_fit(truth, 0.5, 100 + i);
    ASSERT_EQ(f.idle.report.status, CalibrationStatus::kSuccess);
    ASSERT_EQ(f.load.report.status, CalibrationStatus::kSuccess);
    const double zt = (f.idle.friction_nm - truth.friction_nm) / f.idle.friction_sigma_nm;
    const double zx =
        (f.idle.viscous_nm_s_per_rad - truth.viscous_nm_s_per_rad) / f.idle.viscous_sigma;
    const double zk = (f.load.force_gain_m - truth.force_gain_m) / f.load.force_gain_sigma_m;
    z2_t += zt * zt;
    z2_x += zx * zx;
    z2_k += zk * zk;
    worst = std::max({worst, std::abs(zt), std::abs(zx), std::abs(zk)});
    sigma_short += f.idle.friction_sigma_nm;
    if (i == 0) {
      EXPECT_NEAR(f.idle.current_noise_a / (0.1 / std::sqrt(3.0)), 1.0, 0.05);
      EXPECT_NEAR(f.idle.speed_noise_rad_s / 0.2, 1.0, 0.05);
      EXPECT_LT(f.load.force_gain_sigma_from_idle_m, f.load.force_gain_sigma_m);
    }
  }
  EXPECT_GT(std::sqrt(z2_t / n), 0.7);
  EXPECT_LT(std::sqrt(z2_t / n), 1.35);
  EXPECT_GT(std::sqrt(z2_x / n), 0.7);
  EXPECT_LT(std::sqrt(z2_x / n), 1.35);
  EXPECT_GT(std::sqrt(z2_k / n), 0.7);
  EXPECT_LT(std::sqrt(z2_k / n), 1.35);
  EXPECT_LT(worst, 4.0);
  for (int i = 0; i < 8; ++i) sigma_long += noisy_fit(truth, 2.0, 500 + i).idle.friction_sigma_nm;
  const double ratio = (sigma_long / 8) / (sigma_short / n);
  EXPECT_GT(ratio, 0.4);
  EXPECT_LT(ratio, 0.6);
}

// Servo axes change speed at 1000 rad/s² and more, and their speed loop overshoots and rings
// before it settles. Windows in which the speed still rings have a flat speed line but a
// mean J·ε that is not J·slope (and phases where the motor brakes): counted as steady they
// biased Tnzm by 0.15 N·m (10 times the noise-limited σ, case A) or inflated σ 2.5 times
// (case B). The true Tnzm and X are known; over 30 noisy logs each the errors must be what the
// reported σ says: RMS of error/σ in 0.65–1.45 (the sampling spread of an RMS of 30 is ±0.13,
// so about 3 of it), no error beyond 4σ, and σ itself noise-limited (Tnzm's RMS error below
// 0.03 N·m = 0.2 %, which the transients broke by 5 times).
TEST(MonitorCalibration, SteadyWindowsSkipServoTransients) {
  const AxisModel truth = zheng2012_axis('x');
  const std::vector<double> speeds{20, 60, 120, -40, -150, 90, 30};  // rad/s
  struct Case {
    double accel_rad_s2, loop_hz, loop_damping, hold_s;
  };
  for (const Case& c : {Case{2000.0, 20.0, 0.15, 0.6}, Case{3000.0, 10.0, 0.1, 1.0}}) {
    double z2_t = 0, z2_x = 0, e2_t = 0, worst = 0;
    const int n = 30;
    for (int i = 0; i < n; ++i) {
      const IdleFit f =
          fit_idle(truth, {servo_run(truth, speeds, c.accel_rad_s2, c.hold_s, c.loop_hz,
                                     c.loop_damping, 1e-3, LogNoise{0.1, 0.2}, 100 + i)});
      ASSERT_EQ(f.report.status, CalibrationStatus::kSuccess) << f.report.message;
      const double et = f.friction_nm - truth.friction_nm;
      const double zt = et / f.friction_sigma_nm;
      const double zx = (f.viscous_nm_s_per_rad - truth.viscous_nm_s_per_rad) / f.viscous_sigma;
      z2_t += zt * zt;
      z2_x += zx * zx;
      e2_t += et * et;
      worst = std::max({worst, std::abs(zt), std::abs(zx)});
    }
    SCOPED_TRACE(::testing::Message() << "loop " << c.loop_hz << " Hz, damping " << c.loop_damping);
    EXPECT_GT(std::sqrt(z2_t / n), 0.65);
    EXPECT_LT(std::sqrt(z2_t / n), 1.45);
    EXPECT_GT(std::sqrt(z2_x / n), 0.65);
    EXPECT_LT(std::sqrt(z2_x / n), 1.45);
    EXPECT_LT(worst, 4.0);
    EXPECT_LT(std::sqrt(e2_t / n), 0.03);
  }
}

// A log in which the speed rings for the whole of every hold has no steady window: the fit
// says so instead of fitting the transients.
TEST(MonitorCalibration, RingingEverywhereIsNotSteady) {
  const AxisModel truth = zheng2012_axis('x');
  const IdleFit f = fit_idle(truth, {servo_run(truth, {20, 60, 120, -40, -150}, 3000.0, 0.4, 10.0,
                                               0.1, 1e-3, LogNoise{0.1, 0.2}, 7)});
  EXPECT_EQ(f.report.status, CalibrationStatus::kTooFewWindows) << f.report.message;
}

TEST(MonitorCalibration, ReportsTooFewSpeeds) {
  const AxisModel truth = zheng2012_axis('x');
  // ±60 rad/s only: sign(ω) and ω are proportional, Tnzm and X are not separable.
  const IdleFit f = fit_idle(truth, {synthetic_run(truth, {{60.0, 0.5}, {-60.0, 0.5, 0.0, 0.2}})});
  EXPECT_EQ(f.report.status, CalibrationStatus::kTooFewSpeeds);
  const IdleFit none = fit_idle(truth, {});
  EXPECT_EQ(none.report.status, CalibrationStatus::kTooFewWindows);
}

}  // namespace
}  // namespace cutdyn
