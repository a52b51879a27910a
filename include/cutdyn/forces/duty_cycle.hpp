// Pulsed cutting force of vibration-assisted cutting [Chikishev2018, eqs. 1–5];
// docs/models/turning.md §1.
//
// The tool vibrates along the cutting direction, p(t) = v·t + A·sin(2πft) in the
// workpiece frame. It cuts only while it is at a new maximum of p; otherwise it is
// separated from the chip. With ρ = v/(2πfA): ρ >= 1 means no separation (r = 1);
// otherwise, in the phase u = 2πft, separation starts at u1 = acos(−ρ) and contact resumes
// at the u2 in (2π − u1, 2π + u1) with ρ·u2 + sin u2 = ρ·u1 + sin u1; r = (u1 + 2π − u2)/2π.
#pragma once

namespace cutdyn {

/// The contact window g(t) of one vibration period: g = 1 on [start, start + r·T) modulo T,
/// 0 elsewhere.
struct ContactWindow {
  double period_s = 1.0;
  double duty_cycle = 1.0;  // r = Tc/T, 0 < r <= 1
  double start_s = 0.0;     // contact start within the period, in [0, T)

  /// g(t) [Chikishev2018, eq. 2].
  bool in_contact(double t) const;
  /// Mean of g over [t0, t1] (t1 > t0), exact.
  double mean(double t0, double t1) const;
};

struct DutyCycle {
  double ratio = 1.0;                   // r
  double period_s = 0.0;                // T = 1/f
  double critical_speed_m_per_s = 0.0;  // 2πfA: no separation at or above it
  double rho = 0.0;                     // v / (2πfA)
  bool separates = false;               // ρ < 1
  double separation_phase_rad = 0.0;    // u1 (only meaningful when separates)
  double contact_phase_rad = 0.0;       // u2 (only meaningful when separates)

  /// The window with its phase origin at u = 0 of the tool motion: contact from u2 − 2π
  /// to u1.
  ContactWindow window() const;
};

/// Duty cycle from the kinematics. Throws cutdyn::InvalidInput unless v >= 0,
/// f > 0 and A > 0 (all finite).
DutyCycle duty_cycle(double cutting_speed_m_per_s, double frequency_hz, double amplitude_m);

/// A prescribed duty cycle r (0 < r <= 1) at frequency f, contact starting at t = 0.
DutyCycle fixed_duty_cycle(double ratio, double frequency_hz);

/// Forces of the pulsed cut [Chikishev2018, eqs. 3–5]: F = g(t)·K·h·w.
struct PulsedForces {
  double peak_cutting_n = 0.0;  // Kc·h·w, while in contact
  double peak_thrust_n = 0.0;   // Kt·h·w
  double mean_cutting_n = 0.0;  // r·Kc·h·w
  double mean_thrust_n = 0.0;   // r·Kt·h·w
};

/// kc_pa, kt_pa in N/m², uncut chip thickness h and width w in m.
PulsedForces pulsed_forces(double kc_pa, double kt_pa, double uncut_chip_thickness_m,
                           double width_m, double duty_cycle);

}  // namespace cutdyn
