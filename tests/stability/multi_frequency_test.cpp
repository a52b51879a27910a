#include "cutdyn/stability/multi_frequency.hpp"

#include <gtest/gtest.h>

#include "cutdyn/stability/tlusty.hpp"
#include "support/reference_cases.hpp"

namespace cutdyn {
namespace {

using testing::table2_conventional;
using testing::table2_vibration;

TEST(MultiFrequency, ConstantCoefficientIsTlusty) {
  // Every 15 rpm over 500–5000: two independent root searches (phase condition on a
  // frequency grid; eigenvalue crossings of the scan) must find the same boundary.
  const TurningModel m = table2_conventional();
  for (double rpm = 500.0; rpm <= 5000.0; rpm += 15.0) {
    MultiFrequencyOptions o;
    const CriticalDepth mf = multi_frequency_critical_depth(turning_system(m, rpm), o);
    const auto exact = tlusty_critical_depth(m.modal, Direction::kX, m.kt_pa, 60.0 / rpm, 0.03);
    ASSERT_EQ(mf.found, exact.boundary.found) << "rpm " << rpm;
    EXPECT_NEAR(mf.depth_m, exact.boundary.depth_m, 1e-9 * exact.boundary.depth_m) << "rpm " << rpm;
    EXPECT_NEAR(mf.chatter_hz, exact.boundary.chatter_hz, 1e-6) << "rpm " << rpm;
  }
}

TEST(MultiFrequency, AveragedFormScalesKtByTheDutyCycle) {
  const TurningModel m = table2_vibration(20000.0);
  MultiFrequencyOptions o;
  o.harmonics = 0;
  for (double rpm : {700.0, 2600.0}) {
    const CriticalDepth mf = multi_frequency_critical_depth(turning_system(m, rpm), o);
    const auto exact =
        tlusty_critical_depth(m.modal, Direction::kX, 0.6 * m.kt_pa, 60.0 / rpm, 0.03);
    EXPECT_NEAR(mf.depth_m, exact.boundary.depth_m, 1e-9 * exact.boundary.depth_m);
  }
}

TEST(MultiFrequency, ConvergesWithTheNumberOfHarmonics) {
  const TurningModel m = table2_vibration(500.0);  // about 2.2 times fn
  const DelayedSystem s = turning_system(m, 2500.0);
  double previous = 0.0;
  double previous_change = 1.0;
  for (int p : {2, 4, 8, 16}) {
    MultiFrequencyOptions o;
    o.harmonics = p;
    const double depth = multi_frequency_critical_depth(s, o).depth_m;
    if (previous > 0.0) {
      const double change = std::abs(depth - previous) / depth;
      EXPECT_LT(change, previous_change) << "P = " << p;
      previous_change = change;
    }
    previous = depth;
  }
  EXPECT_LT(previous_change, 2e-3);
}

}  // namespace
}  // namespace cutdyn
