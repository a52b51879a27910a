// Adaptive lobe tracing and the advice read off the lobes (stable ranges, pockets, the
// recommended speed), against a fine uniform grid and hand-built curves.
#include "cutdyn/stability/advice.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "cutdyn/stability/milling.hpp"
#include "cutdyn/stability/turning.hpp"
#include "support/reference_cases.hpp"

namespace cutdyn {
namespace {

// Conventional turning, table 2 of [Chikishev2018], by Tlusty's closed form.
LobePoint table2_point(double rpm) {
  TurningStabilityOptions o;
  o.method = TurningMethod::kClosedForm;
  const TurningBoundary b = turning_critical_depth(testing::table2_conventional(), rpm, o);
  return LobePoint{rpm, b.boundary, b.duty_cycle, b.lobe};
}

LobesOptions grid(double from, double to, int steps, bool refine) {
  LobesOptions o;
  o.rpm_min = from;
  o.rpm_max = to;
  o.rpm_steps = steps;
  o.refine = refine;
  o.refine_max_points = std::max(o.refine_max_points, steps);
  return o;
}

// The local maxima (stable-pocket peaks) of a traced curve inside [from, to].
std::vector<double> pocket_peaks(const std::vector<LobePoint>& p, double from, double to) {
  std::vector<double> peaks;
  for (std::size_t i = 1; i + 1 < p.size(); ++i) {
    if (p[i].rpm < from || p[i].rpm > to) continue;
    const double d = p[i].boundary.depth_m;
    if (d >= p[i - 1].boundary.depth_m && d > p[i + 1].boundary.depth_m) peaks.push_back(d);
  }
  return peaks;
}

TEST(LobeTracing, AdaptiveRefinementHoldsTheTruePocketPeaks) {
  // Near 700 rpm the default 200-speed grid has 1.6 speeds per lobe: it shows 3 of the 5
  // pockets between 620 and 780 rpm, one at 7.44 mm, where the true peaks (cusps) are
  // 10.03–11.38 mm. Truth: a uniform grid 400 times finer.
  const LobesReport fine = trace_lobes(table2_point, grid(600.0, 800.0, 80001, false));
  const LobesReport plain = trace_lobes(table2_point, grid(500.0, 5000.0, 200, false));
  const LobesReport traced = trace_lobes(table2_point, grid(500.0, 5000.0, 200, true));
  const std::vector<double> truth = pocket_peaks(fine.points, 620.0, 780.0);
  const std::vector<double> coarse = pocket_peaks(plain.points, 620.0, 780.0);
  const std::vector<double> adaptive = pocket_peaks(traced.points, 620.0, 780.0);
  ASSERT_GE(truth.size(), 5u);
  ASSERT_EQ(adaptive.size(), truth.size());
  for (std::size_t k = 0; k < truth.size(); ++k)
    EXPECT_NEAR(adaptive[k], truth[k], 0.003 * truth[k]) << "pocket " << k;
  // The plain grid misses pockets and shows others far too low.
  EXPECT_LT(coarse.size(), truth.size());
  ASSERT_FALSE(coarse.empty());
  EXPECT_LT(*std::min_element(coarse.begin(), coarse.end()),
            0.8 * *std::min_element(truth.begin(), truth.end()));
  // Ascending, the grid kept, and far fewer speeds than a uniform grid of the same resolution.
  for (std::size_t i = 1; i < traced.points.size(); ++i)
    ASSERT_LT(traced.points[i - 1].rpm, traced.points[i].rpm);
  EXPECT_LT(traced.points.size(), 1000u);
  for (const LobePoint& p : plain.points)
    EXPECT_TRUE(std::any_of(traced.points.begin(), traced.points.end(),
                            [&](const LobePoint& q) { return q.rpm == p.rpm; }));
}

TEST(LobeTracing, RefinementStopsAtItsLimits) {
  LobesOptions o = grid(500.0, 5000.0, 200, true);
  o.refine_max_points = 250;
  EXPECT_EQ(trace_lobes(table2_point, o).points.size(), 250u);
  o.refine_max_points = 20000;
  o.refine_levels = 0;
  EXPECT_EQ(trace_lobes(table2_point, o).points.size(), 200u);
}

LobePoint point(double rpm, double depth, bool found = true) {
  LobePoint p;
  p.rpm = rpm;
  p.boundary.depth_m = depth;
  p.boundary.found = found;
  return p;
}

TEST(Advice, PocketsAreProminentPeaksNotWobbles) {
  // Two lobes meeting at cusps: depth 1 + |sin| shaped, peaks of 2.0 and 1.5 at 30 and 70 rpm,
  // on a grid of 0.01 rpm with a ±0.05 % wobble (a depth search's tolerance) on every point.
  std::vector<LobePoint> p;
  for (int i = 0; i <= 10000; ++i) {
    const double rpm = 0.01 * i;
    const double shape = rpm < 50.0 ? 2.0 - std::abs(rpm - 30.0) / 30.0
                                    : 1.5 - std::abs(rpm - 70.0) / 60.0;
    LobePoint q;
    q.rpm = rpm;
    q.boundary.found = true;
    q.boundary.depth_m = 1e-3 * shape * (1.0 + 5e-4 * std::sin(2.3 * i) * std::cos(0.7 * i * i));
    p.push_back(q);
  }
  const std::vector<std::size_t> pockets = stable_pockets(p, 3);
  ASSERT_EQ(pockets.size(), 2u);
  EXPECT_NEAR(p[pockets[0]].rpm, 30.0, 0.1);
  EXPECT_NEAR(p[pockets[1]].rpm, 70.0, 0.1);
  // Without the wobble, and past 90 rpm a third lobe of depth 1.1 with a pocket (13.6 % above
  // its sides, at 95 rpm) and a notch-bounded bump of 1.8 % (at 98.5 rpm): the pocket counts,
  // the bump does not (kPocketProminence, 10 %).
  for (LobePoint& q : p) {
    const double rpm = q.rpm;
    const double third = 1.1 + 0.15 * std::max(0.0, 1.0 - std::abs(rpm - 95.0) / 2.0) +
                         0.02 * std::max(0.0, 1.0 - std::abs(rpm - 98.5) / 0.5);
    q.boundary.depth_m = 1e-3 * (rpm < 50.0   ? 2.0 - std::abs(rpm - 30.0) / 30.0
                                 : rpm < 90.0 ? 1.5 - std::abs(rpm - 70.0) / 60.0
                                              : third);
  }
  const std::vector<std::size_t> clean = stable_pockets(p, 5);
  ASSERT_EQ(clean.size(), 3u);
  EXPECT_NEAR(p[clean[0]].rpm, 30.0, 1e-9);
  EXPECT_NEAR(p[clean[1]].rpm, 70.0, 1e-9);
  EXPECT_NEAR(p[clean[2]].rpm, 95.0, 1e-9);
}

TEST(Advice, StableRangeEndsAreInterpolated) {
  // Depth 1 → 3 → 1 over 100…300 rpm in steps of 50: above 2 between 125 and 275 rpm.
  const std::vector<LobePoint> p{point(100, 1), point(150, 3), point(200, 3), point(250, 3),
                                 point(300, 1)};
  const auto r = stable_ranges(p, 2.0);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_DOUBLE_EQ(r[0].rpm_from, 125.0);
  EXPECT_DOUBLE_EQ(r[0].rpm_to, 275.0);
  // A range that runs to the end of the lobes stops there.
  const auto all = stable_ranges(p, 0.5);
  ASSERT_EQ(all.size(), 1u);
  EXPECT_DOUBLE_EQ(all[0].rpm_from, 100.0);
  EXPECT_DOUBLE_EQ(all[0].rpm_to, 300.0);
  EXPECT_TRUE(stable_ranges(p, 5.0).empty());
}

TEST(Advice, RecommendedSpeedKeepsAwayFromCliffs) {
  // A band whose best depth sits next to a cliff (910 rpm: 30 mm, 920 rpm: 5 mm) and a wide
  // band at 12 mm: for a 10 mm target the narrow deep band leaves at most 3.5 % in speed, the
  // wide one 20 % in depth and 14 % in speed (its centre is 210 rpm from 5 mm).
  std::vector<LobePoint> p;
  for (double n = 800; n <= 2000; n += 10) {
    double d = 5e-3;
    if (n >= 850 && n <= 910) d = 30e-3;
    if (n >= 1300 && n <= 1700) d = 12e-3;
    p.push_back(point(n, d));
  }
  const SpeedAdvice a = recommend_speed(p, 10e-3);
  ASSERT_TRUE(a.found);
  EXPECT_NEAR(a.rpm, 1500.0, 1e-9);
  EXPECT_NEAR(a.margin, 210.0 / 1500.0, 1e-12);
  EXPECT_NEAR(a.range.rpm_from, 1290.0 + 10.0 * 5.0 / 7.0, 1e-9);
  // Its definition, checked directly: every speed within ±ε has a depth of at least a(1 + ε).
  for (const LobePoint& q : p)
    if (std::abs(q.rpm - a.rpm) < a.margin * a.rpm * (1.0 - 1e-12)) {
      EXPECT_GE(q.boundary.depth_m, 10e-3 * (1.0 + a.margin) - 1e-15) << q.rpm;
    }
  EXPECT_FALSE(recommend_speed(p, 40e-3).found);
}

TEST(Advice, TurningRecommendationIsTheWideDeepBandNotTheCliffEdge) {
  // turning-conventional at 10 mm recommended 2761 rpm, 23 rpm inside a band whose next
  // speed is at 9.6 mm; 3951–4731 rpm is above the 30 mm limit.
  LobesOptions o = grid(500.0, 5000.0, 200, true);
  TurningStabilityOptions so;
  so.method = TurningMethod::kClosedForm;
  const LobesReport r = trace_lobes(table2_point, o);
  const SpeedAdvice a = recommend_speed(r.points, 10e-3);
  ASSERT_TRUE(a.found);
  EXPECT_GT(a.rpm, 3951.0);
  EXPECT_LT(a.rpm, 4731.0);
  EXPECT_GT(a.margin, 0.05);
  EXPECT_GT(a.range.rpm_from, 3900.0);
}

// The advice with its ends found, against a dense reference: every speed of the reference
// inside a stable range has a critical depth above the target, each end lies within the
// speed tolerance of the reference's crossing, and every speed within n·(1 ± ε) of the
// recommended one has a depth of at least a·(1 + ε) — what the points alone (linear between
// traced speeds, margins at traced speeds only) do not give on the same coarse grid.
struct Dense {
  std::vector<double> rpm, depth;
};

Dense dense_reference(const CriticalDepthAt& depth_at, double from, double to, int n) {
  Dense d;
  for (int i = 0; i <= n; ++i) {
    d.rpm.push_back(from + (to - from) * i / n);
    d.depth.push_back(depth_at(d.rpm.back()));
  }
  return d;
}

// The largest ε at speed n on the dense reference (its own resolution aside).
double dense_margin(const Dense& d, double n, double a) {
  double eps = 1.0;
  for (std::size_t i = 0; i < d.rpm.size(); ++i) {
    const double delta = std::abs(d.rpm[i] - n) / n;
    eps = std::min(eps, std::max(delta, d.depth[i] / a - 1.0));
  }
  return std::min({eps, (n - d.rpm.front()) / n, (d.rpm.back() - n) / n});
}

// Checks the resolved advice on `coarse` against `d` with the depth tolerance `depth_tol`
// (relative: the depth searches'); returns how many violations the points alone give.
int check_against_dense(const std::vector<LobePoint>& coarse, const CriticalDepthAt& depth_at,
                        const Dense& d, double a, double depth_tol) {
  const std::vector<SpeedRange> ranges = stable_ranges(coarse, a, depth_at);
  EXPECT_FALSE(ranges.empty());
  for (const SpeedRange& r : ranges) {
    for (std::size_t i = 0; i < d.rpm.size(); ++i)
      if (d.rpm[i] >= r.rpm_from && d.rpm[i] <= r.rpm_to) {
        EXPECT_GT(d.depth[i], a * (1.0 - depth_tol))
            << d.rpm[i] << " in " << r.rpm_from << "–" << r.rpm_to;
      }
  }
  const SpeedAdvice advice = recommend_speed(coarse, a, depth_at);
  EXPECT_TRUE(advice.found);
  const double n = advice.rpm, eps = advice.margin;
  for (std::size_t i = 0; i < d.rpm.size(); ++i)
    if (std::abs(d.rpm[i] - n) <= eps * n) {
      EXPECT_GE(d.depth[i], a * (1.0 + eps) * (1.0 - depth_tol)) << d.rpm[i] << " from " << n;
    }
  // The margin found is the one the dense reference gives at that speed (to its resolution).
  const double step = (d.rpm.back() - d.rpm.front()) / static_cast<double>(d.rpm.size() - 1);
  EXPECT_NEAR(eps, dense_margin(d, n, a), 2.0 * step / n + 2.0 * depth_tol + 1e-4) << n;
  EXPECT_LE(advice.range.rpm_from, n);
  EXPECT_GE(advice.range.rpm_to, n);
  // The points alone on the same grid: how often their ranges or margin are too wide.
  int violations = 0;
  for (const SpeedRange& r : stable_ranges(coarse, a))
    for (std::size_t i = 0; i < d.rpm.size(); ++i)
      violations += d.rpm[i] >= r.rpm_from && d.rpm[i] <= r.rpm_to && d.depth[i] <= a;
  const SpeedAdvice old = recommend_speed(coarse, a);
  for (std::size_t i = 0; i < d.rpm.size(); ++i)
    violations += std::abs(d.rpm[i] - old.rpm) <= old.margin * old.rpm &&
                  d.depth[i] < a * (1.0 + old.margin) * (1.0 - depth_tol);
  return violations;
}

TEST(Advice, EndsFoundHoldOnADenseReferenceInTurning) {
  // Tlusty's closed form (exact depths): 40 traced speeds (refined, as lobes draws them) over
  // 1000–5000 rpm, targets between the lowest depth and the pockets.
  const CriticalDepthAt depth_at = [](double rpm) { return table2_point(rpm).boundary.depth_m; };
  const LobesReport coarse = trace_lobes(table2_point, grid(1000.0, 5000.0, 40, true));
  const Dense d = dense_reference(depth_at, 1000.0, 5000.0, 40000);
  const double lowest = *std::min_element(d.depth.begin(), d.depth.end());
  int violations_alone = 0;
  for (double factor : {1.3, 2.0, 3.0}) {
    SCOPED_TRACE(factor);
    violations_alone += check_against_dense(coarse.points, depth_at, d, factor * lowest, 1e-9);
  }
  EXPECT_GT(violations_alone, 0);  // the points alone overstate some range or margin here
}

TEST(Advice, EndsFoundHoldOnADenseReferenceInMilling) {
  // The four-mode cutter, half immersion, full discretization (depths to 0.1 %): 30 traced
  // speeds (refined) over 6000–14 000 rpm against 800 evaluated ones.
  const MillingProcess model = testing::four_mode_milling(0.5);
  MillingStabilityOptions o;
  o.depth_max_m = 10e-3;
  o.rel_tol = 1e-3;
  o.coarse_steps = 16;
  const CriticalDepthAt depth_at = [&](double rpm) {
    return milling_critical_depth(model, rpm, o).boundary.depth_m;
  };
  const LobesReport coarse = trace_lobes(
      [&](double rpm) {
        return LobePoint{rpm, milling_critical_depth(model, rpm, o).boundary};
      },
      grid(6000.0, 14000.0, 30, true));
  const Dense d = dense_reference(depth_at, 6000.0, 14000.0, 800);
  const double lowest = *std::min_element(d.depth.begin(), d.depth.end());
  int violations_alone = 0;
  for (double factor : {1.2, 1.6}) {
    SCOPED_TRACE(factor);
    violations_alone += check_against_dense(coarse.points, depth_at, d, factor * lowest, 2e-3);
  }
  EXPECT_GT(violations_alone, 0);  // here too (20 reference speeds on 2026-11-28)
}

}  // namespace
}  // namespace cutdyn
