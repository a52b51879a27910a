// "-" as an output file: the file goes to standard output, the report to standard error.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "support/cli_runner.hpp"

namespace cutdyn::cli {
namespace {

using testing::run_cutdyn;

TEST(OutputTargets, DashWritesTheFileToStandardOutputAndTheReportToStandardError) {
  const auto lobes = run_cutdyn({"lobes", "milling-insperger", "--out", "-"});
  ASSERT_EQ(lobes.code, 0) << lobes.err;
  EXPECT_EQ(lobes.out.rfind("spindle_rpm,critical_depth_mm,chatter_hz,", 0), 0u) << lobes.out;
  EXPECT_EQ(lobes.out.find("cutdyn lobes"), std::string::npos);  // only the CSV
  EXPECT_NE(lobes.err.find("cutdyn lobes: example milling-insperger"), std::string::npos);
  EXPECT_NE(lobes.err.find("wrote standard output"), std::string::npos) << lobes.err;
  // The same lobes as a file.
  const auto json = run_cutdyn({"check", "milling-insperger", "--rpm", "10000", "--depth-mm",
                                "0.05", "--json", "-"});
  ASSERT_EQ(json.code, 0) << json.err;
  const auto doc = nlohmann::json::parse(json.out);
  EXPECT_EQ(doc["command"], "check");
  EXPECT_TRUE(doc["stable"].get<bool>());
  const auto plan = run_cutdyn({"plan", "--json", "-"});
  ASSERT_EQ(plan.code, 0) << plan.err;
  EXPECT_NEAR(nlohmann::json::parse(plan.out)["main_time_min"].get<double>(), 24.67, 0.01);
}

TEST(OutputTargets, TwoFilesCannotBothBeStandardOutput) {
  const auto r = run_cutdyn({"lobes", "milling-insperger", "--out", "-", "--json", "-"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--out and --json name the same file (-)"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "");  // nothing written
}

}  // namespace
}  // namespace cutdyn::cli
