// Equivalent current [Zheng2012, eq. 1] and the axis torque balance (eq. 4).
#include "cutdyn/monitor/axis_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn {
namespace {

TEST(MonitorEquivalentCurrent, BalancedSinusoidsGiveRmsAndPeak) {
  // Balanced currents of peak 10 A: RMS 10/√2 at every angle, space vector 10 (the peak).
  for (double angle : {0.0, 0.3, 1.7, 4.0}) {
    const double iu = 10 * std::cos(angle), iv = 10 * std::cos(angle - units::kTwoPi / 3),
                 iw = 10 * std::cos(angle + units::kTwoPi / 3);
    EXPECT_NEAR(equivalent_current(iu, iv, iw, CurrentMeasure::kRms), 10 / std::sqrt(2.0), 1e-12);
    EXPECT_NEAR(equivalent_current(iu, iv, iw, CurrentMeasure::kSpaceVector), 10.0, 1e-12);
  }
  EXPECT_DOUBLE_EQ(equivalent_current(3, 4, 12, CurrentMeasure::kRms), std::sqrt(169.0 / 3));
}

TEST(MonitorEquivalentCurrent, NoiseSigmaMatchesMonteCarlo) {
  // 0.2 A white noise per phase on 8 A peak currents: the scatter of Id is σ/√3 (RMS) and
  // σ·√(2/3) (space vector) to first order; 200 000 draws give it to about 0.5 %.
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g(0.0, 0.2);
  for (CurrentMeasure m : {CurrentMeasure::kRms, CurrentMeasure::kSpaceVector}) {
    double sum = 0, sum2 = 0;
    const int n = 200000;
    for (int k = 0; k < n; ++k) {
      const double a = 0.001 * k;
      const double id =
          equivalent_current(8 * std::cos(a) + g(rng), 8 * std::cos(a - units::kTwoPi / 3) + g(rng),
                             8 * std::cos(a + units::kTwoPi / 3) + g(rng), m);
      sum += id;
      sum2 += id * id;
    }
    const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
    EXPECT_NEAR(sd / equivalent_current_sigma(0.2, m), 1.0, 0.02) << to_string(m);
  }
}

TEST(MonitorAxisModel, PresetAndBalance) {
  // The printed numbers in kgf·cm (× 0.0980665 N·m per kgf·cm), docs/models/monitor.md §2.
  const double k = 0.0980665;
  const AxisModel x = zheng2012_axis('x');
  EXPECT_DOUBLE_EQ(x.friction_nm, 15.60 * k);  // 1.5298 N·m
  EXPECT_NEAR(x.friction_nm, 1.53, 0.005);
  EXPECT_DOUBLE_EQ(x.force_gain_m, 0.00632 * k);  // a lever of 0.62 mm
  EXPECT_DOUBLE_EQ(x.torque_constant_nm_per_a, 1.621 * k);
  EXPECT_DOUBLE_EQ(zheng2012_axis('Y').viscous_nm_s_per_rad, 0.1569 * k);
  EXPECT_DOUBLE_EQ(zheng2012_axis('z').inertia_kg_m2, 0.019 * k);
  EXPECT_THROW(zheng2012_axis('w'), InvalidInput);
  EXPECT_TRUE(x.validate().empty());
  // By hand: ω = 100 rad/s, ε = 50 rad/s², Fc = 2000 N: torque k·(0.017·50 + 0.2103·100 +
  // 15.6 + 0.00632·2000) = k·50.11 N·m, Id = that/(k·1.621) A; both directions.
  const double id = x.equivalent_current_a(2000, 100, 50);
  EXPECT_NEAR(id * 1.621, 0.85 + 21.03 + 15.6 + 12.64, 1e-12);
  EXPECT_NEAR(x.cutting_force_n(id, 100, 50), 2000.0, 1e-9);
  const double back = x.equivalent_current_a(-2000, -100, -50);
  EXPECT_NEAR(back, id, 1e-12);
  EXPECT_NEAR(x.cutting_force_n(back, -100, -50), -2000.0, 1e-9);
  AxisModel bad = x;
  bad.torque_constant_nm_per_a = 0;
  bad.force_gain_m = -1;
  EXPECT_EQ(bad.validate().size(), 2u);
}

}  // namespace
}  // namespace cutdyn

namespace cutdyn {
namespace {

TEST(MonitorPreset, Zheng2012IsPhysicallyPlausible) {
  // The source's motor: 1.5 kW, rated at 2000 rpm, so 7.16 N·m rated torque. Read in kgf·cm
  // the friction torque is 19–25 % of it and the idle loss (Tnzm + X·ω)·ω at 2000 rpm 0.97–1.44
  // kW, below the motor's power (read as SI it was 15.6 N·m, 218 %, and 12.5 kW).
  const double w = 2000.0 * 2.0 * 3.14159265358979323846 / 60.0, rated = 1500.0 / w;
  EXPECT_NEAR(rated, 7.16, 0.01);
  for (char a : {'x', 'y', 'z'}) {
    const AxisModel m = zheng2012_axis(a);
    const double loss = (m.friction_nm + m.viscous_nm_s_per_rad * w) * w;
    EXPECT_LT(m.friction_nm, 0.25 * rated) << a;
    EXPECT_GT(m.friction_nm, 0.19 * rated) << a;
    EXPECT_LT(loss, 1500.0) << a;
    EXPECT_GT(loss, 900.0) << a;
  }
  // x by hand: Tnzm 1.530 N·m, X·ω = 0.020623·209.44 = 4.319 N·m, loss 1225 W.
  const AxisModel x = zheng2012_axis('x');
  EXPECT_NEAR((x.friction_nm + x.viscous_nm_s_per_rad * w) * w, 1225.0, 1.0);
}

}  // namespace
}  // namespace cutdyn
