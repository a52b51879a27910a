#include "cutdyn/stability/lobes.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace cutdyn {
namespace {

// A margin with an unstable island [0.30, 0.36] below the main boundary at 0.70: the coarse
// scan must stop in the island, and Brent's method must land on its lower edge.
double island_margin(double w) {
  if (w < 0.30) return w - 0.30;
  if (w < 0.36) return (w - 0.30) * (0.36 - w);  // > 0 in the island
  if (w < 0.70) return -(w - 0.36) * (0.70 - w);
  return w - 0.70;
}

TEST(CriticalDepthByBracketing, StopsAtAnUnstableIslandBelowTheMainBoundary) {
  // 16 coarse steps of 1/16 = 0.0625: 0.3125 falls in the island.
  const CriticalDepth c = critical_depth_by_bracketing(island_margin, 1.0, 16, 1e-8);
  ASSERT_TRUE(c.found);
  EXPECT_NEAR(c.depth_m, 0.30, 1e-8);
  EXPECT_LT(c.evaluations, 5 + 20);  // 5 coarse + Brent; bisection alone would need ~25
  // Too coarse a scan steps over the island and finds the main boundary (documented limit).
  const CriticalDepth coarse = critical_depth_by_bracketing(island_margin, 1.0, 4, 1e-8);
  ASSERT_TRUE(coarse.found);
  EXPECT_NEAR(coarse.depth_m, 0.70, 1e-8);
}

TEST(CriticalDepthByBracketing, ReportsTheLimitWhenStableEverywhere) {
  const CriticalDepth c =
      critical_depth_by_bracketing([](double w) { return w - 2.0; }, 1.0, 8, 1e-6);
  EXPECT_FALSE(c.found);
  EXPECT_EQ(c.depth_m, 1.0);
  EXPECT_EQ(c.evaluations, 8);
}

TEST(CriticalDepthByBracketing, BoundaryBelowTheFirstCoarseStep) {
  // Root at 0.01 < 1/16: the bracket is [0, 1/16], the margin at 0 is evaluated once.
  const CriticalDepth c = critical_depth_by_bracketing(
      [](double w) { return std::expm1(w) - std::expm1(0.01); }, 1.0, 16, 1e-10);
  ASSERT_TRUE(c.found);
  EXPECT_NEAR(c.depth_m, 0.01, 1e-11);
}

}  // namespace
}  // namespace cutdyn
