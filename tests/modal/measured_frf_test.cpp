#include "cutdyn/modal/measured_frf.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

namespace cutdyn {
namespace {

ModalModel two_modes() {
  return ModalModel{{Mode{Direction::kX, 2 * std::numbers::pi * 500.0, 0.02, 2e7},
                     Mode{Direction::kX, 2 * std::numbers::pi * 1200.0, 0.03, 5e7}}};
}

TEST(MeasuredFrf, SampledTableReturnsTheModesAtItsPointsAndInterpolatesBetween) {
  const ModalModel model = two_modes();
  const MeasuredFrf table = sample_frf(model, Direction::kX, linear_frequencies(0, 3000, 30001));
  EXPECT_TRUE(table.validate().empty());
  for (double f : {0.0, 123.4, 499.95, 1200.0, 2999.99, 3000.0}) {
    const std::complex<double> exact = frf(model, Direction::kX, 2 * std::numbers::pi * f);
    // 0.1 Hz spacing, ζ·fn ≥ 10 Hz: linear interpolation is within 1e-4 of |G| peak.
    EXPECT_LT(std::abs(table.at(f) - exact), 1e-4 * std::abs(exact) + 1e-13) << f;
  }
}

TEST(MeasuredFrf, ValidationNamesEachBadPoint) {
  MeasuredFrf bad;
  bad.frequency_hz = {10.0, 10.0, 5.0, std::numeric_limits<double>::quiet_NaN()};
  bad.receptance_m_per_n = {{1e-8, 0}, {1e-8, 0}, {std::nan(""), 0}, {1e-8, 0}};
  const auto problems = bad.validate();
  ASSERT_GE(problems.size(), 3u);
  EXPECT_NE(problems[0].find("frequency_hz[1]"), std::string::npos) << problems[0];
  const MeasuredFrf too_few{{1.0, 2.0}, {{0, 0}, {0, 0}}};
  EXPECT_FALSE(too_few.validate().empty());
  const MeasuredFrf unequal{{1.0, 2.0, 3.0}, {{0, 0}}};
  EXPECT_FALSE(unequal.validate().empty());
}

}  // namespace
}  // namespace cutdyn
