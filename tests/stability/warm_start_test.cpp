// The warm-started depth search of the milling lobes (fd_critical_depth_from_hint,
// trace_milling_lobes) against the exhaustive one (coarse scan of 16 depths, then Brent) on the
// reference cases, and at the places where a warm start could go wrong: an unstable island
// below the neighbour's depth, hints far off, lobe cusps, flip/Hopf changes and speeds where an
// island grazes the unit circle. docs/models/milling-stability.md, "Warm-started depth search".
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/stability/full_discretization.hpp"
#include "cutdyn/stability/milling.hpp"
#include "support/reference_cases.hpp"

namespace cutdyn {
namespace {

using testing::confirming_grid;
using testing::four_mode_milling;
using testing::insperger_benchmark;

// Both searches stop with the root in a bracket of rel_tol times the upper end of the grid
// cell (0.1 % of at most 2× the depth), and interpolate in it: on the same boundary they
// agree to well within 0.3 %.
constexpr double kSameBoundary = 3e-3;

// The discretization of the lobes (the milling default: quadratic interpolation on 1/32 of
// the structural period).
const FdOptions kLobesFd = MillingStabilityOptions{}.fd;

struct Case {
  std::string name;
  MillingProcess model;
  double rpm_min, rpm_max;
  int speeds;
  double depth_max_m;
  bool refine = false;
};

MillingStabilityOptions fd_options(double depth_max_m, bool warm) {
  MillingStabilityOptions o;
  o.method = MillingMethod::kFullDiscretization;
  o.depth_max_m = depth_max_m;
  o.warm_start = warm;
  return o;
}

LobesReport lobes(const Case& c, bool warm) {
  LobesOptions g;
  g.rpm_min = c.rpm_min;
  g.rpm_max = c.rpm_max;
  g.rpm_steps = c.speeds;
  g.refine = c.refine;
  return trace_milling_lobes(c.model, fd_options(c.depth_max_m, warm), g);
}

// Whether `depth` is an upward crossing of the spectral radius at `rpm`: stable 0.2 % below it,
// unstable 0.2 % above it.
bool is_crossing(const MillingProcess& m, double rpm, double depth) {
  const auto rho = [&](double w) {
    return FdDiscretization(milling_system(m, rpm, w), confirming_grid(kLobesFd, depth))
        .spectral_radius_arnoldi(w)
        .value;
  };
  return rho(depth * (1.0 - 2e-3)) < 1.0 && rho(depth * (1.0 + 2e-3)) >= 1.0;
}

// The warm lobes against the exhaustive ones at every speed both have: the same boundary
// (found, depth to kSameBoundary, lobe, bifurcation and chatter frequency), or — where the
// exhaustive search's Brent step in a grid cell that holds an island landed on the island's
// upper crossing — a lower depth that is a true crossing; never a larger one. Returns the
// number of speeds compared; `lower` counts the second kind.
int expect_same_lobes(const Case& c, int* lower = nullptr) {
  const LobesReport old = lobes(c, false), warm = lobes(c, true);
  EXPECT_EQ(old.status, LobesStatus::kSuccess) << c.name;
  EXPECT_EQ(warm.status, LobesStatus::kSuccess) << c.name;
  int compared = 0, below = 0;
  std::size_t j = 0;
  for (const LobePoint& p : old.points) {
    while (j < warm.points.size() && warm.points[j].rpm < p.rpm) ++j;
    if (j == warm.points.size() || warm.points[j].rpm != p.rpm) continue;
    const LobePoint& q = warm.points[j];
    ++compared;
    const std::string where = c.name + " at " + std::to_string(p.rpm) + " rpm";
    EXPECT_EQ(q.boundary.found, p.boundary.found) << where;
    EXPECT_LE(q.boundary.depth_m, p.boundary.depth_m * (1.0 + kSameBoundary)) << where;
    if (q.boundary.depth_m < p.boundary.depth_m * (1.0 - kSameBoundary)) {
      ++below;
      EXPECT_TRUE(is_crossing(c.model, p.rpm, q.boundary.depth_m)) << where;
      continue;
    }
    EXPECT_EQ(q.lobe, p.lobe) << where;
    EXPECT_EQ(q.boundary.bifurcation, p.boundary.bifurcation) << where;
    EXPECT_NEAR(q.boundary.chatter_hz, p.boundary.chatter_hz, 5e-3 * p.boundary.chatter_hz)
        << where;
  }
  if (lower) *lower = below;
  return compared;
}

TEST(WarmStart, DefaultExampleLobesAreTheExhaustiveOnes) {
  // The embedded example (slotting benchmark, 200 speeds 5000–25 000 rpm, 1 mm), with the
  // adaptive refinement: the added speeds sit at every cusp between lobes.
  Case c{"slotting", insperger_benchmark(1.0), 5000.0, 25000.0, 200, 1e-3, true};
  EXPECT_GE(expect_same_lobes(c), 250);
}

TEST(WarmStart, UpAndDownMillingLobesAreTheExhaustiveOnes) {
  for (bool down : {true, false}) {
    Case c{down ? "a/D 0.5 down" : "a/D 0.5 up",
           insperger_benchmark(0.5, true, down),
           5000.0,
           25000.0,
           60,
           2e-3};
    EXPECT_EQ(expect_same_lobes(c), 60);
  }
}

TEST(WarmStart, LowImmersionFlipAndHopfLobesAreTheExhaustiveOnes) {
  // a/D 0.05, one direction: flip lobes between the Hopf lobes, and unstable islands (the
  // refinement adds the speeds where flip and Hopf take turns). Two refined speeds (5943 and
  // 7711 rpm, where flip and Hopf lobes cross) hold an island inside one 0.625 mm grid cell,
  // where the exhaustive search's Brent step returned the upper crossing (3.5 and 3.7 mm);
  // with the flip crossings below every answer, both searches return the lower one.
  Case c{"a/D 0.05 flip", insperger_benchmark(0.05, false), 5000.0, 25000.0, 60, 10e-3, true};
  int lower = 0;
  EXPECT_GE(expect_same_lobes(c, &lower), 60);
  EXPECT_EQ(lower, 0);
}

TEST(WarmStart, FourModeLobesAreTheExhaustiveOnes) {
  Case c{"four modes", four_mode_milling(0.5, true), 4000.0, 16000.0, 24, 0.03};
  EXPECT_EQ(expect_same_lobes(c), 24);
}

TEST(WarmStart, VariablePitchHelicalExampleLobesAreTheExhaustiveOnes) {
  // The milling-variable-pitch example: 4 teeth 70/110/70/110°, 30° helix, a/D 0.5 down — one
  // delay per tooth and a depth-dependent coefficient (the system rebuilt at each depth).
  MillingProcess m = insperger_benchmark(0.5);
  m.tool.teeth = 4;
  m.tool.helix_rad = units::deg_to_rad(30.0);
  for (double deg : {70.0, 110.0, 70.0, 110.0}) m.tool.pitch_rad.push_back(units::deg_to_rad(deg));
  Case c{"variable pitch", m, 4000.0, 12000.0, 24, 1e-3};
  EXPECT_EQ(expect_same_lobes(c), 24);
}

// ---- edge cases ---------------------------------------------------------------------------

// The low-immersion speed of MillingLobes.UnstableIslandAtLowImmersionIsNotSkipped: unstable
// in a band near 1.7–2.0 mm, stable above it up to about 4.5 mm.
struct Island {
  MillingProcess model = insperger_benchmark(0.05, false);
  double rpm = 10900.0;
  MillingStabilityOptions options = fd_options(10e-3, true);
};

TEST(WarmStart, IslandBelowTheNeighboursDepthIsFoundByTheGuard) {
  // A hint on the upper boundary (4.5 mm, as a neighbouring speed without the island would
  // give): the bracket forms there, and the guard's grid point in the island (1.875 mm) sends
  // the speed to the exhaustive search, which returns the island's lower edge.
  const Island is;
  const MillingBoundary old = milling_critical_depth(is.model, is.rpm, is.options);
  ASSERT_TRUE(old.boundary.found);
  ASSERT_LT(old.boundary.depth_m, 2.0e-3);
  for (double hint : {4.45e-3, 5e-3, 3e-3, 2.5e-3}) {
    const MillingBoundary warm = milling_critical_depth(is.model, is.rpm, is.options, hint);
    EXPECT_NEAR(warm.boundary.depth_m, old.boundary.depth_m, kSameBoundary * old.boundary.depth_m)
        << "hint " << hint;
    EXPECT_EQ(warm.boundary.bifurcation, old.boundary.bifurcation) << "hint " << hint;
  }
}

TEST(WarmStart, HintsFarOffGiveTheSameBoundary) {
  // Far below, far above, at the limit, on a grid point: the same boundary every time.
  const MillingProcess m = insperger_benchmark(1.0);
  const MillingStabilityOptions warm = fd_options(1e-3, true);
  for (double rpm : {5000.0, 9200.0, 13800.0, 21000.0}) {
    const MillingBoundary old = milling_critical_depth(m, rpm, warm);
    for (double hint : {1e-9, 1e-6, 0.5 * old.boundary.depth_m, 2.0 * old.boundary.depth_m,
                        1e-3 / 16, 1e-3, 2e-3}) {
      const MillingBoundary b = milling_critical_depth(m, rpm, warm, hint);
      EXPECT_NEAR(b.boundary.depth_m, old.boundary.depth_m, kSameBoundary * old.boundary.depth_m)
          << rpm << " rpm, hint " << hint;
      EXPECT_EQ(b.lobe, old.lobe) << rpm << " rpm, hint " << hint;
    }
  }
  EXPECT_THROW(milling_critical_depth(m, 5000.0, warm, 0.0), InvalidInput);
}

TEST(WarmStart, StableToTheLimitIsLeftToTheExhaustiveSearch) {
  // A limit below the boundary: no crossing near any hint, so the exhaustive search decides
  // (stable to the limit, found = false).
  const MillingProcess m = insperger_benchmark(1.0);
  const MillingStabilityOptions o = fd_options(0.04e-3, true);
  const MillingBoundary b = milling_critical_depth(m, 5000.0, o, 0.03e-3);
  EXPECT_FALSE(b.boundary.found);
  EXPECT_EQ(b.boundary.depth_m, 0.04e-3);
}

TEST(WarmStart, NeverLessConservativeWhereAnIslandGrazes) {
  // Around the island's speed at a/D 0.05 the island is born and dies (its depth band shrinks
  // to a point: ρ's local maximum grazes 1). 81 speeds 10 000–12 000 rpm: wherever warm and
  // exhaustive differ, the warm depth is the lower one and a true crossing (stable just below
  // it, unstable just above), never a larger depth.
  const Island is;
  Case c{"grazing", is.model, 10000.0, 12000.0, 81, 10e-3};
  const LobesReport old = lobes(c, false), warm = lobes(c, true);
  ASSERT_EQ(old.points.size(), warm.points.size());
  int islands = 0;
  for (std::size_t i = 0; i < old.points.size(); ++i) {
    const CriticalDepth& p = old.points[i].boundary;
    const CriticalDepth& q = warm.points[i].boundary;
    const double rpm = old.points[i].rpm;
    if (p.depth_m < 2.5e-3) ++islands;
    EXPECT_LE(q.depth_m, p.depth_m * (1.0 + kSameBoundary)) << rpm;
    if (std::abs(q.depth_m - p.depth_m) <= kSameBoundary * p.depth_m) continue;
    const FdDiscretization fd(milling_system(is.model, rpm), confirming_grid(kLobesFd, q.depth_m));
    EXPECT_LT(fd.spectral_radius_arnoldi(q.depth_m * (1.0 - 2e-3)).value, 1.0) << rpm;
    EXPECT_GE(fd.spectral_radius_arnoldi(q.depth_m * (1.0 + 2e-3)).value, 1.0) << rpm;
  }
  EXPECT_GT(islands, 0) << "no island in this speed range";
}

// ---- the pieces -------------------------------------------------------------------------

// Maps near a boundary (its depth at that speed, about): slotting at three speeds, low
// immersion on a flip and a Hopf lobe, four modes.
struct KrylovPoint {
  MillingProcess m;
  double rpm, depth;
};

std::vector<KrylovPoint> krylov_points() {
  return {{insperger_benchmark(1.0), 5000.0, 0.0475e-3},
          {insperger_benchmark(1.0), 9200.0, 0.5e-3},
          {insperger_benchmark(1.0), 24000.0, 0.3e-3},
          {insperger_benchmark(0.05, false), 10900.0, 1.9e-3},
          {insperger_benchmark(0.05, false), 16000.0, 1e-3},
          {four_mode_milling(0.5), 8000.0, 2e-3}};
}

TEST(WarmStart, KrylovRadiusIsSpectrasAndTheDenseOne) {
  // The unrestarted Arnoldi of dominant_multiplier against Spectra's restarted one and the
  // dense eigenvalues, on both sides of the boundary, slotting, low immersion and four modes.
  const std::vector<KrylovPoint> points = krylov_points();
  for (const KrylovPoint& p : points) {
    const FdDiscretization fd(milling_system(p.m, p.rpm), kLobesFd);
    for (double f : {0.5, 0.99, 1.0, 1.01, 2.0}) {
      const double w = f * p.depth;
      const DominantMultiplier k = fd.dominant_multiplier(w, RadiusSolver::kArnoldi);
      const double spectra = fd.spectral_radius_arnoldi(w).value;
      EXPECT_NEAR(k.radius, spectra, 1e-7) << p.rpm << " rpm, " << w;
      EXPECT_NEAR(k.radius, std::abs(k.mu), 1e-15);
      if (p.rpm == 24000.0 || p.rpm == 16000.0) {  // small enough for the dense matrix
        EXPECT_NEAR(k.radius, fd.spectral_radius(w), 1e-7) << p.rpm << " rpm, " << w;
      }
    }
  }
}

TEST(WarmStart, KrylovScheduleAndScreeningKeepTheRadius) {
  // When the Ritz values are first tested (ArnoldiOptions::first_test) does not change what is
  // accepted; a radius at the bracket's tolerance of 1e-8 is within 1e-5; a screened radius
  // (the guard's question, ρ < 0.99) is within 1e-4 of the full one and only given below
  // 0.99; at or above it the full tolerance decides. Depths from far below the boundary to
  // above it.
  const std::vector<KrylovPoint> points = krylov_points();
  int screened = 0, full = 0;
  long long loose_products = 0, full_products = 0;
  for (const KrylovPoint& p : points) {
    const FdDiscretization fd(milling_system(p.m, p.rpm), kLobesFd);
    for (double f : {0.05, 0.3, 0.6, 0.9, 0.97, 0.995, 1.0, 1.01, 1.5}) {
      const double w = f * p.depth;
      const DominantMultiplier reference = fd.dominant_multiplier(w, RadiusSolver::kArnoldi);
      ASSERT_TRUE(reference.krylov);
      // The Krylov radius against the dense matrix's: the residual test at 1e-10 leaves it
      // within a few times that (3.4e-10 at most here).
      if (f == 0.3 || f == 1.0 || f == 1.5) {
        const DominantMultiplier dense = fd.dominant_multiplier(w, RadiusSolver::kDense);
        EXPECT_NEAR(reference.radius, dense.radius, 1e-9 * dense.radius) << p.rpm << ", " << w;
      }
      for (int first : {3, 6, 9, 12, 20}) {
        ArnoldiOptions o;
        o.first_test = first;
        const DominantMultiplier k = fd.dominant_multiplier(w, RadiusSolver::kArnoldi, o);
        EXPECT_NEAR(k.radius, reference.radius, 1e-8) << p.rpm << " rpm, " << w << ", " << first;
        EXPECT_FALSE(k.screened);
      }
      // The bracket's tolerance (1e-8): the sign of ρ − 1 and a secant, ρ within 1e-5.
      ArnoldiOptions loose;
      loose.tolerance = 1e-8;
      const DominantMultiplier b = fd.dominant_multiplier(w, RadiusSolver::kArnoldi, loose);
      EXPECT_NEAR(b.radius, reference.radius, 1e-5) << p.rpm << " rpm, " << w;
      EXPECT_FALSE(b.screened);
      loose_products += b.operations;
      full_products += reference.operations;
      ArnoldiOptions o;
      o.screen_below = 0.99;
      const DominantMultiplier s = fd.dominant_multiplier(w, RadiusSolver::kArnoldi, o);
      if (s.screened) {
        ++screened;
        EXPECT_LT(s.radius, 0.99);
        EXPECT_LT(reference.radius, 0.99 + 1e-4);
        EXPECT_NEAR(s.radius, reference.radius, 1e-4) << p.rpm << " rpm, " << w;
        EXPECT_LE(s.operations, reference.operations);
      } else {
        ++full;
        EXPECT_NEAR(s.radius, reference.radius, 1e-8) << p.rpm << " rpm, " << w;
      }
      if (reference.radius < 0.98) {
        EXPECT_TRUE(s.screened) << p.rpm << " rpm, " << w;
      }
      if (reference.radius >= 0.99 + 1e-4) {
        EXPECT_FALSE(s.screened) << p.rpm << " rpm, " << w;
      }
    }
  }
  EXPECT_GT(screened, 10);
  EXPECT_GT(full, 10);
  EXPECT_LT(loose_products, full_products);  // the point of the looser tolerance
}

TEST(WarmStart, RadiusWithoutCuttingIsThatOfTheMap) {
  for (double rpm : {5000.0, 13000.0, 25000.0}) {
    const FdDiscretization fd(milling_system(insperger_benchmark(1.0), rpm), kLobesFd);
    EXPECT_NEAR(fd.radius_without_cutting(), fd.spectral_radius(0.0), 1e-10) << rpm;
  }
}

TEST(WarmStart, HintFromTheNeighbours) {
  LobePoint a{10000.0, {}, 1.0, 2}, b{10100.0, {}, 1.0, 2};
  a.boundary.found = b.boundary.found = true;
  a.boundary.depth_m = 1e-4;
  b.boundary.depth_m = 2e-4;
  a.boundary.bifurcation = b.boundary.bifurcation = Bifurcation::kHopf;
  EXPECT_EQ(milling_depth_hint(10200.0, {}), 0.0);
  EXPECT_EQ(milling_depth_hint(10200.0, {&b}), 2e-4);
  EXPECT_NEAR(milling_depth_hint(10200.0, {&b, &a}), 4e-4, 1e-15);  // the ratio carried on
  EXPECT_NEAR(milling_depth_hint(10050.0, {&a, &b}), std::sqrt(2.0) * 1e-4, 1e-15);
  b.lobe = 3;  // across a cusp: the smaller of the two around a refined speed
  EXPECT_EQ(milling_depth_hint(10050.0, {&a, &b}), 1e-4);
  EXPECT_EQ(milling_depth_hint(10200.0, {&b, &a}), 2e-4);
  b.boundary.found = false;
  EXPECT_EQ(milling_depth_hint(10200.0, {&b, &a}), 0.0);
}

TEST(WarmStart, ParabolaThroughThreeSpeedsOfOneLobeIsACloseHint) {
  // ln(depth) quadratic in the speed: the prediction from three speeds before is exact, and
  // close; with the third on another lobe (or bifurcation) it is the line through two, not close.
  const auto ln_depth = [](double rpm) {
    const double x = (rpm - 10000.0) / 100.0;
    return std::log(1e-4) + 0.3 * x - 0.05 * x * x;
  };
  LobePoint p[3];
  for (int i = 0; i < 3; ++i) {
    p[i] = LobePoint{10000.0 + 100.0 * i, {}, 1.0, 2};
    p[i].boundary.found = true;
    p[i].boundary.depth_m = std::exp(ln_depth(p[i].rpm));
    p[i].boundary.bifurcation = Bifurcation::kHopf;
  }
  const std::vector<const LobePoint*> near{&p[2], &p[1], &p[0]};  // nearest first
  const MillingDepthHint h = milling_depth_prediction(10300.0, near);
  EXPECT_TRUE(h.close);
  EXPECT_NEAR(h.depth_m, std::exp(ln_depth(10300.0)), 1e-12 * h.depth_m);
  EXPECT_EQ(milling_depth_hint(10300.0, near), h.depth_m);
  const double line = std::exp(2.0 * ln_depth(10200.0) - ln_depth(10100.0));
  p[0].boundary.bifurcation = Bifurcation::kFlip;
  EXPECT_FALSE(milling_depth_prediction(10300.0, near).close);
  EXPECT_NEAR(milling_depth_prediction(10300.0, near).depth_m, line, 1e-12 * line);
  p[0].boundary.bifurcation = Bifurcation::kHopf;
  p[0].lobe = 3;
  EXPECT_FALSE(milling_depth_prediction(10300.0, near).close);
  EXPECT_FALSE(milling_depth_prediction(10300.0, {&p[2], &p[1]}).close);  // two: the line
}

TEST(WarmStart, CloseHintsGiveTheSameBoundaryAndTwoRadiiWhenRight) {
  // A close hint is straddled first (0.45 tolerance on either side). Right (the boundary to
  // 1e-7): the search takes two radii, then the guard's grid points below. Wrong by a little or
  // by a lot, above or below: the same boundary as the exhaustive search, as for any hint.
  struct Point {
    MillingProcess model;
    double rpm, depth_max_m;
  };
  const std::vector<Point> points = {
      {insperger_benchmark(1.0), 5000.0, 1e-3},
      {insperger_benchmark(1.0), 13800.0, 1e-3},
      {insperger_benchmark(1.0), 21000.0, 1e-3},
      {insperger_benchmark(0.5, false), 9000.0, 5e-3},
      {insperger_benchmark(0.05, false), 10900.0, 10e-3},  // the island below the upper boundary
      {four_mode_milling(), 8000.0, 30e-3}};
  constexpr double kRelTol = 1e-3;
  constexpr int kCoarse = 16;
  for (const Point& p : points) {
    const DelayedSystem s = milling_system(p.model, p.rpm);
    FdOptions fd = kLobesFd;
    fd.depth_max_m = p.depth_max_m;
    fd.refinements = 0;  // the warm search's own radii (the convergence check adds its own)
    const CriticalDepth exact =
        fd_critical_depth_by_radius(s, fd, RadiusSolver::kArnoldi, 1e-7, kCoarse);
    const CriticalDepth old =
        fd_critical_depth_by_radius(s, fd, RadiusSolver::kArnoldi, kRelTol, kCoarse);
    ASSERT_TRUE(exact.found && old.found) << p.rpm;
    for (double off : {0.0, 2e-4, -2e-4, 3e-3, -3e-3, 0.05, -0.05, 0.5, -0.5}) {
      const double hint = exact.depth_m * (1.0 + off);
      const CriticalDepth warm = fd_critical_depth_from_hint(s, fd, RadiusSolver::kArnoldi,
                                                             kRelTol, kCoarse, hint, true);
      EXPECT_NEAR(warm.depth_m, old.depth_m, kSameBoundary * old.depth_m)
          << p.rpm << " rpm, hint off by " << off;
      EXPECT_EQ(warm.bifurcation, old.bifurcation) << p.rpm << " rpm, hint off by " << off;
      EXPECT_NEAR(warm.chatter_hz, old.chatter_hz, 5e-3 * old.chatter_hz) << p.rpm;
      if (off != 0.0) continue;
      const double cell = p.depth_max_m / kCoarse;
      const double straddle = 0.45 * kRelTol * cell * std::ceil(hint / cell - 1e-9);
      const long long guard = static_cast<long long>(std::ceil((hint - straddle) / cell)) - 1;
      // ... and the eigenvalue problem of the flip crossings below the answer.
      EXPECT_EQ(warm.evaluations, 2 + guard + 1) << p.rpm << " rpm";
    }
  }
}

TEST(WarmStart, AMapThatOverflowsIsUnstableNotAnError) {
  // A y mode of 20.7 N/m (6.2e-7 kg at 922 Hz): at 5000 rpm and 0.1 mm a unit vector grows
  // beyond 1e308 in one period of the linear interpolation's 355 steps (the quadratic one's
  // 178 stay below it). The radius is then infinite (never NaN, never an exception from
  // the eigenvalue solvers). The boundary lies near 1e-9 m, five orders below the first grid
  // point (6.25e-5 m), where it came back as 0 before the first cell was narrowed: now a true
  // crossing, to the tolerance, on both searches.
  MillingProcess m = insperger_benchmark(1.0);
  const double wn = units::hz_to_rad_per_s(testing::kInspergerHz);
  m.modal.modes[1] = mode_from_mass(Direction::kY, wn, testing::kInspergerDamping, 6.2e-7);
  const FdDiscretization fd(milling_system(m, 5000.0), FdOptions{});
  const DominantMultiplier d = fd.dominant_multiplier(1e-4, RadiusSolver::kArnoldi);
  EXPECT_TRUE(std::isinf(d.radius));
  // The other solvers: infinite too, or a huge finite radius where the dense eigenvalues of a
  // map of entries near 1e300 still come out finite; never NaN.
  EXPECT_GT(fd.spectral_radius_arnoldi(1e-4).value, 1e100);
  EXPECT_GT(fd.spectral_radius(1e-4), 1e100);
  for (bool warm : {false, true}) {
    LobesOptions g;
    g.rpm_min = 5000.0;
    g.rpm_max = 25000.0;
    g.rpm_steps = 12;
    g.refine = false;
    const LobesReport r = trace_milling_lobes(m, fd_options(1e-3, warm), g);
    for (const LobePoint& p : r.points) {
      ASSERT_TRUE(p.boundary.found) << p.rpm;
      EXPECT_TRUE(std::isfinite(p.boundary.depth_m) && p.boundary.depth_m > 0.0) << p.rpm;
      EXPECT_TRUE(std::isfinite(p.boundary.chatter_hz)) << p.rpm;
      EXPECT_TRUE(is_crossing(m, p.rpm, p.boundary.depth_m)) << p.rpm << " rpm, warm " << warm;
    }
  }
}

// The runs are cut from the speeds alone, so the lobes are the same, bit for bit, on any number
// of threads (a sweep under MPI gives each rank a share of the cores and must write the file of
// a single process).
TEST(WarmStart, LobesDoNotDependOnTheThreads) {
  LobesOptions g;
  g.rpm_min = 5000.0;
  g.rpm_max = 25000.0;
  g.rpm_steps = 120;
  std::vector<LobesReport> reports;
  for (int threads : {1, 2, 3, 5}) {
    g.threads = threads;
    reports.push_back(trace_milling_lobes(insperger_benchmark(1.0), fd_options(1e-3, true), g));
  }
  for (std::size_t k = 1; k < reports.size(); ++k) {
    ASSERT_EQ(reports[k].points.size(), reports[0].points.size());
    for (std::size_t i = 0; i < reports[0].points.size(); ++i) {
      const LobePoint &a = reports[0].points[i], &b = reports[k].points[i];
      EXPECT_EQ(a.rpm, b.rpm);
      EXPECT_EQ(a.boundary.depth_m, b.boundary.depth_m) << a.rpm << " rpm, run " << k;
      EXPECT_EQ(a.boundary.chatter_hz, b.boundary.chatter_hz) << a.rpm;
      EXPECT_EQ(a.lobe, b.lobe) << a.rpm;
    }
  }
}

TEST(WarmStart, RunsShareTheCostEqually) {
  std::vector<double> speeds;
  for (int i = 0; i < 200; ++i) speeds.push_back(5000.0 + 100.0 * i);
  const std::vector<int> starts = warm_run_starts(speeds);
  const int shares = 200 / kWarmRunLength;
  ASSERT_EQ(starts.size(), static_cast<std::size_t>(shares + kWarmTailRuns));
  EXPECT_EQ(starts.front(), 0);
  EXPECT_EQ(starts.back(), 200);
  double total = 0.0;
  for (double rpm : speeds) total += 1.0 / rpm;
  const double share = total / shares;
  for (std::size_t r = 0; r + 1 < starts.size(); ++r) {
    ASSERT_LT(starts[r], starts[r + 1]);
    double cost = 0.0;
    for (int i = starts[r]; i < starts[r + 1]; ++i)
      cost += 1.0 / speeds[static_cast<std::size_t>(i)];
    // Each run ends at the first speed that completes its share (the last share cut in
    // kWarmTailRuns): off by at most one speed.
    const bool tail = r + kWarmTailRuns >= starts.size() - 1;
    EXPECT_NEAR(cost, tail ? share / kWarmTailRuns : share, 1.0 / 5000.0) << "run " << r;
  }
  // Longer runs where the speeds are cheaper (higher), among the equal shares.
  EXPECT_GT(starts[starts.size() - kWarmTailRuns] - starts[starts.size() - kWarmTailRuns - 1],
            starts[1] - starts[0]);
  EXPECT_EQ(warm_run_starts({}), (std::vector<int>{0, 0}));
  EXPECT_EQ(warm_run_starts({1000.0, 2000.0}), (std::vector<int>{0, 2}));
  // Two shares: the second cut in three.
  EXPECT_EQ(warm_run_starts(std::vector<double>(32, 1024.0)),
            (std::vector<int>{0, 16, 22, 27, 32}));
}

}  // namespace
}  // namespace cutdyn
