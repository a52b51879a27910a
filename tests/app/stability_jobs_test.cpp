// The lobes and check jobs agree with each other: `check` at a speed of the lobes finds the
// lobes' critical depth there, and its verdict flips across it; the recommended speed is
// stable at the target depth by `check`, with the stated margin.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "cutdyn/app/case_models.hpp"
#include "cutdyn/app/stability.hpp"
#include "cutdyn/core/error.hpp"

namespace cutdyn::app {
namespace {

struct Example {
  const char* name;
  double rel_tol;  // of the critical depth between the two jobs
};

class StabilityJobs : public ::testing::TestWithParam<Example> {};

TEST_P(StabilityJobs, CheckAgreesWithTheLobesAndTheRecommendation) {
  const io::Case c = load_case(GetParam().name, "");
  LobesRequest lr;
  lr.threads = 2;
  const LobesJobReport lobes = run_lobes(c, lr);
  ASSERT_FALSE(lobes.lobes.points.empty());
  const auto& pts = lobes.lobes.points;
  // Three speeds: the lowest depth, a pocket (if any) and the middle of the grid.
  std::vector<std::size_t> at{lobes.lowest, pts.size() / 2};
  if (!lobes.pockets.empty()) at.push_back(lobes.pockets.front());
  for (std::size_t i : at) {
    const LobePoint& p = pts[i];
    if (!p.boundary.found) continue;
    CheckRequest below, above;
    below.rpm = above.rpm = p.rpm;
    below.depth_m = 0.97 * p.boundary.depth_m;
    above.depth_m = 1.03 * p.boundary.depth_m;
    const CheckJobReport b = run_check(c, below), a = run_check(c, above);
    EXPECT_EQ(b.method, lobes.method);
    EXPECT_NEAR(b.boundary.depth_m / p.boundary.depth_m, 1.0, GetParam().rel_tol)
        << GetParam().name << " at " << p.rpm << " rpm";
    EXPECT_TRUE(b.stable) << p.rpm;
    EXPECT_FALSE(a.stable) << p.rpm;
    ASSERT_TRUE(b.margin.has_value());
    EXPECT_NEAR(*b.margin, 1.0 - 0.97 * p.boundary.depth_m / b.boundary.depth_m, 1e-12);
  }
  // The recommended speed at half the lowest pocket's depth: stable there by `check`, and
  // still stable with the speed off by the stated margin.
  LobesRequest target = lr;
  target.target_depth_m =
      0.5 * pts[lobes.pockets.empty() ? lobes.lowest : lobes.pockets.front()].boundary.depth_m;
  const LobesJobReport advised = run_lobes(c, target);
  if (!advised.advice.found) return;
  for (double factor :
       {1.0, 1.0 - 0.9 * advised.advice.margin, 1.0 + 0.9 * advised.advice.margin}) {
    CheckRequest r;
    r.rpm = advised.advice.rpm * factor;
    r.depth_m = *target.target_depth_m;
    EXPECT_TRUE(run_check(c, r).stable) << GetParam().name << " at " << r.rpm << " rpm";
  }
}

// Turning (conventional, vibration-assisted) and milling (even and variable pitch).
INSTANTIATE_TEST_SUITE_P(Examples, StabilityJobs,
                         ::testing::Values(Example{"turning-conventional", 1e-9},
                                           Example{"turning-ultrasonic", 1e-9},
                                           Example{"milling-insperger", 2e-3},
                                           Example{"milling-variable-pitch", 2e-3}),
                         [](const auto& p) {
                           std::string n = p.param.name;
                           for (char& ch : n)
                             if (ch == '-') ch = '_';
                           return n;
                         });

TEST(StabilityJobsInput, EachJobAsksForWhatItUses) {
  // A case of [material] and [cutting] alone: the force job runs, the lobes job asks for the
  // structure (and names the command).
  const io::Case c = io::parse_case(
      "[material]\nname = \"AISI1045\"\n[cutting]\nspeed_m_per_min = 200\n"
      "uncut_chip_thickness_mm = 0.15\nwidth_mm = 1.6\nrake_deg = -7\n",
      "bare.toml");
  EXPECT_EQ(c.process, io::Process::kTurning);
  try {
    run_lobes(c, LobesRequest{});
    FAIL() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("modes: missing (required by `cutdyn lobes`"),
              std::string::npos)
        << e.what();
  }
}

TEST(StabilityJobsInput, RequestNamesAppearInTheErrors) {
  const io::Case c = load_case("turning-conventional", "");
  CheckRequest r;
  r.rpm = -5.0;
  r.depth_m = 1e-3;
  r.names = {"command line", "--rpm", "--depth-mm", "--method"};
  try {
    run_check(c, r);
    FAIL() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("--rpm"), std::string::npos) << e.what();
  }
  r.rpm = 1000.0;
  r.method = "tlusty";
  EXPECT_THROW(run_check(c, r), InvalidInput);
}

TEST(StabilityJobsInput, EveryGridTheCaseFileAcceptsIsAGrid) {
  // The refinement's speed budget is not a case key, so it never refuses a grid the case file
  // accepts: up to 100 000 speeds, refined or not, and refinement may still double it.
  io::Case c = load_case("milling-insperger", "");
  for (const bool refine : {true, false}) {
    for (const int steps : {2, 200, 20000, 20001, 100000}) {
      c.lobes.grid.refine = refine;
      c.lobes.grid.rpm_steps = steps;
      const LobesOptions grid = lobes_grid(c, 1);
      EXPECT_EQ(grid.rpm_steps, steps);
      EXPECT_GE(grid.refine_max_points, std::max(20000, 2 * steps));
    }
  }
  // In the library the budget is checked only when refining.
  LobesOptions o;
  o.rpm_steps = 30000;
  o.refine = false;
  EXPECT_TRUE(o.validate().empty());
  o.refine = true;
  ASSERT_EQ(o.validate().size(), 1u);
  EXPECT_NE(o.validate()[0].find("refine_max_points"), std::string::npos);
}

// [lobes] refine_levels reaches the tracing: 0 keeps the uniform grid, each level may halve
// an interval once more (the speeds added at level k lie on the grid of spacing Δ/2^k), and
// the echo writes the key only when it is set.
TEST(StabilityJobsInput, RefineLevelsFromTheCaseSetTheFinestSpacing) {
  const std::string base = std::string(*io::example_text("turning-conventional"));
  const auto lobes_with = [&](int levels) {
    const io::Case c =
        io::with_value(io::parse_case(base, "t.toml"), "lobes.refine_levels", levels);
    EXPECT_EQ(c.lobes.grid.refine_levels, levels);
    LobesRequest r;
    r.threads = 1;
    return run_lobes(c, r).lobes.points;
  };
  const io::Case plain = io::parse_case(base, "t.toml");
  const double spacing =
      (plain.lobes.grid.rpm_max - plain.lobes.grid.rpm_min) / (plain.lobes.grid.rpm_steps - 1);
  const auto finest = [](const std::vector<LobePoint>& p) {
    double f = std::numeric_limits<double>::infinity();
    for (std::size_t i = 1; i < p.size(); ++i) f = std::min(f, p[i].rpm - p[i - 1].rpm);
    return f;
  };
  const std::vector<LobePoint> none = lobes_with(0), two = lobes_with(2), eight = lobes_with(8);
  EXPECT_EQ(none.size(), static_cast<std::size_t>(plain.lobes.grid.rpm_steps));
  EXPECT_GT(two.size(), none.size());
  EXPECT_GT(eight.size(), two.size());
  EXPECT_NEAR(finest(two), spacing / 4.0, 1e-9 * spacing);
  EXPECT_GE(finest(eight), spacing / 256.0 * (1.0 - 1e-9));
  EXPECT_LT(finest(eight), finest(two));
  EXPECT_FALSE(io::to_json(plain)["lobes"].contains("refine_levels"));
  EXPECT_EQ(io::to_json(io::with_value(plain, "lobes.refine_levels", 3))["lobes"]["refine_levels"],
            3);
}

}  // namespace
}  // namespace cutdyn::app
