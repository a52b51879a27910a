// Two-edge face milling of large bores [Zenkin2012]: kinematics and quality;
// docs/models/bore-milling.md.
//
// A face mill of diameter D whose knives cut with an outer and an inner edge machines the bore
// of diameter d of a ring blank turning at n_o; the cutter turns at n_u and feeds axially by S0
// per blank revolution. The equations (1)–(14) of [Zenkin2012] are evaluated with every square
// root and arcsine checked: an input outside a formula's domain throws cutdyn::InvalidInput
// naming the condition and the inputs, never NaN.
#pragma once

#include <string>
#include <vector>

namespace cutdyn {

/// The source's range of the accuracy coefficient k: 0.1 roughing … 0.005 finishing.
inline constexpr double kAccuracyCoefficientMin = 0.005;
inline constexpr double kAccuracyCoefficientMax = 0.1;

struct BoreMillingCase {
  // Bore and blank.
  double bore_diameter_m = 0.0;  // d, the machined bore
  double length_m = 0.0;         // L
  double allowance_m = 0.0;      // t, radial
  // Cutter.
  double cutter_diameter_m = 0.0;  // D
  int teeth = 0;                   // z
  double offset_m = 0.0;           // h, of the cutter relative to the blank
  double lead_angle_rad = 0.0;     // φ, 0 < φ <= π/2
  double inclination_rad = 0.0;    // λ, |λ| < π/2
  // Process.
  double cutting_speed_m_per_s = 0.0;  // v
  double mean_chip_thickness_m = 0.0;  // a_cp, allowed
  double accuracy_coefficient = 0.0;   // k: Δ1 <= k·t, 0.005 (finishing) … 0.1 (roughing)

  std::vector<std::string> validate() const;
};

/// How the two edge sets share the allowance at the case's offset (docs/models/bore-milling.md,
/// "The offset h"). The point of the edge circle opposite the one that finishes the bore
/// reaches R_π = sqrt(d²/4 − 2·D·|h|): the outer edges cut from d/2 − t to R_π, the inner
/// edges from there to d/2. Even (t/2 each) only at h* = (2dt − t²)/(8D); for
/// |h| >= (dt − t²)/(2D) the outer edges do not reach the blank.
struct BoreEdgeSplit {
  double inner_entry_radius_m = 0.0;  // r_e = max(R_π, d/2 − t)
  double inner_depth_m = 0.0;         // d/2 − r_e
  double outer_depth_m = 0.0;         // t − inner depth (0 when the outer edges do not cut)
  double balanced_offset_m = 0.0;     // h*
  double outer_limit_offset_m = 0.0;  // (dt − t²)/(2D)
};
BoreEdgeSplit bore_edge_split(const BoreMillingCase& c);

/// Every quantity of the plan (docs/models/bore-milling.md) at the axial feed `S0` (SI; speeds in
/// rev/s, times in s).
struct BoreMillingResult {
  double q_m = 0.0;                           // (1) corrected: width of the cut of one pass
  double axial_feed_m = 0.0;                  // S0 used
  double max_axial_feed_m = 0.0;              // S0 with Δ1 = k·t, exact inversion of (3)
  double max_axial_feed_closed_form_m = 0.0;  // (4) corrected (no d²k²t²): equals the above
  double max_axial_feed_printed_form_m = 0.0;  // (4) as printed, for comparison
  double inner_depth_m = 0.0, outer_depth_m = 0.0;  // the allowance's split (BoreEdgeSplit)
  double balanced_offset_m = 0.0;                   // h*
  double milling_width_m = 0.0;               // (2) bф
  double straightness_error_m = 0.0;          // (3) Δ1
  double cutter_rev_per_s = 0.0;              // n_u = v/(π·D)
  double workpiece_rev_per_s = 0.0;           // (8) n_o for a_cp
  double feed_per_tooth_m = 0.0;              // (5) S_z
  double max_chip_thickness_m = 0.0;          // (5) a_max = S_z·sin φ
  double contact_arc_m = 0.0;                 // (6) l
  double chip_width_m = 0.0;                  // (6) m = t/(2 sin φ) at h*; the deeper set's
  double mean_chip_thickness_m = 0.0;         // (7) a_cp (= the case's, by (8))
  double path_per_edge_m = 0.0;               // (9) l_u
  double edge_width_m = 0.0;                  // (10) b at h*; the deeper set's
  double engaged_fraction = 0.0;              // (11) p
  int teeth_in_cut = 0;                       // (11) z' = floor(z·p)
  double total_edge_width_m = 0.0;            // (12) b0
  double main_time_s = 0.0;                   // (13) t0
  double faceting_m = 0.0;                    // (14) Δ2
  double removal_rate_m3_per_s = 0.0;         // π(d·t − t²)·S0·n_o
  /// False when the axial feed breaks Δ1 <= k·t (a given S0 above max_axial_feed_m); then
  /// `warnings` says by how much and names the largest feed that keeps it.
  bool accuracy_met = true;
  std::vector<std::string> warnings;  // in machinist units (mm, 4 significant digits)
};

/// (1) corrected: q = 2·sqrt(D²/4 − (y_e − |h|)²), y_e = sqrt(r_e² − d²/4 + (D/2 + |h|)²), r_e
/// the inner edges' entry radius ((d − t)/2 at h*; the printed form has D/2 + |h| − y_e in
/// place of y_e − |h|, which fails Δ1(S0 = q) = t/2). Throws if a root's argument is negative.
double bore_q(const BoreMillingCase& c);
/// (3): Δ1 at the axial feed S0 (with |h|: −h is the mirror image of the same cut).
double straightness_error(const BoreMillingCase& c, double axial_feed_m);
/// The largest S0 with Δ1(S0) <= k·t, by Brent's method on (3) to 1e-12 relative.
double max_axial_feed(const BoreMillingCase& c);
/// (4) corrected: the exact inversion of (3) at Δ1 = k·t (the printed form's d²k²t² under
/// the inner root removed).
double max_axial_feed_closed_form(const BoreMillingCase& c);
/// (4) as printed, with the d²k²t² term (too large: +0.05 … +41 %, √2 at h = 0).
double max_axial_feed_printed_form(const BoreMillingCase& c);

/// The whole plan at S0 = `axial_feed_m` (0: the largest, max_axial_feed). Checks S0 < q (an
/// error); a given S0 that breaks Δ1 <= k·t is computed and warned about. The
/// blank speed n_o is (8)'s for the case's a_cp, or `workpiece_rev_per_s` if given (then a_cp
/// is (7)'s for it).
BoreMillingResult bore_milling(const BoreMillingCase& c, double axial_feed_m = 0.0,
                               double workpiece_rev_per_s = 0.0);

/// The box and the limits of the plan optimiser.
struct BoreMillingLimits {
  double offset_min_m = 0.0, offset_max_m = 0.0;  // the box of |h|, which must hold h*
  double cutting_speed_max_m_per_s = 0.0;         // v of the tool
  double cutter_rev_per_s_max = 0.0;              // n_u of the spindle
  double workpiece_rev_per_s_max = 0.0;           // n_o of the blank drive
  double faceting_max_m = 0.0;                    // Δ2
  double max_chip_thickness_m = 0.0;              // a_max of the tool
  int feed_samples = 101;                         // scan of S0 before refinement

  std::vector<std::string> validate() const;
};

struct BoreMillingPlan {
  bool feasible = false;
  BoreMillingCase chosen;    // the case with h and v (= π·D·n_u) chosen
  BoreMillingResult result;  // at the chosen S0 and n_o
  /// The constraints active at the optimum: "straightness" (Δ1 = k·t), "uncut ridges"
  /// (S0 → q), "mean chip" (a_cp), "max chip" (a_max), "faceting" (Δ2), "blank speed"
  /// (n_o max); n_u is always at its limit (t0 falls with it).
  std::vector<std::string> binding;
  int evaluations = 0;
  std::string reason;  // why no plan is feasible (empty when feasible)
};

/// At h = h* (the balanced offset, which must lie in the box of |h|), chooses S0, n_u and n_o
/// to minimise the main time t0 = (L/S0 + 1)/n_o subject to
/// Δ1 <= k·t, S0 < q, a_cp <= the case's a_cp, a_max and Δ2 within `limits`, n_o and n_u
/// within the machine's. The speed constraints depend on n_o/n_u only, so n_u takes its limit
/// and n_o the largest allowed ratio; S0 is scanned and refined by Brent's minimiser.
BoreMillingPlan optimise_bore_milling(const BoreMillingCase& c, const BoreMillingLimits& limits);

/// The same objective and constraints at one point (h, S0): t0, or +∞ if infeasible. For the
/// plan's trade-off plot and for checking the optimiser against a grid.
double bore_milling_main_time(const BoreMillingCase& c, const BoreMillingLimits& limits,
                              double offset_m, double axial_feed_m);

}  // namespace cutdyn
