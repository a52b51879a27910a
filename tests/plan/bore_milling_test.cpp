#include "cutdyn/plan/bore_milling.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn {
namespace {

using units::kPi;

// The example case (examples/bore-plan.toml): d = 500 mm, L = 300 mm, t = 5 mm, D = 200 mm, z = 8, φ = 60°, λ = 0,
// v = 120 m/min, a_cp = 0.2 mm, k = 0.05; the offset at h* = (2dt − t²)/(8D) = 3.109 mm, where
// the two edge sets share the allowance evenly (the example's former 10 mm is beyond
// (dt − t²)/(2D) = 6.188 mm, where the outer edges no longer cut).
constexpr double kBalancedOffset = (2 * 0.5 * 0.005 - 0.005 * 0.005) / (8 * 0.2);
constexpr double kOuterLimitOffset = (0.5 * 0.005 - 0.005 * 0.005) / (2 * 0.2);

BoreMillingCase example() {
  BoreMillingCase c;
  c.bore_diameter_m = 0.5;
  c.length_m = 0.3;
  c.allowance_m = 0.005;
  c.cutter_diameter_m = 0.2;
  c.teeth = 8;
  c.offset_m = kBalancedOffset;
  c.lead_angle_rad = units::deg_to_rad(60.0);
  c.inclination_rad = 0.0;
  c.cutting_speed_m_per_s = 2.0;
  c.mean_chip_thickness_m = 0.2e-3;
  c.accuracy_coefficient = 0.05;
  return c;
}

// The points of the edge circle, from the geometry alone (docs/models/bore-milling.md,
// "Geometry"): the circle of radius D/2 in the plane at x0 = sqrt(d²/4 − (D/2 + |h|)²) from the
// bore's axis, centred |h| from it; the point at angle α is at radius
// R(α) = sqrt(x0² + (|h| + (D/2)·cos α)²) and axial position (D/2)·sin α.
double radius_at(const BoreMillingCase& c, double alpha) {
  const double d = c.bore_diameter_m, D = c.cutter_diameter_m, h = std::abs(c.offset_m);
  const double x0_sq = d * d / 4 - (D / 2 + h) * (D / 2 + h);
  const double y = h + D / 2 * std::cos(alpha);
  return std::sqrt(x0_sq + y * y);
}

TEST(BoreMilling, WidthOfCutPassesThePapersOwnConsistencyCheck) {
  // By the definition of q, eq. (3) at S0 = q must give Δ1 = t/2 (the inner edges' share):
  // the printed eq. (1) gave 22.1 mm for t/2 = 2.5 mm at h* (and q = 199.66 mm at h = 10 mm).
  // The corrected (1), over a grid of d, D, t and h (h from 0 to just below the limit where
  // the outer edges stop cutting, and its mirror −h): Δ1(q) = the inner edges' depth, t/2 at
  // h*, to 1e-9.
  int checked = 0;
  for (double d : {0.3, 0.5, 1.2}) {
    for (double D_ratio : {0.2, 0.4, 0.7}) {
      for (double t : {0.002, 0.005, 0.012}) {
        BoreMillingCase c = example();
        c.bore_diameter_m = d;
        c.cutter_diameter_m = D_ratio * d;
        c.allowance_m = t;
        const double D = c.cutter_diameter_m;
        const double h_star = (2 * d * t - t * t) / (8 * D);
        const double h_limit = (d * t - t * t) / (2 * D);
        for (double h : {0.0, 0.5 * h_star, h_star, 0.5 * (h_star + h_limit), 0.99 * h_limit}) {
          for (double sign : {1.0, -1.0}) {
            c.offset_m = sign * h;
            const BoreEdgeSplit split = bore_edge_split(c);
            if (h > D / 4) {
              // A small cutter with a large allowance: the inner edges enter on the far half
              // of the edge circle, outside the equations' domain, and (1) says so.
              EXPECT_THROW(bore_q(c), InvalidInput) << "d " << d << " D " << D << " h " << h;
              ++checked;
              continue;
            }
            const double q = bore_q(c);
            EXPECT_NEAR(straightness_error(c, q), split.inner_depth_m, 1e-9 * t)
                << "d " << d << " D " << D << " t " << t << " h " << c.offset_m;
            if (h == h_star) {
              EXPECT_NEAR(split.inner_depth_m, t / 2, 1e-12);
            }
            ++checked;
          }
        }
      }
    }
  }
  EXPECT_EQ(checked, 270);
  // By hand at h*: r_e = 247.5 mm; y_e = √(247.5² − 250² + 103.109²); q = 2√(100² − (y_e −
  // 3.109)²), and the geometry's own circle reaches 247.5 mm at axial ±q/2.
  const BoreMillingCase c = example();
  const double h_mm = kBalancedOffset * 1e3;
  const double y_e = std::sqrt(247.5 * 247.5 - 250.0 * 250.0 + (100.0 + h_mm) * (100.0 + h_mm));
  const double q_mm = 2 * std::sqrt(100.0 * 100.0 - (y_e - h_mm) * (y_e - h_mm));
  EXPECT_NEAR(bore_q(c), q_mm * 1e-3, 1e-15);
  const double alpha = std::asin(q_mm / 200.0);
  EXPECT_NEAR(radius_at(c, alpha), 0.2475, 1e-12);
}

TEST(BoreMilling, TheEdgeSetsShareTheAllowanceEvenlyOnlyAtTheBalancedOffset) {
  // R_π, the radius the opposite point of the circle reaches, from the geometry: the split.
  BoreMillingCase c = example();
  for (double h : {0.0, 1e-3, kBalancedOffset, 5e-3, kOuterLimitOffset, 10e-3, 40e-3}) {
    c.offset_m = h;
    const BoreEdgeSplit s = bore_edge_split(c);
    const double r_pi = radius_at(c, kPi);
    EXPECT_NEAR(s.inner_entry_radius_m, std::max(r_pi, 0.245), 1e-12) << h;
    EXPECT_NEAR(s.inner_depth_m + s.outer_depth_m, 0.005, 1e-15) << h;
    EXPECT_NEAR(s.balanced_offset_m, kBalancedOffset, 1e-15);
    EXPECT_NEAR(s.outer_limit_offset_m, kOuterLimitOffset, 1e-15);
  }
  // Even at h*: b = t/(2·sin φ·cos λ) = 2.887 mm, no warning.
  c.offset_m = kBalancedOffset;
  BoreMillingResult r = bore_milling(c);
  EXPECT_NEAR(r.inner_depth_m, 2.5e-3, 1e-12);
  EXPECT_NEAR(r.edge_width_m, 0.005 / (2 * std::sin(kPi / 3)), 1e-12);
  EXPECT_TRUE(r.warnings.empty());
  // At h = 10 mm the outer edges do not reach the blank: the inner edges take all 5 mm
  // (b = 5.774 mm, not 2.887), and the report says so.
  c.offset_m = 10e-3;
  r = bore_milling(c);
  EXPECT_NEAR(r.outer_depth_m, 0.0, 1e-15);
  EXPECT_NEAR(r.edge_width_m, 0.005 / std::sin(kPi / 3), 1e-12);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("the outer edges do not reach the blank"), std::string::npos);
  // In between: an uneven split is named.
  c.offset_m = 1e-3;
  r = bore_milling(c);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("splits the allowance unevenly"), std::string::npos)
      << r.warnings[0];
}

TEST(BoreMilling, NegativeOffsetIsTheMirrorImage) {
  // −h and +h are the same cut mirrored: h = −10 mm used with its sign gave an S0 whose Δ1 was
  // 0.306 mm > k·t; h = −100 mm, the mirror of a valid +100 mm, was refused.
  for (double h : {2e-3, 10e-3, 100e-3}) {
    BoreMillingCase plus = example(), minus = example();
    plus.offset_m = h;
    minus.offset_m = -h;
    const BoreMillingResult a = bore_milling(plus), b = bore_milling(minus);
    EXPECT_DOUBLE_EQ(b.q_m, a.q_m) << h;
    EXPECT_DOUBLE_EQ(b.max_axial_feed_m, a.max_axial_feed_m) << h;
    EXPECT_DOUBLE_EQ(b.straightness_error_m, a.straightness_error_m) << h;
    EXPECT_LE(b.straightness_error_m, 0.05 * 0.005 * (1 + 1e-9)) << h;
    EXPECT_DOUBLE_EQ(b.main_time_s, a.main_time_s) << h;
  }
}

TEST(BoreMilling, TheCutterMustFitInTheBore) {
  // D/2 + |h| < d/2: D = 450 mm with h = 30 mm in a 500 mm bore returned a plan.
  BoreMillingCase c = example();
  c.cutter_diameter_m = 0.45;
  for (double h : {30e-3, -30e-3, 25e-3}) {
    c.offset_m = h;
    try {
      bore_milling(c);
      FAIL() << "expected InvalidInput for h = " << h;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find("the cutter does not fit: D/2 + |h| must be less than "
                                           "d/2 (D = 450 mm, d = 500 mm)"),
                std::string::npos)
          << e.what();
    }
  }
  c.offset_m = 20e-3;
  EXPECT_NO_THROW(bore_milling(c));
}

TEST(BoreMilling, CorrectedClosedFormIsTheExactInversion) {
  // Eq. (4) without the d²k²t² term under the inner root is the exact inversion of (3) at
  // Δ1 = k·t; as printed it is too large (+0.05 … +41 %; a factor √2 at h = 0 for small k·t),
  // so it breaks the accuracy it stands for.
  for (double k : {0.1, 0.05, 0.02, 0.005}) {
    for (double h_mm : {0.0, 1.0, 2.0, kBalancedOffset * 1e3, 6.0}) {
      BoreMillingCase c = example();
      c.accuracy_coefficient = k;
      c.offset_m = h_mm * 1e-3;
      const double s0 = max_axial_feed(c);
      const double kt = k * c.allowance_m;
      EXPECT_NEAR(straightness_error(c, s0), kt, 1e-9 * kt) << "k " << k << " h " << h_mm;
      EXPECT_LT(straightness_error(c, 0.999 * s0), kt);
      EXPECT_GT(straightness_error(c, 1.001 * s0), kt);
      EXPECT_NEAR(max_axial_feed_closed_form(c), s0, 1e-9 * s0) << "k " << k << " h " << h_mm;
      const double printed = max_axial_feed_printed_form(c);
      EXPECT_GT(printed, s0 * 1.0004) << "k " << k << " h " << h_mm;
      EXPECT_GT(straightness_error(c, std::min(printed, 0.999 * c.cutter_diameter_m)), kt);
      if (h_mm == 0.0) {
        EXPECT_NEAR(printed / s0, std::sqrt(2.0), 0.01) << k;
      }
      if (s0 < bore_q(c)) {
        const BoreMillingResult r = bore_milling(c);
        EXPECT_DOUBLE_EQ(r.max_axial_feed_printed_form_m, printed);
        EXPECT_DOUBLE_EQ(r.max_axial_feed_m, s0);
      }
    }
  }
}

TEST(BoreMilling, Equations7And8InvertEachOtherAndBothFormsOf9Agree) {
  const BoreMillingCase c = example();
  const double s0 = 0.5 * bore_q(c);
  const BoreMillingResult r = bore_milling(c, s0);
  // (8) gives n_o for the case's a_cp, (7) gives back that a_cp.
  EXPECT_NEAR(r.mean_chip_thickness_m, c.mean_chip_thickness_m, 1e-15);
  // (8)'s second form: n_o = 500·a_cp·z·v·(asin(q/D) + asin(S0/D))/(d·π²·S0·sin φ), with v in
  // m/min, a_cp, d, S0 in mm and n_o in rev/min.
  const double arcs = std::asin(r.q_m / c.cutter_diameter_m) + std::asin(s0 / c.cutter_diameter_m);
  const double n_o_rpm =
      500 * 0.2 * 8 * 120.0 * arcs / (500.0 * kPi * kPi * s0 * 1e3 * std::sin(c.lead_angle_rad));
  EXPECT_NEAR(r.workpiece_rev_per_s * 60.0, n_o_rpm, 1e-12 * n_o_rpm);
  // (9): l·n_u·L/(n_o·S0) = π·d·L·sin φ/(a_cp·z).
  EXPECT_NEAR(r.path_per_edge_m,
              kPi * c.bore_diameter_m * c.length_m * std::sin(c.lead_angle_rad) /
                  (c.mean_chip_thickness_m * c.teeth),
              1e-9 * r.path_per_edge_m);
  // (13): the cutter passes L at S0 per revolution, plus one revolution.
  EXPECT_NEAR(r.main_time_s * r.workpiece_rev_per_s, c.length_m / s0 + 1.0, 1e-12);
  // (11)–(12): z' = floor(z·p), b0 = b·z·p.
  EXPECT_EQ(r.teeth_in_cut, static_cast<int>(std::floor(c.teeth * r.engaged_fraction)));
  EXPECT_NEAR(r.total_edge_width_m, r.edge_width_m * c.teeth * r.engaged_fraction, 1e-15);
  // (14) by hand: ξ/2 = π·n_o/(z·n_u).
  const double half_xi = kPi * r.workpiece_rev_per_s / (c.teeth * r.cutter_rev_per_s);
  EXPECT_NEAR(r.faceting_m, 0.25 * (1 - std::cos(half_xi)), 1e-15);
}

TEST(BoreMilling, UncutRidgesAreRefused) {
  const BoreMillingCase c = example();
  try {
    bore_milling(c, 1.01 * bore_q(c));
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("uncut ridges (S0 < q)"), std::string::npos) << e.what();
  }
}

TEST(BoreMilling, Equation3OutsideItsDomainAndAnAccuracyThatDoesNotLimit) {
  BoreMillingCase c = example();
  const auto message = [&](auto call) {
    try {
      call();
    } catch (const InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  // D² − S0² < 0: a feed wider than the cutter.
  EXPECT_NE(message([&] { straightness_error(c, 0.3); }).find("eq. (3), D² − S0²"),
            std::string::npos);
  // |h|·√(D² − S0²) + (d² − S0²)/4 − D·|h| < 0: a far offset (one the case would refuse: the
  // cutter does not fit; eq. (3) on its own still names its root).
  c.offset_m = 10.0;
  EXPECT_NE(message([&] {
              straightness_error(c, 0.15);
            }).find("eq. (3), |h|·√(D² − S0²) + (d² − S0²)/4 − D·|h|"),
            std::string::npos);
  // h = 0: Δ1(S0 = D) = d/2 − √(d² − D²)/2 = 20.87 mm, below k·t = 0.1·240 mm = 24 mm: the
  // accuracy does not limit the feed (k at the top of its range, a very large allowance).
  c = example();
  c.offset_m = 0.0;
  c.allowance_m = 0.24;
  c.accuracy_coefficient = 0.1;
  EXPECT_NE(message([&] { max_axial_feed(c); }).find("the accuracy does not limit the feed"),
            std::string::npos);
}

// mm to 4 significant digits, as the messages print lengths.
std::string mm4(double m) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", m * 1e3);
  return std::string(b) + " mm";
}

// A given axial feed above the largest one breaks Δ1 <= k·t: the plan is computed (an expert
// may rough beyond the finishing accuracy on purpose) and warned about, naming Δ1, k·t and
// the largest feed that keeps the accuracy; at or below that feed there is no warning.
TEST(BoreMilling, AFeedThatBreaksTheAccuracyIsWarnedAbout) {
  const BoreMillingCase c = example();
  const double s_max = max_axial_feed(c);
  const double kt = 0.05 * 0.005;  // 0.25 mm
  for (double s0 : {0.5 * s_max, s_max}) {
    const BoreMillingResult r = bore_milling(c, s0);
    EXPECT_TRUE(r.accuracy_met) << s0;
    EXPECT_TRUE(r.warnings.empty()) << s0;
  }
  const double s0 = 1.2 * s_max;
  ASSERT_LT(s0, bore_q(c));
  const BoreMillingResult r = bore_milling(c, s0);
  EXPECT_FALSE(r.accuracy_met);
  EXPECT_DOUBLE_EQ(r.axial_feed_m, s0);
  EXPECT_DOUBLE_EQ(r.straightness_error_m, straightness_error(c, s0));
  EXPECT_GT(r.straightness_error_m, kt * 1.01);
  ASSERT_EQ(r.warnings.size(), 1u);
  const std::string& w = r.warnings[0];
  EXPECT_NE(w.find("Δ1 = " + mm4(r.straightness_error_m)), std::string::npos) << w;
  EXPECT_NE(w.find("k·t = 0.25 mm"), std::string::npos) << w;
  EXPECT_NE(w.find("S0 = " + mm4(s0)), std::string::npos) << w;
  EXPECT_NE(w.find("the largest axial feed with Δ1 <= k·t is " + mm4(s_max)), std::string::npos)
      << w;
}

// k outside the source's range (0.1 roughing … 0.005 finishing) is refused, naming the range.
TEST(BoreMilling, AccuracyCoefficientOutsideTheSourcesRangeIsRefused) {
  for (double k : {0.004, 0.101, 0.5}) {
    BoreMillingCase c = example();
    c.accuracy_coefficient = k;
    try {
      bore_milling(c);
      FAIL() << "expected InvalidInput for k = " << k;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find("must be from 0.005 (finishing) to 0.1 (roughing)"),
                std::string::npos)
          << e.what();
    }
  }
  for (double k : {0.005, 0.1}) {
    BoreMillingCase c = example();
    c.accuracy_coefficient = k;
    EXPECT_NO_THROW(bore_milling(c)) << k;
  }
}

TEST(BoreMilling, ErrorsPrintMillimetres) {
  const BoreMillingCase c = example();
  try {
    bore_milling(c, 0.25);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("axial feed S0 = 250 mm: must be less than q = " + mm4(bore_q(c))),
              std::string::npos)
        << m;
  }
}

TEST(BoreMilling, OutOfRangeInputsAreListed) {
  BoreMillingCase c = example();
  c.cutter_diameter_m = 0.6;  // larger than the bore
  c.lead_angle_rad = 0.0;
  c.accuracy_coefficient = 2.0;
  try {
    bore_milling(c);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    const std::string all = e.what();
    EXPECT_NE(all.find("cutter_diameter_m"), std::string::npos) << all;
    EXPECT_NE(all.find("lead_angle_rad"), std::string::npos) << all;
    EXPECT_NE(all.find("accuracy_coefficient"), std::string::npos) << all;
  }
}

BoreMillingLimits limits() {
  BoreMillingLimits l;
  l.offset_min_m = 0.0;
  l.offset_max_m = 0.04;
  l.cutting_speed_max_m_per_s = 2.5;     // 150 m/min
  l.cutter_rev_per_s_max = 10.0;         // 600 rpm
  l.workpiece_rev_per_s_max = 5.0 / 60;  // 5 rpm
  l.faceting_max_m = 0.01e-3;            // Δ2 <= 0.01 mm
  l.max_chip_thickness_m = 1.5e-3;
  return l;
}

TEST(BoreMillingPlan, OptimumMeetsEveryConstraintAndBeatsAFineGrid) {
  const BoreMillingCase c = example();
  const BoreMillingLimits l = limits();
  const BoreMillingPlan plan = optimise_bore_milling(c, l);
  ASSERT_TRUE(plan.feasible);
  const BoreMillingResult& r = plan.result;
  // Every constraint, recomputed from the chosen parameters by the plain equations.
  const double kt = c.accuracy_coefficient * c.allowance_m;
  EXPECT_LE(r.straightness_error_m, kt * (1 + 1e-9));
  EXPECT_LT(r.axial_feed_m, r.q_m);
  EXPECT_LE(r.mean_chip_thickness_m, c.mean_chip_thickness_m * (1 + 1e-9));
  EXPECT_LE(r.max_chip_thickness_m, l.max_chip_thickness_m * (1 + 1e-9));
  EXPECT_LE(r.faceting_m, l.faceting_max_m * (1 + 1e-9));
  EXPECT_LE(r.workpiece_rev_per_s, l.workpiece_rev_per_s_max * (1 + 1e-9));
  EXPECT_LE(r.cutter_rev_per_s, l.cutter_rev_per_s_max * (1 + 1e-9));
  EXPECT_LE(plan.chosen.cutting_speed_m_per_s, l.cutting_speed_max_m_per_s * (1 + 1e-9));
  EXPECT_NEAR(plan.chosen.offset_m, kBalancedOffset, 1e-15);  // h*: the even split
  EXPECT_NEAR(r.inner_depth_m, 0.5 * c.allowance_m, 1e-12);
  EXPECT_TRUE(r.warnings.empty());
  EXPECT_FALSE(plan.binding.empty());
  // No worse than a fine grid of S0 in (0, D] at h*.
  double grid = std::numeric_limits<double>::infinity();
  for (int j = 1; j <= 20000; ++j)
    grid = std::min(grid, bore_milling_main_time(c, l, kBalancedOffset,
                                                 c.cutter_diameter_m * j / 20000.0));
  ASSERT_TRUE(std::isfinite(grid));
  EXPECT_LE(r.main_time_s, grid * (1 + 1e-9));
  EXPECT_NEAR(r.main_time_s, bore_milling_main_time(c, l, plan.chosen.offset_m, r.axial_feed_m),
              1e-9 * r.main_time_s);
}

TEST(BoreMillingPlan, NoFeasiblePointIsReportedNotThrown) {
  BoreMillingCase c = example();
  BoreMillingLimits l = limits();
  // The box does not hold h* = 3.109 mm.
  l.offset_min_m = -0.101;
  l.offset_max_m = -0.099;
  const BoreMillingPlan plan = optimise_bore_milling(c, l);
  EXPECT_FALSE(plan.feasible);
  EXPECT_NE(plan.reason.find("the balanced offset h* = 3.109 mm"), std::string::npos)
      << plan.reason;
  // A negative box is its mirror: −4 … 0 mm plans as 0 … 4 mm.
  l = limits();
  l.offset_min_m = -0.004;
  l.offset_max_m = 0.0;
  const BoreMillingPlan mirrored = optimise_bore_milling(c, l);
  l.offset_min_m = 0.0;
  l.offset_max_m = 0.004;
  const BoreMillingPlan direct = optimise_bore_milling(c, l);
  ASSERT_TRUE(mirrored.feasible && direct.feasible);
  EXPECT_NEAR(mirrored.result.main_time_s, direct.result.main_time_s,
              1e-9 * direct.result.main_time_s);
}

}  // namespace
}  // namespace cutdyn
