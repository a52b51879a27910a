// `cutdyn lobes` and `cutdyn check` tell one story: every method, every way of giving the
// cut and every depth asked give the same critical depth at a speed (no result may be
// silently wrong).
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cutdyn/io/case_file.hpp"
#include "support/cli_runner.hpp"
#include "support/temp_dir.hpp"

namespace cutdyn::cli {
namespace {

using testing::run_cutdyn;

class StabilityCli : public testing::TempDirTest {
 protected:
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  // The milling-insperger example with some lines replaced.
  std::string insperger(const std::vector<std::pair<std::string, std::string>>& edits,
                        const std::string& name) const {
    std::string text(*io::example_text("milling-insperger"));
    for (const auto& [from, to] : edits) {
      const auto at = text.find(from);
      EXPECT_NE(at, std::string::npos) << from;
      if (at != std::string::npos) text.replace(at, from.size(), to);
    }
    std::ofstream(path(name)) << text;
    return path(name);
  }
  // `cutdyn check` through its JSON.
  nlohmann::json check(const std::string& file, const std::string& rpm, const std::string& depth,
                       const std::vector<std::string>& more = {}) {
    std::vector<std::string> args{"check",      file,  "--rpm",  rpm,
                                  "--depth-mm", depth, "--json", path("check.json")};
    args.insert(args.end(), more.begin(), more.end());
    const auto r = run_cutdyn(args);
    EXPECT_EQ(r.code, 0) << r.err;
    return nlohmann::json::parse(std::ifstream(path("check.json")));
  }
  // `cutdyn lobes` through its JSON points.
  nlohmann::json lobes(const std::string& file, const std::vector<std::string>& more = {}) {
    std::vector<std::string> args{"lobes", file, "--json", path("lobes.json")};
    args.insert(args.end(), more.begin(), more.end());
    const auto r = run_cutdyn(args);
    EXPECT_EQ(r.code, 0) << r.err;
    return nlohmann::json::parse(std::ifstream(path("lobes.json")))["points"];
  }
};

TEST_F(StabilityCli, MultiFrequencyCheckOfTheShippedExampleIsUnstable) {
  // Before: "STABLE (> 1 mm)" with 5 harmonics of the 167 Hz tooth frequency, which do not
  // reach the 922 Hz mode; the full discretization says 0.0475 mm.
  const auto fd = check("milling-insperger", "5000", "0.1");
  const auto mf = check("milling-insperger", "5000", "0.1", {"--method", "multi-frequency"});
  EXPECT_FALSE(fd["stable"].get<bool>());
  EXPECT_FALSE(mf["stable"].get<bool>());
  EXPECT_NEAR(mf["critical_depth_mm"].get<double>(), fd["critical_depth_mm"].get<double>(),
              0.005 * fd["critical_depth_mm"].get<double>());
}

TEST_F(StabilityCli, ZeroOrderSaysWhereItIsWeak) {
  // The shipped example at a/D 0.05, 20 000 rpm: the full discretization finds a flip lobe at
  // 3.26 mm, the zero-order method (which cannot see flip lobes) 6.85 mm — twice the safe
  // depth. Its check and lobes carry the caveat (stdout, stderr, JSON); the default method,
  // and the zero-order method on a slot at high speed (its range), carry none.
  const std::string low = insperger({{"radial_immersion = 1.0           # slotting",
                                      "radial_immersion = 0.05"},
                                     {"depth_max_mm = 1", "depth_max_mm = 10"}},
                                    "low.toml");
  const auto zo = check(low, "20000", "0.1", {"--method", "zero-order"});
  const auto fd = check(low, "20000", "0.1");
  EXPECT_EQ(fd["bifurcation"], "flip");
  EXPECT_GT(zo["critical_depth_mm"].get<double>(), 1.8 * fd["critical_depth_mm"].get<double>());
  ASSERT_TRUE(zo.contains("warnings"));
  EXPECT_NE(zo["warnings"][0].get<std::string>().find("the cut is not a slot"), std::string::npos);
  EXPECT_FALSE(fd.contains("warnings"));
  EXPECT_FALSE(check("milling-insperger", "20000", "0.01", {"--method", "zero-order"})
                   .contains("warnings"));
  const auto r = run_cutdyn({"lobes", low, "--method", "zero-order", "--json", path("zo.json")});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("cutdyn: warning: zero-order (averaged) method outside its range"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(nlohmann::json::parse(std::ifstream(path("zo.json")))["warnings"].size(), 1u);
}

TEST_F(StabilityCli, EntryAndExitAnglesActInLobesAndCheck) {
  // A 90–180° window is half immersion in down-milling (0.181 mm at 10 000 rpm), not the
  // slotting limit (0.0714 mm) that lobes and check gave when they ignored the angles.
  const auto window =
      insperger({{"radial_immersion = 1.0           # slotting", "entry_deg = 90\nexit_deg = 180"},
                 {"direction = \"down\"\n", ""}},
                "window.toml");
  const auto half = insperger({{"radial_immersion = 1.0", "radial_immersion = 0.5"}}, "half.toml");
  const auto a = check(window, "10000", "0.1");
  const auto b = check(half, "10000", "0.1");
  EXPECT_NEAR(a["critical_depth_mm"].get<double>(), b["critical_depth_mm"].get<double>(), 1e-9);
  EXPECT_NEAR(a["critical_depth_mm"].get<double>(), 0.181, 0.002);
  const auto r = run_cutdyn({"check", window, "--rpm", "10000", "--depth-mm", "0.1"});
  EXPECT_NE(r.out.find("entry 90°, exit 180° (a_e/D = 0.5)"), std::string::npos) << r.out;
  const auto la = lobes(window, {"--method", "zero-order"});
  const auto lb = lobes(half, {"--method", "zero-order"});
  ASSERT_EQ(la.size(), lb.size());
  for (std::size_t i = 0; i < la.size(); i += 20)
    EXPECT_NEAR(la[i]["critical_depth_mm"].get<double>(), lb[i]["critical_depth_mm"].get<double>(),
                1e-9);
  // Up-milling 0–90° is half immersion up.
  const auto up_window =
      insperger({{"radial_immersion = 1.0           # slotting", "entry_deg = 0.0\nexit_deg = 90"},
                 {"direction = \"down\"\n", ""}},
                "up-window.toml");
  const auto up_half = insperger({{"radial_immersion = 1.0", "radial_immersion = 0.5"},
                                  {"direction = \"down\"", "direction = \"up\""}},
                                 "up-half.toml");
  EXPECT_NEAR(check(up_window, "12000", "0.1")["critical_depth_mm"].get<double>(),
              check(up_half, "12000", "0.1")["critical_depth_mm"].get<double>(), 1e-9);
}

TEST_F(StabilityCli, CriticalDepthDoesNotDependOnTheDepthAsked) {
  // Before: 0.0715 mm asked at 0.064, 0.069 at 100, 0.125 at 1000, "0 mm, margin −inf %" at
  // 5000. The critical depth is a property of the speed: that of the lobes at that speed.
  const auto file = insperger({{"rpm_min = 5000", "rpm_min = 10000"},
                               {"rpm_max = 25000", "rpm_max = 10001"},
                               {"rpm_steps = 200", "rpm_steps = 2"}},
                              "one-speed.toml");
  const double lobe = lobes(file)[0]["critical_depth_mm"].get<double>();
  for (const char* depth : {"0.01", "0.064", "3", "100", "1000", "5000"}) {
    const auto doc = check(file, "10000", depth);
    EXPECT_DOUBLE_EQ(doc["critical_depth_mm"].get<double>(), lobe) << depth;
    EXPECT_TRUE(doc["margin"].is_number()) << depth;
    EXPECT_EQ(doc["stable"].get<bool>(), std::stod(depth) < lobe) << depth;
  }
  const auto deep = check("milling-insperger", "25000", "2");
  EXPECT_NEAR(deep["critical_depth_mm"].get<double>(), 0.5304, 0.002);
  // 100 times softer cutting: stable beyond the case's limit (1 mm); the search goes on, on the
  // lobes' depth grid, to 1.25 × the depth asked, and the margin is a lower bound.
  const auto low = insperger(
      {{"kt_n_per_mm2 = 600", "kt_n_per_mm2 = 6"}, {"kr_n_per_mm2 = 200", "kr_n_per_mm2 = 2"}},
      "soft.toml");
  const auto stable = check(low, "25000", "10");
  EXPECT_TRUE(stable["stable"].get<bool>());
  EXPECT_TRUE(stable["beyond_limit"].get<bool>());
  EXPECT_NEAR(stable["critical_depth_mm"].get<double>(), 12.5, 1e-9);
  EXPECT_NEAR(stable["margin"].get<double>(), 0.2, 1e-9);
  const auto found = check(low, "25000", "45");  // the 0.53 mm boundary, scaled by 100
  EXPECT_NEAR(found["critical_depth_mm"].get<double>(), 53.04, 0.2);
  const auto r = run_cutdyn({"check", low, "--rpm", "25000", "--depth-mm", "500"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("raise lobes.depth_max_mm"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace cutdyn::cli
