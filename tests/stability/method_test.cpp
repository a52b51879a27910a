#include "cutdyn/stability/method.hpp"

#include <gtest/gtest.h>

#include "cutdyn/stability/milling.hpp"
#include "cutdyn/stability/turning.hpp"
#include "support/reference_cases.hpp"

namespace cutdyn {
namespace {

TEST(StabilityMethodNames, EveryNameParsesBackAndUnknownOnesDoNot) {
  for (StabilityMethod m :
       {StabilityMethod::kAuto, StabilityMethod::kZeroOrder, StabilityMethod::kClosedForm,
        StabilityMethod::kMultiFrequency, StabilityMethod::kFullDiscretization,
        StabilityMethod::kFullDiscretizationDense}) {
    ASSERT_TRUE(parse_stability_method(to_string(m)).has_value()) << to_string(m);
    EXPECT_EQ(*parse_stability_method(to_string(m)), m);
    EXPECT_NE(std::string(kStabilityMethodNames).find(to_string(m)), std::string::npos);
  }
  EXPECT_FALSE(parse_stability_method("Auto").has_value());
  EXPECT_FALSE(parse_stability_method("").has_value());
  EXPECT_FALSE(parse_stability_method("tlusty").has_value());
}

TEST(StabilityMethodNames, ZeroOrderAndClosedFormAreOneMethodInEachProcess) {
  // Turning: the zero-order solution is the closed form (exact without vibration, the averaged
  // theory with it); milling: the closed form is the zero-order solution. Same numbers.
  for (bool vibration : {false, true}) {
    const TurningProcess m =
        vibration ? testing::table2_vibration() : testing::table2_conventional();
    EXPECT_EQ(turning_method(StabilityMethod::kZeroOrder, vibration), TurningMethod::kClosedForm);
    EXPECT_EQ(turning_method(StabilityMethod::kClosedForm, vibration), TurningMethod::kClosedForm);
    EXPECT_EQ(turning_method(StabilityMethod::kAuto, vibration),
              vibration ? TurningMethod::kFullDiscretization : TurningMethod::kClosedForm);
    TurningStabilityOptions o;
    o.method = turning_method(StabilityMethod::kZeroOrder, vibration);
    const double zero_order = turning_critical_depth(m, 1400.0, o).boundary.depth_m;
    o.method = TurningMethod::kClosedForm;
    EXPECT_EQ(turning_critical_depth(m, 1400.0, o).boundary.depth_m, zero_order);
  }
  EXPECT_EQ(milling_method(StabilityMethod::kClosedForm), MillingMethod::kZeroOrder);
  EXPECT_EQ(milling_method(StabilityMethod::kZeroOrder), MillingMethod::kZeroOrder);
  EXPECT_EQ(milling_method(StabilityMethod::kAuto), MillingMethod::kFullDiscretization);
  EXPECT_EQ(milling_method(StabilityMethod::kFullDiscretizationDense),
            MillingMethod::kFullDiscretizationDense);
  EXPECT_STREQ(to_string(MillingMethod::kZeroOrder), "zero-order");
}

}  // namespace
}  // namespace cutdyn
