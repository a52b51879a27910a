#include "cutdyn/plan/bore_milling.hpp"

#include <cmath>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/roots.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn {
namespace {

using units::kPi;

const char* const kWhere = "bore milling";

// √x, or an error naming the condition x >= 0 of `formula` and the case's inputs.
double checked_sqrt(double x, const char* formula, const BoreMillingCase& c) {
  if (!(x >= 0.0)) {
    throw InvalidInput(
        {std::string(formula) + ": the square root's argument is " + format_value(x) +
         " (< 0) for d = " + format_value(c.bore_diameter_m) +
         " m, D = " + format_value(c.cutter_diameter_m) + " m, t = " + format_value(c.allowance_m) +
         " m, h = " + format_value(c.offset_m) + " m: the geometry is impossible"},
        kWhere);
  }
  return std::sqrt(x);
}

double checked_asin(double x, const char* what, const BoreMillingCase& c) {
  if (!(x >= -1.0 && x <= 1.0)) {
    throw InvalidInput({std::string(what) + " = " + format_value(x) +
                        ": must be at most 1 (the cut is wider than the cutter, D = " +
                        format_value(c.cutter_diameter_m) + " m)"},
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
  v.require(teeth >= 1 && teeth <= 500, "teeth", teeth, "", "must be 1 to 500");
  v.require(std::isfinite(offset_m), "offset_m", offset_m, "m", "must be finite");
  v.require(lead_angle_rad > 0.0 && lead_angle_rad <= 0.5 * kPi, "lead_angle_rad", lead_angle_rad,
            "rad", "must be greater than 0 and at most π/2");
  v.require(std::abs(inclination_rad) < 0.5 * kPi, "inclination_rad", inclination_rad, "rad",
            "must be between −π/2 and π/2");
  v.require_positive("cutting_speed_m_per_s", cutting_speed_m_per_s, "m/s");
  v.require_positive("mean_chip_thickness_m", mean_chip_thickness_m, "m");
  v.require(accuracy_coefficient > 0.0 && accuracy_coefficient < 1.0, "accuracy_coefficient",
            accuracy_coefficient, "", "must be greater than 0 and less than 1");
  return v.problems();
}

double bore_q(const BoreMillingCase& c) {
  const double D = c.cutter_diameter_m, d = c.bore_diameter_m, t = c.allowance_m, h = c.offset_m;
  // [Zenkin2012, eq. 1]
  const double inner =
      checked_sqrt((d - t) * (d - t) / 4.0 - d * d / 4.0 + (D / 2 + h) * (D / 2 + h),
                   "eq. (1), ((d − t)/2)² − d²/4 + (D/2 + h)²", c);
  const double e = D / 2 + h - inner;
  return 2.0 * checked_sqrt(D * D / 4.0 - e * e, "eq. (1), D²/4 − (D/2 + h − √…)²", c);
}

double straightness_error(const BoreMillingCase& c, double s0) {
  const double D = c.cutter_diameter_m, d = c.bore_diameter_m, h = c.offset_m;
  // [Zenkin2012, eq. 3]
  const double root = checked_sqrt(D * D - s0 * s0, "eq. (3), D² − S0²", c);
  return d / 2 - checked_sqrt(h * root + (d * d - s0 * s0) / 4.0 - D * h,
                              "eq. (3), h·√(D² − S0²) + (d² − S0²)/4 − D·h", c);
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
  throw InvalidInput(
      {"accuracy_coefficient = " + format_value(c.accuracy_coefficient) +
       ": the straightness error Δ1 of eq. (3) stays below k·t = " + format_value(target) +
       " m for every axial feed S0 up to " + format_value(lo) + " m (D = " +
       format_value(c.cutter_diameter_m) + " m): the accuracy does not limit the feed"},
      kWhere);
}

double max_axial_feed_closed_form(const BoreMillingCase& c) {
  const double D = c.cutter_diameter_m, d = c.bore_diameter_m, h = c.offset_m;
  const double kt = c.accuracy_coefficient * c.allowance_m;
  // [Zenkin2012, eq. 4]
  const double a = D * h - d * kt + kt * kt + 2 * h * h;
  const double inner =
      checked_sqrt(D * D * h * h + d * d * kt * kt + 4 * h * h * (D * h - d * kt + kt * kt + h * h),
                   "eq. (4), inner root", c);
  return 2.0 * checked_sqrt(inner - a, "eq. (4), outer root", c);
}

BoreMillingResult bore_milling(const BoreMillingCase& c, double s0) {
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
  r.axial_feed_m = s0 > 0.0 ? s0 : r.max_axial_feed_m;
  const double S0 = r.axial_feed_m;
  if (!(S0 < r.q_m)) {
    throw InvalidInput({"axial feed S0 = " + format_value(S0) +
                        " m: must be less than q = " + format_value(r.q_m) +
                        " m (eq. 1), or the main edges leave uncut ridges (S0 < q)"},
                       kWhere);
  }
  // (2)
  r.milling_width_m = r.q_m / 2 + S0 / 2 +
                      S0 / (2 * kPi * d) *
                          (checked_sqrt(D * D - S0 * S0, "eq. (2), D² − S0²", c) -
                           checked_sqrt(D * D - r.q_m * r.q_m, "eq. (2), D² − q²", c));
  r.straightness_error_m = straightness_error(c, S0);  // (3)
  // n_u = v/(π·D); (8) n_o for the allowed mean chip thickness.
  r.cutter_rev_per_s = c.cutting_speed_m_per_s / (kPi * D);
  const double arcs = checked_asin(r.q_m / D, "q/D", c) + checked_asin(S0 / D, "S0/D", c);
  r.workpiece_rev_per_s = c.mean_chip_thickness_m * r.cutter_rev_per_s * c.teeth * D * arcs /
                          (2 * d * kPi * S0 * std::sin(phi));
  // (5)
  r.feed_per_tooth_m = std::sqrt(kPi * kPi * d * d + S0 * S0) * r.workpiece_rev_per_s /
                       (c.teeth * r.cutter_rev_per_s);
  r.max_chip_thickness_m = r.feed_per_tooth_m * std::sin(phi);
  // (6)
  r.contact_arc_m = D / 2 * arcs;
  r.chip_width_m = t / (2 * std::sin(phi));
  // (7)
  r.mean_chip_thickness_m = 2 * d * r.workpiece_rev_per_s * kPi * S0 * std::sin(phi) /
                            (r.cutter_rev_per_s * c.teeth * D * arcs);
  // (9)
  r.path_per_edge_m =
      r.contact_arc_m * r.cutter_rev_per_s * c.length_m / (r.workpiece_rev_per_s * S0);
  // (10)–(12)
  r.edge_width_m = t / (2 * std::sin(phi) * std::cos(c.inclination_rad));
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

}  // namespace cutdyn
