#include "cutdyn/plan/bore_milling.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/detail/roots.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn {
namespace {

using units::kPi;

const char* const kWhere = "bore milling";

// A length for a machinist: millimetres to 4 significant digits ("21.59 mm"), never NaN (the
// callers pass finite values).
std::string mm_text(double m) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.4g", m * 1e3);
  return std::string(buffer) + " mm";
}

// "d = 500 mm, D = 200 mm, t = 5 mm, h = 10 mm": the inputs of the geometry.
std::string geometry_text(const BoreMillingCase& c) {
  return "d = " + mm_text(c.bore_diameter_m) + ", D = " + mm_text(c.cutter_diameter_m) +
         ", t = " + mm_text(c.allowance_m) + ", h = " + mm_text(c.offset_m);
}

// √x, or an error naming the condition x >= 0 of `formula` and the case's inputs.
double checked_sqrt(double x, const char* formula, const BoreMillingCase& c) {
  if (!(x >= 0.0)) {
    throw InvalidInput({std::string(formula) + ": the square root's argument is negative for " +
                        geometry_text(c) + ": the geometry is impossible"},
                       kWhere);
  }
  return std::sqrt(x);
}

double checked_asin(double x, const char* what, const BoreMillingCase& c) {
  if (!(x >= -1.0 && x <= 1.0)) {
    char ratio[32];
    std::snprintf(ratio, sizeof ratio, "%.4g", x);
    throw InvalidInput({std::string(what) + " = " + ratio +
                        ": must be at most 1 (the cut is wider than the cutter, D = " +
                        mm_text(c.cutter_diameter_m) + ")"},
                       kWhere);
  }
  return std::asin(x);
}

}  // namespace

std::vector<std::string> BoreMillingCase::validate() const {
  Validator v;
  v.require_positive("bore_diameter_m", bore_diameter_m, "m");
  v.require_positive("length_m", length_m, "m");
  v.require_positive("allowance_m", allowance_m, "m");
  v.require(allowance_m < 0.5 * bore_diameter_m, "allowance_m", allowance_m, "m",
            "must be less than the bore's radius");
  v.require_positive("cutter_diameter_m", cutter_diameter_m, "m");
  v.require(cutter_diameter_m < bore_diameter_m, "cutter_diameter_m", cutter_diameter_m, "m",
            "must be less than the bore diameter d = " + format_value(bore_diameter_m) + " m");
  v.require(std::isfinite(offset_m), "offset_m", offset_m, "m", "must be finite");
  // The cutter must fit in the bore: its centre is at sqrt(d²/4 − (D/2 + |h|)²) from the
  // plane through the bore's axis (docs/models/bore-milling.md, "Geometry").
  v.require(!(cutter_diameter_m < bore_diameter_m) ||
                0.5 * cutter_diameter_m + std::abs(offset_m) < 0.5 * bore_diameter_m,
            "offset_m", offset_m, "m",
            "the cutter does not fit: D/2 + |h| must be less than d/2 (D = " +
                format_value(cutter_diameter_m * 1e3) + " mm, d = " +
                format_value(bore_diameter_m * 1e3) + " mm)");
  v.require(teeth >= 1 && teeth <= 500, "teeth", teeth, "", "must be 1 to 500");
  v.require(lead_angle_rad > 0.0 && lead_angle_rad <= 0.5 * kPi, "lead_angle_rad", lead_angle_rad,
            "rad", "must be greater than 0 and at most π/2");
  v.require(std::abs(inclination_rad) < 0.5 * kPi, "inclination_rad", inclination_rad, "rad",
            "must be between −π/2 and π/2");
  v.require_positive("cutting_speed_m_per_s", cutting_speed_m_per_s, "m/s");
  v.require_positive("mean_chip_thickness_m", mean_chip_thickness_m, "m");
  v.require(accuracy_coefficient >= kAccuracyCoefficientMin &&
                accuracy_coefficient <= kAccuracyCoefficientMax,
            "accuracy_coefficient", accuracy_coefficient, "",
            "must be from 0.005 (finishing) to 0.1 (roughing), the source's range");
  return v.problems();
}

BoreEdgeSplit bore_edge_split(const BoreMillingCase& c) {
  const double D = c.cutter_diameter_m, d = c.bore_diameter_m, t = c.allowance_m;
  const double h = std::abs(c.offset_m);
  BoreEdgeSplit s;
  s.balanced_offset_m = (2 * d * t - t * t) / (8 * D);
  s.outer_limit_offset_m = (d * t - t * t) / (2 * D);
  // The point of the edge circle opposite the one that finishes the bore (α = π) reaches
  // R_π = sqrt(d²/4 − 2·D·|h|) (> 0 whenever the cutter fits, since D·(d − D) <= d²/4).
  const double r_pi = checked_sqrt(d * d / 4 - 2 * D * h, "d²/4 − 2·D·|h|", c);
  s.inner_entry_radius_m = std::max(r_pi, d / 2 - t);
  s.inner_depth_m = d / 2 - s.inner_entry_radius_m;
  s.outer_depth_m = t - s.inner_depth_m;
  return s;
}

double bore_q(const BoreMillingCase& c) {
  const double D = c.cutter_diameter_m, d = c.bore_diameter_m, h = std::abs(c.offset_m);
  const double r_e = bore_edge_split(c).inner_entry_radius_m;
  // Corrected eq. (1) [Zenkin2012]: the axial distance between the points where the inner
  // edges reach r_e ((d − t)/2 at the balanced offset), y_e from the cutter's plane.
  const double y_e = checked_sqrt(r_e * r_e - d * d / 4 + (D / 2 + h) * (D / 2 + h),
                                  "eq. (1), r_e² − d²/4 + (D/2 + |h|)²", c);
  const double e = y_e - h;
  // The equations take the inner edges' entry on the near half of the edge circle (the half
  // that finishes the bore, which eq. (3) describes); with a small cutter, a large allowance
  // and |h| > D/4 it lies on the far half and q of (1) is not the width of (3).
  if (e < 0.0) {
    throw InvalidInput({"eq. (1): the inner edges reach r_e = " + mm_text(r_e) +
                        " on the far half of the edge circle for " + geometry_text(c) +
                        " (|h| > D/4 with the outer edges cutting): outside the equations' "
                        "domain; use a larger cutter or an offset nearer h* = " +
                        mm_text(bore_edge_split(c).balanced_offset_m)},
                       kWhere);
  }
  return 2.0 * checked_sqrt(D * D / 4.0 - e * e, "eq. (1), D²/4 − (y_e − |h|)²", c);
}

double straightness_error(const BoreMillingCase& c, double s0) {
  const double D = c.cutter_diameter_m, d = c.bore_diameter_m, h = std::abs(c.offset_m);
  // [Zenkin2012, eq. 3], with |h| (−h is the mirror image of the same cut)
  const double root = checked_sqrt(D * D - s0 * s0, "eq. (3), D² − S0²", c);
  return d / 2 - checked_sqrt(h * root + (d * d - s0 * s0) / 4.0 - D * h,
                              "eq. (3), |h|·√(D² − S0²) + (d² − S0²)/4 − D·|h|", c);
}

double max_axial_feed(const BoreMillingCase& c) {
  if (const auto p = c.validate(); !p.empty()) throw InvalidInput(p, kWhere);
  const double target = c.accuracy_coefficient * c.allowance_m;
  const double top = c.cutter_diameter_m;  // (3) needs S0 <= D
  const auto g = [&](double s0) { return straightness_error(c, s0) - target; };
  // Δ1(0) = 0 < k·t; the first crossing on a scan, then Brent.
  double lo = 0.0, g_lo = g(0.0);
  constexpr int kScan = 64;
  for (int i = 1; i <= kScan; ++i) {
    const double s = top * i / kScan;
    double g_s;
    try {
      g_s = g(s);
    } catch (const InvalidInput&) {
      break;  // (3) leaves its domain before reaching k·t
    }
    if (g_s >= 0.0) {
      const auto root = brent_root(g, lo, g_lo, s, g_s, 1e-12 * s);
      return root ? root->x : s;
    }
    lo = s;
    g_lo = g_s;
  }
  throw InvalidInput({"accuracy_coefficient = " + format_value(c.accuracy_coefficient) +
                      ": the straightness error Δ1 of eq. (3) stays below k·t = " +
                      mm_text(target) + " for every axial feed S0 up to " + mm_text(lo) + " (" +
                      geometry_text(c) + "): the accuracy does not limit the feed"},
                     kWhere);
}

namespace {

// Eq. (4) with or without the d²k²t² term under the inner root.
double closed_form_feed(const BoreMillingCase& c, bool printed) {
  const double D = c.cutter_diameter_m, d = c.bore_diameter_m, h = std::abs(c.offset_m);
  const double kt = c.accuracy_coefficient * c.allowance_m;
  const double a = D * h - d * kt + kt * kt + 2 * h * h;
  const double inner = checked_sqrt(D * D * h * h + (printed ? d * d * kt * kt : 0.0) +
                                        4 * h * h * (D * h - d * kt + kt * kt + h * h),
                                    "eq. (4), inner root", c);
  return 2.0 * checked_sqrt(inner - a, "eq. (4), outer root", c);
}

}  // namespace

double max_axial_feed_closed_form(const BoreMillingCase& c) { return closed_form_feed(c, false); }

double max_axial_feed_printed_form(const BoreMillingCase& c) { return closed_form_feed(c, true); }

BoreMillingResult bore_milling(const BoreMillingCase& c, double s0, double n_o) {
  if (const auto p = c.validate(); !p.empty()) throw InvalidInput(p, kWhere);
  Validator v;
  v.require(s0 >= 0.0 && std::isfinite(s0), "axial_feed_m", s0, "m", "must not be negative");
  v.throw_if_any(kWhere);
  BoreMillingResult r;
  const double D = c.cutter_diameter_m, d = c.bore_diameter_m, t = c.allowance_m;
  const double phi = c.lead_angle_rad;
  r.q_m = bore_q(c);
  r.max_axial_feed_m = max_axial_feed(c);
  r.max_axial_feed_closed_form_m = max_axial_feed_closed_form(c);
  r.max_axial_feed_printed_form_m = max_axial_feed_printed_form(c);
  const BoreEdgeSplit split = bore_edge_split(c);
  r.inner_depth_m = split.inner_depth_m;
  r.outer_depth_m = split.outer_depth_m;
  r.balanced_offset_m = split.balanced_offset_m;
  // The source's equations share the allowance evenly between the edge sets; only the
  // balanced offset h* does (docs/models/bore-milling.md, "The offset h").
  const double h = std::abs(c.offset_m);
  if (split.outer_depth_m <= 0.0) {
    r.warnings.push_back("the offset |h| = " + mm_text(h) + " is at or beyond " +
                         mm_text(split.outer_limit_offset_m) +
                         ": the outer edges do not reach the blank and the inner edges take the "
                         "whole allowance t = " + mm_text(t) + " (the balanced offset is h* = " +
                         mm_text(split.balanced_offset_m) + ")");
  } else if (std::abs(split.inner_depth_m - 0.5 * t) > 0.05 * t) {
    r.warnings.push_back("the offset |h| = " + mm_text(h) + " splits the allowance unevenly: inner "
                         "edges " + mm_text(split.inner_depth_m) + ", outer edges " +
                         mm_text(split.outer_depth_m) + " (even at h* = " +
                         mm_text(split.balanced_offset_m) + ")");
  }
  r.axial_feed_m = s0 > 0.0 ? s0 : r.max_axial_feed_m;
  const double S0 = r.axial_feed_m;
  if (!(S0 < r.q_m)) {
    throw InvalidInput({"axial feed S0 = " + mm_text(S0) + ": must be less than q = " +
                        mm_text(r.q_m) + " (eq. 1), or the main edges leave uncut ridges (S0 < q)"},
                       kWhere);
  }
  // (2)
  r.milling_width_m = r.q_m / 2 + S0 / 2 +
                      S0 / (2 * kPi * d) *
                          (checked_sqrt(D * D - S0 * S0, "eq. (2), D² − S0²", c) -
                           checked_sqrt(D * D - r.q_m * r.q_m, "eq. (2), D² − q²", c));
  r.straightness_error_m = straightness_error(c, S0);  // (3)
  // A given S0 may break Δ1 <= k·t (a roughing pass that a finishing pass follows may do so
  // on purpose): reported, not refused (docs/models/bore-milling.md).
  const double kt = c.accuracy_coefficient * t;
  if (r.straightness_error_m > kt * (1.0 + 1e-9)) {
    r.accuracy_met = false;
    r.warnings.push_back(
        "the straightness error Δ1 = " + mm_text(r.straightness_error_m) +
        " at the axial feed S0 = " + mm_text(S0) + " is above k·t = " + mm_text(kt) +
        " (k = " + format_value(c.accuracy_coefficient) + ", t = " + mm_text(t) +
        "): the largest axial feed with Δ1 <= k·t is " + mm_text(r.max_axial_feed_m));
  }
  // n_u = v/(π·D); (8) n_o for the allowed mean chip thickness.
  r.cutter_rev_per_s = c.cutting_speed_m_per_s / (kPi * D);
  const double arcs = checked_asin(r.q_m / D, "q/D", c) + checked_asin(S0 / D, "S0/D", c);
  r.workpiece_rev_per_s = n_o > 0.0 ? n_o
                                    : c.mean_chip_thickness_m * r.cutter_rev_per_s * c.teeth * D *
                                          arcs / (2 * d * kPi * S0 * std::sin(phi));
  // (5)
  r.feed_per_tooth_m = std::sqrt(kPi * kPi * d * d + S0 * S0) * r.workpiece_rev_per_s /
                       (c.teeth * r.cutter_rev_per_s);
  r.max_chip_thickness_m = r.feed_per_tooth_m * std::sin(phi);
  // (6)
  r.contact_arc_m = D / 2 * arcs;
  const double deeper = std::max(split.inner_depth_m, split.outer_depth_m);
  r.chip_width_m = deeper / std::sin(phi);  // t/(2·sin φ) at h*
  // (7)
  r.mean_chip_thickness_m = 2 * d * r.workpiece_rev_per_s * kPi * S0 * std::sin(phi) /
                            (r.cutter_rev_per_s * c.teeth * D * arcs);
  // (9)
  r.path_per_edge_m =
      r.contact_arc_m * r.cutter_rev_per_s * c.length_m / (r.workpiece_rev_per_s * S0);
  // (10)–(12)
  r.edge_width_m = deeper / (std::sin(phi) * std::cos(c.inclination_rad));  // t/(2 sin φ cos λ) at h*
  r.engaged_fraction = arcs / (2 * kPi);
  r.teeth_in_cut = static_cast<int>(std::floor(c.teeth * r.engaged_fraction));
  r.total_edge_width_m = r.edge_width_m * c.teeth * r.engaged_fraction;
  // (13), (14)
  r.main_time_s = c.length_m / (r.workpiece_rev_per_s * S0) + 1.0 / r.workpiece_rev_per_s;
  const double half_xi = kPi * r.workpiece_rev_per_s / (c.teeth * r.cutter_rev_per_s);
  r.faceting_m = d / 2 * (1 - std::cos(half_xi));
  r.removal_rate_m3_per_s = kPi * (d * t - t * t) * S0 * r.workpiece_rev_per_s;
  return r;
}

std::vector<std::string> BoreMillingLimits::validate() const {
  Validator v;
  v.require(
      std::isfinite(offset_min_m) && std::isfinite(offset_max_m) && offset_max_m >= offset_min_m,
      "offset_max_m", offset_max_m, "m", "must be finite and at least offset_min_m");
  v.require_positive("cutting_speed_max_m_per_s", cutting_speed_max_m_per_s, "m/s");
  v.require_positive("cutter_rev_per_s_max", cutter_rev_per_s_max, "rev/s");
  v.require_positive("workpiece_rev_per_s_max", workpiece_rev_per_s_max, "rev/s");
  v.require_positive("faceting_max_m", faceting_max_m, "m");
  v.require_positive("max_chip_thickness_m", max_chip_thickness_m, "m");
  v.require(feed_samples >= 2 && feed_samples <= 100000, "feed_samples", feed_samples, "",
            "must be 2 to 100000");
  return v.problems();
}

namespace {

struct PlanPoint {
  double t0 = std::numeric_limits<double>::infinity();
  double n_u = 0.0, n_o = 0.0;
  std::vector<std::string> binding;
};

// The best speeds at (h, S0) and the main time; t0 = +∞ when infeasible.
PlanPoint plan_point(const BoreMillingCase& base, const BoreMillingLimits& lim, double h,
                     double s0) {
  PlanPoint p;
  BoreMillingCase c = base;
  c.offset_m = h;
  const double D = c.cutter_diameter_m, d = c.bore_diameter_m, z = c.teeth;
  const double sphi = std::sin(c.lead_angle_rad);
  double q = 0.0, delta1 = 0.0;
  try {
    if (!c.validate().empty()) return p;  // e.g. the cutter does not fit at this h
    // Both edge sets must cut (the plan's range of h).
    if (!(bore_edge_split(c).outer_depth_m > 0.0)) return p;
    q = bore_q(c);
    if (!(s0 > 0.0 && s0 < q && s0 <= D)) return p;
    delta1 = straightness_error(c, s0);
  } catch (const InvalidInput&) {
    return p;
  }
  const double kt = c.accuracy_coefficient * c.allowance_m;
  if (delta1 > kt * (1.0 + 1e-12)) return p;
  p.n_u = std::min(lim.cutter_rev_per_s_max, lim.cutting_speed_max_m_per_s / (kPi * D));
  const double arcs = std::asin(std::min(1.0, q / D)) + std::asin(s0 / D);
  // The largest n_o/n_u each limit allows.
  struct Limit {
    const char* name;
    double ratio;
  };
  const double faceting = 1.0 - 2.0 * lim.faceting_max_m / d;
  const Limit limits[] = {
      {"mean chip", c.mean_chip_thickness_m * z * D * arcs / (2 * d * kPi * s0 * sphi)},  // (7)
      {"max chip", lim.max_chip_thickness_m * z / (std::sqrt(kPi * kPi * d * d + s0 * s0) * sphi)},
      {"faceting", faceting <= -1.0 ? std::numeric_limits<double>::infinity()
                                    : z * std::acos(faceting) / kPi},  // (14)
      {"blank speed", lim.workpiece_rev_per_s_max / p.n_u}};
  double ratio = std::numeric_limits<double>::infinity();
  for (const Limit& l : limits) ratio = std::min(ratio, l.ratio);
  for (const Limit& l : limits)
    if (l.ratio <= ratio * (1.0 + 1e-6)) p.binding.push_back(l.name);
  if (delta1 >= kt * (1.0 - 1e-6)) p.binding.push_back("straightness");
  if (s0 >= q * (1.0 - 1e-6)) p.binding.push_back("uncut ridges");
  p.n_o = ratio * p.n_u;
  p.t0 = (c.length_m / s0 + 1.0) / p.n_o;  // (13)
  return p;
}

}  // namespace

double bore_milling_main_time(const BoreMillingCase& c, const BoreMillingLimits& limits, double h,
                              double s0) {
  return plan_point(c, limits, h, s0).t0;
}

BoreMillingPlan optimise_bore_milling(const BoreMillingCase& c, const BoreMillingLimits& lim) {
  Validator v;
  v.merge(c.validate());
  v.merge(lim.validate());
  v.throw_if_any(kWhere);
  BoreMillingPlan plan;
  const double D = c.cutter_diameter_m;
  // The offset: h* = (2dt − t²)/(8D), the one offset at which the two edge sets share the
  // allowance evenly as the equations assume (docs/models/bore-milling.md, "The offset h");
  // it must lie in the box of |h| (−h is the mirror image of +h). (Left free, the main time
  // falls as |h| grows towards the limit where the outer edges stop cutting: the optimum
  // would sit on that degenerate edge.)
  double h_lo = lim.offset_min_m, h_hi = lim.offset_max_m;
  if (h_hi <= 0.0) {
    h_lo = -lim.offset_max_m;
    h_hi = -lim.offset_min_m;
  } else if (h_lo < 0.0) {
    h_hi = std::max(h_hi, -h_lo);
    h_lo = 0.0;
  }
  BoreMillingCase probe = c;
  probe.offset_m = 0.0;
  const double h_star = bore_edge_split(probe).balanced_offset_m;
  if (!(h_star >= h_lo * (1.0 - 1e-12) && h_star <= h_hi * (1.0 + 1e-12))) {
    plan.reason = "the balanced offset h* = " + mm_text(h_star) +
                  " (the edge sets share the allowance evenly only there) is outside the box of "
                  "|h|, " + mm_text(h_lo) + " … " + mm_text(h_hi);
    return plan;
  }
  // For one h: the best S0 (scan, then Brent's minimiser around the best sample).
  const auto best_feed = [&](double h, double& t0) {
    const int n = lim.feed_samples;
    double best_s = 0.0;
    t0 = std::numeric_limits<double>::infinity();
    for (int i = 1; i <= n; ++i) {
      const double s = D * i / n;
      const double t = plan_point(c, lim, h, s).t0;
      ++plan.evaluations;
      if (t < t0) {
        t0 = t;
        best_s = s;
      }
    }
    if (!std::isfinite(t0)) return best_s;
    const double step = D / n;
    const double s = brent_minimum(
                         [&](double x) {
                           ++plan.evaluations;
                           return plan_point(c, lim, h, x).t0;
                         },
                         std::max(step * 1e-3, best_s - step), std::min(D, best_s + step), 1e-9 * D)
                         .x;
    const double t = plan_point(c, lim, h, s).t0;
    if (t < t0) {
      t0 = t;
      best_s = s;
    }
    return best_s;
  };
  double best_t;
  const double s0 = best_feed(h_star, best_t);
  if (!std::isfinite(best_t)) {
    plan.reason = "no axial feed at h* = " + mm_text(h_star) +
                  " meets every limit (accuracy, uncut ridges, chip thickness, faceting, speeds)";
    return plan;
  }
  const PlanPoint p = plan_point(c, lim, h_star, s0);
  plan.feasible = true;
  plan.chosen = c;
  plan.chosen.offset_m = h_star;
  plan.chosen.cutting_speed_m_per_s = kPi * D * p.n_u;
  plan.result = bore_milling(plan.chosen, s0, p.n_o);
  plan.binding = p.binding;
  return plan;
}

}  // namespace cutdyn
