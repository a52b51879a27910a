// Flip islands: every depth at which −1 is a multiplier of the full discretization's period
// map, from one linear eigenvalue problem (FdDiscretization::first_flip_depth), and the depth
// searches that use it so that an unstable island between two points of their depth grid is
// not stepped over. docs/models/milling-stability.md, "Unstable islands".
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <string>
#include <vector>

#include "cutdyn/core/units.hpp"
#include "cutdyn/modal/modal_model.hpp"
#include "cutdyn/stability/full_discretization.hpp"
#include "cutdyn/stability/milling.hpp"
#include "support/reference_cases.hpp"

namespace cutdyn {
namespace {

using testing::confirming_grid;
using testing::insperger_benchmark;

// The multipliers of the dense transition matrix at `depth`.
Eigen::VectorXcd multipliers(const FdDiscretization& fd, double depth) {
  return fd.transition_matrix(depth).eigenvalues();
}

// The number of real multipliers beyond `edge` (−1: below it; +1: above it), counted where
// |Im μ| < 1e-9.
int beyond(const Eigen::VectorXcd& mu, double edge = -1.0) {
  int count = 0;
  for (Eigen::Index i = 0; i < mu.size(); ++i)
    if (std::abs(mu(i).imag()) < 1e-9 && mu(i).real() * edge > 1.0) ++count;
  return count;
}

// 3 teeth, a/D 0.1 down-milling, modes of 700 and 720 Hz (ζ 0.015, 0.1 kg): at 29 090 rpm a
// flip island (0.71 mm) lies far below the next crossing (1.43 mm).
MillingProcess three_teeth() {
  MillingProcess m;
  m.modal.modes.push_back(
      mode_from_mass(Direction::kX, units::hz_to_rad_per_s(700.0), 0.015, 0.1));
  m.modal.modes.push_back(
      mode_from_mass(Direction::kY, units::hz_to_rad_per_s(720.0), 0.015, 0.1));
  m.tool.teeth = 3;
  m.tool.diameter_m = 0.02;
  m.engagement.radial_immersion = 0.1;
  m.cutting.kt_pa = 7e8;
  m.cutting.kr_pa = 2.1e8;
  return m;
}

// The Insperger–Stépán structure (x and y) at a/D 0.05 with a 30° helix, 20 mm cutter: the
// coefficient depends on the depth.
MillingProcess helical_low_immersion() {
  MillingProcess m = insperger_benchmark(0.05);
  m.tool.diameter_m = 0.02;
  m.tool.helix_rad = units::deg_to_rad(30.0);
  return m;
}

// 4 teeth at 80/100/80/100°, the Insperger–Stépán structure in x only, a/D 0.05 down: one
// delay per tooth, the period a revolution.
MillingProcess uneven_pitch() {
  MillingProcess m = insperger_benchmark(0.05, false);
  m.tool.teeth = 4;
  for (double deg : {80.0, 100.0, 80.0, 100.0}) m.tool.pitch_rad.push_back(units::deg_to_rad(deg));
  return m;
}

TEST(FlipIslands, FirstRealCrossingIsWhereMinusOrPlusOneBecomesAMultiplier) {
  // Against the dense transition matrix's eigenvalues (a second way): at the depth found, −1
  // (flip) or +1 (fold) is a multiplier (to 1e-8); 0.2 % below it no real multiplier lies
  // beyond it, 0.2 % above it one does. Order 1 and 2, one mode and two, two, three and four
  // teeth, even and uneven pitch.
  struct Case {
    std::string name;
    MillingProcess model;
    double rpm, below;
    int order;
    Bifurcation kind = Bifurcation::kFlip;
  };
  const std::vector<Case> cases{
      {"a/D 0.05 x, order 2", insperger_benchmark(0.05, false), 10888.9, 20e-3, 2},
      {"a/D 0.05 x, order 1", insperger_benchmark(0.05, false), 10888.9, 20e-3, 1},
      {"a/D 0.05 x and y", insperger_benchmark(0.05), 18640.0, 5e-3, 2},
      {"3 teeth a/D 0.1", three_teeth(), 29090.0, 10e-3, 2},
      // μ = +1 per revolution: a flip of the half-revolution that the pitch pattern repeats
      {"uneven pitch 80/100°, a/D 0.05 x", uneven_pitch(), 27000.0, 20e-3, 2, Bifurcation::kFold},
  };
  for (const Case& c : cases) {
    FdOptions o = MillingStabilityOptions{}.fd;
    o.order = c.order;
    const FdDiscretization fd(milling_system(c.model, c.rpm), o);
    const CriticalDepth crossing = fd.first_real_crossing(c.below, c.kind);
    ASSERT_TRUE(crossing.found) << c.name;
    EXPECT_EQ(crossing.bifurcation, c.kind) << c.name;
    const double edge = c.kind == Bifurcation::kFlip ? -1.0 : 1.0;
    const Eigen::VectorXcd at = multipliers(fd, crossing.depth_m);
    EXPECT_LT((at.array() - edge).abs().minCoeff(), 1e-8) << c.name;
    EXPECT_EQ(beyond(multipliers(fd, crossing.depth_m * (1.0 - 2e-3)), edge), 0) << c.name;
    EXPECT_EQ(beyond(multipliers(fd, crossing.depth_m * (1.0 + 2e-3)), edge), 1) << c.name;
    // The vibration of a flip is at an odd multiple of half the period's frequency, of a fold
    // at a multiple of it (the period: a tooth's, a revolution's with uneven pitch).
    const double per_period =
        c.rpm / 60.0 * (c.model.tool.even_pitch() ? c.model.tool.teeth : 1);
    const double ratio = crossing.chatter_hz / per_period;
    const double off = c.kind == Bifurcation::kFlip ? 0.5 : 0.0;
    EXPECT_NEAR(std::remainder(ratio - off, 1.0), 0.0, 1e-6) << c.name << ": " << ratio;
  }
}

TEST(FlipIslands, NoneBelowTheFirstFlip) {
  // Below the first flip depth there is none: asked for one below it, the answer is "none",
  // and the dense matrix agrees (no real multiplier beyond −1 on a scan of 50 depths).
  const MillingProcess m = insperger_benchmark(0.05, false);
  const FdDiscretization fd(milling_system(m, 10888.9), MillingStabilityOptions{}.fd);
  const CriticalDepth first = fd.first_real_crossing(20e-3);
  ASSERT_TRUE(first.found);
  const CriticalDepth none = fd.first_real_crossing(first.depth_m * 0.99);
  EXPECT_FALSE(none.found);
  EXPECT_EQ(none.depth_m, first.depth_m * 0.99);
  for (int i = 1; i <= 50; ++i)
    EXPECT_EQ(beyond(multipliers(fd, first.depth_m * 0.99 * i / 50)), 0) << i;
}

// ---- the searches -------------------------------------------------------------------------

// Both searches stop with the root in a bracket of rel_tol times the upper end of the grid
// cell (0.1 % of at most 2× the depth): on one boundary they agree to well within 0.3 %.
constexpr double kSameBoundary = 3e-3;

struct IslandCase {
  std::string name;
  MillingProcess model;
  double rpm_min, rpm_max;
  int speeds;
  double depth_max_m;
};

// Cases with flip (and, with uneven pitch, fold) islands below a deeper boundary, each speed
// range around speeds where the depth grid (16 points to the limit) steps over the island.
std::vector<IslandCase> island_cases() {
  MillingProcess one_tooth = insperger_benchmark(0.05, false, false);
  one_tooth.tool.teeth = 1;
  return {
      {"2 teeth a/D 0.05 x", insperger_benchmark(0.05, false), 10850.0, 10950.0, 11, 20e-3},
      {"3 teeth a/D 0.1", three_teeth(), 29060.0, 29120.0, 13, 10e-3},
      {"2 teeth a/D 0.05, 30° helix", helical_low_immersion(), 18620.0, 18660.0, 9, 10e-3},
      {"1 tooth a/D 0.05 up", one_tooth, 12528.0, 12632.0, 9, 20e-3},
      {"uneven pitch a/D 0.05", uneven_pitch(), 8940.0, 9044.0, 9, 20e-3},
      // islands of a complex pair (ρ > 1 at 4.09–4.89 mm between the grid points 3.75 and
      // 5 mm at 12 788 rpm; at 16.42–17.42 mm between 16.25 and 17.5 mm at 15 336 rpm)
      {"uneven pitch, Hopf island", uneven_pitch(), 12736.0, 12840.0, 5, 20e-3},
      {"uneven pitch, Hopf island below a fold", uneven_pitch(), 15284.0, 15388.0, 5, 20e-3},
      // a flip island (10.53–11.10 mm at 12 640 rpm) that the coefficient at the answer's
      // depth does not have
      {"2 teeth a/D 0.05, 30° helix, deep", helical_low_immersion(), 12600.0, 12680.0, 5, 20e-3},
  };
}

MillingStabilityOptions search_options(double depth_max_m, bool crossings = true) {
  MillingStabilityOptions o;
  o.depth_max_m = depth_max_m;
  o.fd.flip_crossings = crossings;
  return o;
}

TEST(FlipIslands, LobesAreCheckAtEverySpeedAndNeverTooDeep) {
  // At every speed: the lobes (warm-started search) and `check` (the search on its own) give
  // the same boundary; a scan of the spectral radius at 300 depths up to it (a second way)
  // finds no unstable depth below it; it is a crossing (stable 0.3 % below, unstable 0.3 %
  // above). And the cases do hold islands that the depth grid steps over: at some speed of
  // each, the grid point above the answer is stable, or the search without the
  // real-multiplier crossings answers more than 10 % deeper.
  for (const IslandCase& c : island_cases()) {
    LobesOptions grid;
    grid.rpm_min = c.rpm_min;
    grid.rpm_max = c.rpm_max;
    grid.rpm_steps = c.speeds;
    grid.refine = false;
    const MillingStabilityOptions o = search_options(c.depth_max_m);
    const LobesReport lobes = trace_milling_lobes(c.model, o, grid);
    ASSERT_EQ(lobes.status, LobesStatus::kSuccess) << c.name;
    int stepped_over = 0;
    const double cell = c.depth_max_m / o.coarse_steps;
    for (const LobePoint& p : lobes.points) {
      const std::string where = c.name + " at " + std::to_string(p.rpm) + " rpm";
      const MillingBoundary check = milling_critical_depth(c.model, p.rpm, o);
      ASSERT_TRUE(check.boundary.found && p.boundary.found) << where;
      EXPECT_NEAR(p.boundary.depth_m, check.boundary.depth_m,
                  kSameBoundary * check.boundary.depth_m)
          << where;
      EXPECT_EQ(p.boundary.bifurcation, check.boundary.bifurcation) << where;
      const double depth = std::min(p.boundary.depth_m, check.boundary.depth_m);
      const auto rho = [&](double w) {
        return FdDiscretization(milling_system(c.model, p.rpm, w), confirming_grid(o.fd, depth))
            .spectral_radius_arnoldi(w)
            .value;
      };
      constexpr int kScan = 300;
      for (int i = 1; i <= kScan; ++i) {
        const double w = depth * (1.0 - kSameBoundary) * i / kScan;
        ASSERT_LT(rho(w), 1.0) << where << ", unstable at " << w * 1e3 << " mm";
      }
      EXPECT_GE(rho(depth * (1.0 + kSameBoundary)), 1.0) << where;
      const MillingBoundary without =
          milling_critical_depth(c.model, p.rpm, search_options(c.depth_max_m, false));
      const double grid_above = cell * std::ceil(depth / cell);
      if (without.boundary.depth_m > depth * (1.0 + 0.1) || rho(grid_above) < 1.0) ++stepped_over;
    }
    EXPECT_GE(stepped_over, 1) << c.name << ": no island stepped over";
  }
}

}  // namespace
}  // namespace cutdyn
