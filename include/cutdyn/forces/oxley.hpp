// Oxley's predictive machining theory for orthogonal cutting, extended to the Johnson–Cook
// flow stress [Oxley1989; AdibiSedeh2003; Lalwani2009]; docs/models/oxley.md.
//
// A parallel-sided primary shear zone of thickness l/C0 around the shear plane AB (length
// l = t1/sinφ) and a secondary zone of thickness δ·t2 along the tool–chip interface. For a
// trial (φ, C0, δ) the state follows in closed form apart from the shear-plane temperature,
// which is a fixed point (§2). The theory then fixes the three unknowns by
//   φ:  the interface shear stress F/(h·w) equals the chip's flow shear stress k_chip,
//   C0: the normal stress at B from the shear-plane analysis σ'_N equals the mean interface
//       normal stress N/(h·w),
//   δ:  the cutting force Fc is least,
// solved as nested 1-D problems: the largest φ root (the low-φ root is not physical), a
// bracketed C0 root, and a bracketed minimum in δ (§3).
#pragma once

#include "cutdyn/forces/work_material.hpp"

namespace cutdyn {

/// One orthogonal cut. Speed, thickness and width are SI; rake in rad.
struct OrthogonalCut {
  double speed_m_per_s = 0.0;             // V
  double uncut_chip_thickness_m = 0.0;    // t1
  double width_m = 0.0;                   // w
  double rake_rad = 0.0;                  // α
  double workpiece_temperature_c = 20.0;  // Tw, before cutting
};

struct OxleyOptions {
  double eta = 0.9;  // η: T_AB = Tw + η·ΔT_SZ [Oxley1989]
  double psi = 0.9;  // ψ: T_int = Tw + ΔT_SZ + ψ·ΔT_M [Lalwani2009]
  // Search ranges of the strain-rate constant and the secondary-zone thickness ratio.
  double c0_min = 1.0;
  double c0_max = 10.0;
  double delta_min = 0.005;
  double delta_max = 0.2;
  // Shear angles scanned for the largest root of the interface condition.
  double phi_min_rad = 0.02;
  double phi_max_rad = 1.0;
  int phi_scan_points = 48;
  int c0_scan_points = 9;
  int delta_scan_points = 9;
  double phi_tolerance_rad = 1e-10;
  double c0_tolerance = 1e-8;
  double delta_tolerance = 1e-5;  // Fc is flat at its minimum: δ matters to second order

  /// Every problem, with field names "oxley.<name>".
  void validate(Validator& v) const;
};

/// Everything at one trial (φ, C0, δ). Forces in N, stresses in Pa, temperatures in °C.
struct OxleyState {
  bool admissible = false;  // the geometry exists: tanθ > 0, 0 < λ < π/2
  double phi_rad = 0.0, c0 = 0.0, delta = 0.0;
  // Shear plane.
  double shear_plane_length_m = 0.0;      // l = t1/sinφ
  double shear_velocity_m_per_s = 0.0;    // Vs = V·cosα/cos(φ−α)
  double chip_velocity_m_per_s = 0.0;     // Vc = V·sinφ/cos(φ−α)
  double chip_thickness_m = 0.0;          // t2 = t1·cos(φ−α)/sinφ
  double strain_ab = 0.0;                 // equivalent plastic strain at AB
  double strain_rate_ab_per_s = 0.0;      // equivalent plastic strain rate at AB
  double thermal_number = 0.0;            // R_T = ρ·S·V·t1/K at T_AB
  double heat_into_work = 0.0;            // β
  double temperature_rise_shear_c = 0.0;  // ΔT_SZ
  double temperature_ab_c = 0.0;
  double shear_flow_stress_pa = 0.0;  // k_AB
  double hardening_index = 0.0;       // n_eq at AB
  double theta_rad = 0.0;             // angle of the resultant to AB
  double friction_angle_rad = 0.0;    // λ
  // Forces.
  double shear_force_n = 0.0;     // Fs = k_AB·l·w
  double resultant_n = 0.0;       // R = Fs/cosθ
  double cutting_force_n = 0.0;   // Fc = R·cos(λ−α)
  double thrust_force_n = 0.0;    // Ft = R·sin(λ−α)
  double friction_force_n = 0.0;  // F = R·sinλ, along the rake face
  double normal_force_n = 0.0;    // N = R·cosλ
  // Tool–chip interface.
  double contact_length_m = 0.0;            // h
  double interface_shear_stress_pa = 0.0;   // τ_int = F/(h·w)
  double interface_normal_stress_pa = 0.0;  // σ_N = N/(h·w)
  double normal_stress_b_pa = 0.0;          // σ'_N at B from the shear-plane analysis
  double temperature_rise_chip_c = 0.0;     // ΔT_C, mean rise from the interface work
  double temperature_chip_c = 0.0;          // T_c = Tw + ΔT_SZ + ΔT_C, mean chip temperature
  double temperature_rise_max_c = 0.0;      // ΔT_M
  double temperature_interface_c = 0.0;     // T_int
  double strain_interface = 0.0;
  double strain_rate_interface_per_s = 0.0;
  double chip_flow_stress_pa = 0.0;  // k_chip at the interface
};

/// The state at one trial (φ, C0, δ): shear-plane temperature solved to 1e-9 °C, the rest in
/// closed form. Inputs are assumed valid (oxley_orthogonal checks them).
OxleyState oxley_state(const WorkMaterial& material, const OrthogonalCut& cut, double phi_rad,
                       double c0, double delta, const OxleyOptions& options = {});

/// The shear angle satisfying the interface condition at (C0, δ): the largest root (the
/// low-φ roots are not physical), found by a scan down from phi_max_rad and Brent's method;
/// NaN if there is none. Inputs are assumed valid.
double oxley_shear_angle(const WorkMaterial& material, const OrthogonalCut& cut, double c0,
                         double delta, const OxleyOptions& options = {});

struct OxleyResult {
  OxleyState state;         // at the solution
  double kc_pa = 0.0;       // Fc/(t1·w)
  double kt_pa = 0.0;       // Ft/(t1·w)
  double chip_ratio = 0.0;  // t1/t2
  int evaluations = 0;      // oxley_state evaluations
  /// The minimum in δ or the C0 root sits on its search bound (so the range may be too
  /// narrow); said in words.
  std::vector<std::string> warnings;
};

/// Solves the theory for one cut. Throws cutdyn::InvalidInput when the inputs are invalid
/// (material, cut, options) or the cut is outside the theory's validity: no physical
/// equilibrium in the search ranges, a thermal number outside Boothroyd's correlation, or an
/// interface at or above melting. The messages name the condition and the numbers.
OxleyResult oxley_orthogonal(const WorkMaterial& material, const OrthogonalCut& cut,
                             const OxleyOptions& options = {});

/// Checks a cut's inputs: V > 0, t1 > 0, w > 0, |α| < 45°, Tr <= Tw < Tm (field names
/// "cut.<name>").
void validate(const OrthogonalCut& cut, const WorkMaterial& material, Validator& v);

}  // namespace cutdyn
