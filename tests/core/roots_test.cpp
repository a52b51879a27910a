#include "cutdyn/core/detail/roots.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cutdyn/core/error.hpp"

namespace cutdyn {
namespace {

TEST(BrentMinimum, FindsTheMinimumOfSmoothAndKinkedFunctions) {
  // Smooth: (x − 1)² + 3 on [−2, 5]; superlinear convergence, few evaluations.
  const MinimumResult r =
      brent_minimum([](double x) { return (x - 1.0) * (x - 1.0) + 3.0; }, -2.0, 5.0, 1e-10);
  EXPECT_TRUE(r.converged);
  EXPECT_NEAR(r.x, 1.0, 1e-7);  // the minimum of a parabola is flat: x to about sqrt(eps)
  EXPECT_NEAR(r.fx, 3.0, 1e-14);
  EXPECT_LT(r.evaluations, 15);
  // cos on [2, 5]: minimum at π.
  const MinimumResult c = brent_minimum([](double x) { return std::cos(x); }, 2.0, 5.0, 1e-10);
  EXPECT_NEAR(c.x, std::numbers::pi, 1e-7);
  // A kink |x − 0.3| defeats the parabolas; the golden sections still converge.
  const MinimumResult k = brent_minimum([](double x) { return std::abs(x - 0.3); }, 0.0, 1.0, 1e-9);
  EXPECT_TRUE(k.converged);
  EXPECT_NEAR(k.x, 0.3, 1e-8);
  // Minimum on the boundary: it ends within the tolerance of the bound.
  const MinimumResult b = brent_minimum([](double x) { return x; }, 0.0, 1.0, 1e-9);
  EXPECT_LT(b.x, 1e-8);
}

TEST(BrentRoot, FindsCubeRootOfTwoToTolerance) {
  auto r = brent_root([](double x) { return x * x * x - 2.0; }, 0.0, 2.0, 1e-14);
  ASSERT_TRUE(r.has_value());
  EXPECT_TRUE(r->converged);
  EXPECT_NEAR(r->x, std::cbrt(2.0), 1e-13);
  EXPECT_LT(r->evaluations, 30);  // superlinear: bisection would need ~47
}

TEST(BrentRoot, RejectsBracketWithoutSignChange) {
  EXPECT_FALSE(brent_root([](double x) { return x * x + 1.0; }, -1.0, 1.0, 1e-12).has_value());
}

TEST(BrentRoot, HandlesRootAtEndpoint) {
  auto r = brent_root([](double x) { return std::sin(x); }, 0.0, 1.0, 1e-12);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->x, 0.0);
}

TEST(BrentRoot, KnownEndValuesAreNotEvaluatedAgain) {
  int calls = 0;
  const auto f = [&](double x) {
    ++calls;
    return std::exp(x) - 3.0;
  };
  auto r = brent_root(f, 0.0, f(0.0), 2.0, f(2.0), 1e-13);
  ASSERT_TRUE(r.has_value());
  EXPECT_NEAR(r->x, std::log(3.0), 1e-12);
  EXPECT_EQ(calls, r->evaluations + 2);  // the two calls above, then the method's own
}

TEST(Validator, ListsEveryProblemWithFieldValueUnitAndRule) {
  Validator v("modes[0]");
  v.require_positive("stiffness_n_per_m", -5.0, "N/m");
  v.require_in_open("damping_ratio", 1.5, "", 0.0, 1.0);
  v.require_positive("natural_hz", std::nan(""), "Hz");
  ASSERT_EQ(v.problems().size(), 3u);
  EXPECT_EQ(v.problems()[0], "modes[0].stiffness_n_per_m = -5 N/m: must be positive");
  EXPECT_EQ(v.problems()[1],
            "modes[0].damping_ratio = 1.5: must be greater than 0 and less than 1");
  EXPECT_EQ(v.problems()[2], "modes[0].natural_hz = nan Hz: must be a finite number");
  try {
    v.throw_if_any("case.toml");
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where(), "case.toml");
    EXPECT_EQ(e.problems().size(), 3u);
  }
}

}  // namespace
}  // namespace cutdyn
