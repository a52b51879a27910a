// The full discretization's step from the physics and its convergence check: where a tooth
// cuts, steps of at most 1/32 of the period of the structure stiffened by the cut at the
// boundary, and at least 8 per contact window; the boundary confirmed on a grid of half the
// step (FdOptions::window_steps, cutting_depth_m, refinements). docs/models/milling-stability.md,
// "The step and its convergence check".
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "cutdyn/core/units.hpp"
#include "cutdyn/modal/modal_model.hpp"
#include "cutdyn/stability/full_discretization.hpp"
#include "cutdyn/stability/lobes.hpp"
#include "cutdyn/stability/milling.hpp"
#include "support/reference_cases.hpp"

namespace cutdyn {
namespace {

using testing::insperger_benchmark;

// x and y modes 5 % apart, one tooth of a 20 mm cutter, Kt 600 N/mm², Kr 200 N/mm².
MillingProcess one_tooth(double hz, double zeta, double mass_kg, double immersion, bool down) {
  MillingProcess m;
  m.modal.modes.push_back(mode_from_mass(Direction::kX, units::hz_to_rad_per_s(hz), zeta, mass_kg));
  m.modal.modes.push_back(
      mode_from_mass(Direction::kY, units::hz_to_rad_per_s(1.05 * hz), zeta, mass_kg));
  m.tool.teeth = 1;
  m.tool.diameter_m = 0.02;
  m.engagement.radial_immersion = immersion;
  m.engagement.down_milling = down;
  m.cutting.kt_pa = 6e8;
  m.cutting.kr_pa = 2e8;
  return m;
}

struct StepCase {
  std::string name;
  MillingProcess model;
  double rpm_min, rpm_max;
  int speeds;
  double depth_max_m;
  /// The old default (1/32 of the structure's period everywhere, no check) is more than this
  /// too deep at some speed: the case tests something.
  double old_error_above;
};

std::vector<StepCase> step_cases() {
  std::vector<StepCase> cases;
  // One tooth at a/D 0.03 on modes 10× softer than Insperger–Stépán's (a tenth of the mass):
  // pockets up to 17 mm where the cut is 20× stiffer than the structure in a 20° window.
  cases.push_back({"1 tooth a/D 0.03, 10x softer", one_tooth(922.0, 0.011, 0.003993, 0.03, true),
                   20000.0, 60000.0, 41, 30e-3, 0.005});
  // The same structure 10× softer by its frequency (291 Hz): the error grows with the speed.
  cases.push_back({"1 tooth a/D 0.03, 291 Hz", one_tooth(291.6, 0.011, 0.03993, 0.03, true),
                   30000.0, 60000.0, 31, 30e-3, 0.005});
  // Up-milling, damped (ζ 0.03) 600 Hz modes: a 25 mm pocket at 35 000 rpm.
  cases.push_back({"1 tooth a/D 0.03 up, 600 Hz", one_tooth(600.0, 0.03, 0.01, 0.03, false),
                   20000.0, 60000.0, 41, 30e-3, 0.02});
  // Three teeth at a/D 0.05 up-milling, Insperger–Stépán structure.
  MillingProcess three = insperger_benchmark(0.05, true, false);
  three.tool.teeth = 3;
  cases.push_back({"3 teeth a/D 0.05 up", three, 5000.0, 25000.0, 41, 10e-3, 0.0});
  // Uneven pitch (80/100/80/100°), the x mode only, a/D 0.05 down.
  MillingProcess uneven = insperger_benchmark(0.05, false, true);
  uneven.tool.teeth = 4;
  uneven.tool.pitch_rad = {units::deg_to_rad(80.0), units::deg_to_rad(100.0),
                           units::deg_to_rad(80.0), units::deg_to_rad(100.0)};
  cases.push_back({"uneven pitch a/D 0.05", uneven, 8000.0, 20000.0, 13, 20e-3, 0.0});
  // A window inside the cut (5 teeth, 30–150°), three modes.
  MillingProcess window;
  window.modal.modes.push_back(
      mode_from_mass(Direction::kX, units::hz_to_rad_per_s(600.0), 0.03, 0.5));
  window.modal.modes.push_back(
      mode_from_mass(Direction::kY, units::hz_to_rad_per_s(660.0), 0.03, 0.5));
  window.modal.modes.push_back(
      mode_from_mass(Direction::kX, units::hz_to_rad_per_s(1400.0), 0.04, 0.3));
  window.tool.teeth = 5;
  window.tool.diameter_m = 0.02;
  window.engagement.entry_rad = units::deg_to_rad(30.0);
  window.engagement.exit_rad = units::deg_to_rad(150.0);
  window.cutting.kt_pa = 8e8;
  window.cutting.kr_pa = 2.4e8;
  cases.push_back({"5 teeth 30-150 deg", window, 3000.0, 9000.0, 25, 10e-3, 0.0});
  return cases;
}

// The converged reference at one speed: the search to 1e-7 on a grid sized by the cut at the
// boundary (5 % deeper), 1/128 of the periods, 64 steps per window (4× the check's step).
double converged_depth(const MillingProcess& m, double rpm, double depth_max_m, double near_m) {
  MillingStabilityOptions o;
  o.depth_max_m = depth_max_m;
  o.rel_tol = 1e-7;
  o.fd.max_step_fraction = 1.0 / 128.0;
  o.fd.window_steps = 64;
  o.fd.cutting_depth_m = 1.05 * near_m;
  o.fd.refinements = 0;
  return milling_critical_depth(m, rpm, o, near_m).boundary.depth_m;
}

// The default's accuracy asserted here: rel_tol (0.1 %) of the converged depth. What the
// construction guarantees is looser (docs/models/milling-stability.md: the search's tolerance
// plus the convergence test's); measured on these cases, 0.012 % at most.
double stated_tolerance(double depth, const MillingStabilityOptions& o) {
  return o.rel_tol * depth;
}

TEST(StepConvergence, LobesAndCheckAgreeAndAreWithinTheStatedToleranceOfTheConvergedDepth) {
  for (const StepCase& c : step_cases()) {
    MillingStabilityOptions o;
    o.depth_max_m = c.depth_max_m;
    MillingStabilityOptions old = o;
    old.fd.window_steps = 0;
    old.fd.refinements = 0;
    LobesOptions grid;
    grid.rpm_min = c.rpm_min;
    grid.rpm_max = c.rpm_max;
    grid.rpm_steps = c.speeds;
    grid.refine = false;
    const LobesReport lobes = trace_milling_lobes(c.model, o, grid);
    const LobesReport before = trace_milling_lobes(c.model, old, grid);
    ASSERT_EQ(lobes.status, LobesStatus::kSuccess) << c.name << ": " << lobes.message;
    double worst_old = 0.0;
    int found = 0;
    for (std::size_t i = 0; i < lobes.points.size(); ++i) {
      const LobePoint& p = lobes.points[i];
      const std::string where = c.name + " at " + std::to_string(p.rpm) + " rpm";
      EXPECT_FALSE(p.boundary.unconverged) << where;
      const MillingBoundary check = milling_critical_depth(c.model, p.rpm, o);
      ASSERT_EQ(check.boundary.found, p.boundary.found) << where;
      if (!p.boundary.found) continue;  // stable to the limit
      ++found;
      const double reference = converged_depth(c.model, p.rpm, c.depth_max_m, p.boundary.depth_m);
      EXPECT_NEAR(p.boundary.depth_m, reference, stated_tolerance(reference, o)) << where;
      EXPECT_NEAR(check.boundary.depth_m, reference, stated_tolerance(reference, o)) << where;
      EXPECT_EQ(check.boundary.bifurcation, p.boundary.bifurcation) << where;
      worst_old = std::max(worst_old, before.points[i].boundary.depth_m / reference - 1.0);
    }
    EXPECT_GT(worst_old, c.old_error_above) << c.name;
    EXPECT_GE(found, c.speeds * 3 / 4) << c.name;
  }
}

TEST(StepConvergence, HelicalCutterConvergesToo) {
  // A 30° helix at a/D 0.05 (the coefficient depends on the depth): the helical searches size
  // and check their grid the same way.
  MillingProcess m = insperger_benchmark(0.05);
  m.tool.helix_rad = units::deg_to_rad(30.0);
  MillingStabilityOptions o;
  o.depth_max_m = 10e-3;
  int found = 0;
  for (double rpm : {7000.0, 11000.0, 14000.0, 18640.0, 24000.0}) {
    const CriticalDepth b = milling_critical_depth(m, rpm, o).boundary;
    if (!b.found) continue;  // stable to the limit
    ++found;
    EXPECT_FALSE(b.unconverged) << rpm;
    const double reference = converged_depth(m, rpm, o.depth_max_m, b.depth_m);
    EXPECT_NEAR(b.depth_m, reference, stated_tolerance(reference, o)) << rpm << " rpm";
  }
  EXPECT_GE(found, 3);
}

TEST(StepConvergence, ContactStepsFollowTheStiffenedStructureAndTheWindow) {
  // The grid's steps where the tooth cuts, against the stiffened structure's fastest pole
  // computed here on each step's own coefficient (a second sampling of H: the step's mean,
  // where the grid takes quarter-window means; 10 % slack for the difference).
  const MillingProcess m = one_tooth(922.0, 0.011, 0.003993, 0.03, true);
  const DelayedSystem s = milling_system(m, 55000.0);
  int at_zero = 0;
  for (double depth : {0.0, 1e-3, 17e-3}) {
    FdOptions o;
    o.order = 2;
    o.max_step_fraction = 1.0 / 32.0;
    o.window_steps = 8;
    o.cutting_depth_m = depth;
    const FdGrid g = fd_grid(s, o);
    int contact = 0;
    double structure_rad_s = 0.0;
    {
      const Eigen::VectorXcd poles = s.A0.eigenvalues();
      structure_rad_s = poles.cwiseAbs().maxCoeff();
    }
    for (int j = 0; j < g.steps(); ++j) {
      const double t0 = g.nodes_s[static_cast<std::size_t>(j)];
      const double t1 = g.nodes_s[static_cast<std::size_t>(j + 1)];
      const double h = t1 - t0;
      EXPECT_LE(h, 1.0 / 32.0 * units::kTwoPi / structure_rad_s * (1.0 + 1e-9)) << j;
      const Eigen::MatrixXd H = s.H.mean(t0, t1);
      if (H.norm() == 0.0) continue;
      ++contact;
      if (depth == 0.0) continue;
      const Eigen::MatrixXd cut = s.A0 - depth * s.E * H * s.C;
      Eigen::ComplexEigenSolver<Eigen::MatrixXcd> eig(cut.cast<std::complex<double>>(), false);
      const double fastest = eig.eigenvalues().cwiseAbs().maxCoeff();
      EXPECT_LE(h, 1.1 / 32.0 * units::kTwoPi / fastest) << depth << " m, step " << j;
    }
    EXPECT_GE(contact, 8) << depth;
    if (depth == 0.0) at_zero = contact;
    // At 17 mm the cut is 20× stiffer than the structure: more steps than the window's 8.
    if (depth == 17e-3) {
      EXPECT_GT(contact, at_zero);
    }
  }
}

TEST(StepConvergence, AStepTooLongToConvergeIsReported) {
  // Steps of half the structure's period, one per window, and a single halving allowed: the
  // boundary moves by more than the tolerance, and says so — in `check` and in the lobes.
  const MillingProcess m = one_tooth(922.0, 0.011, 0.003993, 0.03, true);
  MillingStabilityOptions o;
  o.depth_max_m = 30e-3;
  o.fd.max_step_fraction = 0.5;
  o.fd.window_steps = 1;
  o.fd.refinements = 1;
  const CriticalDepth b = milling_critical_depth(m, 50000.0, o).boundary;
  ASSERT_TRUE(b.found);
  EXPECT_TRUE(b.unconverged);
  LobesOptions grid;
  grid.rpm_min = 45000.0;
  grid.rpm_max = 55000.0;
  grid.rpm_steps = 5;
  grid.refine = false;
  const LobesReport lobes = trace_milling_lobes(m, o, grid);
  EXPECT_EQ(lobes.status, LobesStatus::kTruncated);
  EXPECT_NE(lobes.message.find("time step was halved"), std::string::npos) << lobes.message;
  // Allowed five halvings, the same coarse start converges (to 1/64 of the period).
  o.fd.refinements = 5;
  const CriticalDepth three = milling_critical_depth(m, 50000.0, o).boundary;
  EXPECT_FALSE(three.unconverged);
  EXPECT_NEAR(three.depth_m, converged_depth(m, 50000.0, o.depth_max_m, three.depth_m),
              stated_tolerance(three.depth_m, o));
}

TEST(StepConvergence, OptionsOutOfRangeAreNamed) {
  FdOptions o;
  o.window_steps = -1;
  o.cutting_depth_m = -1e-3;
  o.refinements = 7;
  const std::vector<std::string> problems = o.validate();
  ASSERT_EQ(problems.size(), 3u);
  EXPECT_NE(problems[0].find("window_steps"), std::string::npos);
  EXPECT_NE(problems[1].find("cutting_depth_m"), std::string::npos);
  EXPECT_NE(problems[2].find("refinements"), std::string::npos);
}

}  // namespace
}  // namespace cutdyn
