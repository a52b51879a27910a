// Torque balance of a feed axis driven by a servo motor [Zheng2012, eqs. 2–4];
// docs/models/monitor.md §2.
//
//   J·ε = s·KT·Id − X·ω − Tnzm·sign(ω) − KBlf·Fc
//
// ε angular acceleration, ω angular speed of the motor, Id the equivalent current (a
// magnitude, equivalent_current.hpp), s the sign of the motor torque, X the viscous
// coefficient, Tnzm the no-load friction torque, Fc the cutting force along the axis and KBlf
// the slope of motor torque against cutting force (lever arm plus the friction that grows
// with load). Decisions: friction opposes motion (sign(ω)); the motor drives its axis, so the
// torque has the sign of the motion, s = sign(ω) (the current alone does not carry a sign);
// Fc > 0 opposes motion in the axis's + direction.
#pragma once

#include <string>
#include <vector>

#include "cutdyn/drive/equivalent_current.hpp"

namespace cutdyn {

/// One axis, SI units (the motor side: rad, rad/s, N·m).
struct AxisModel {
  double inertia_kg_m2 = 0.0;             // J, motor plus load reflected to the motor, >= 0
  double torque_constant_nm_per_a = 0.0;  // KT, for `measure`, > 0
  double viscous_nm_s_per_rad = 0.0;      // X, >= 0
  double friction_nm = 0.0;               // Tnzm, no-load (Coulomb) friction torque, >= 0
  double force_gain_m = 0.0;              // KBlf, motor torque per newton of cutting force, > 0
  CurrentMeasure measure = CurrentMeasure::kSpaceVector;  // the default everywhere (§1)

  /// Every problem as "field = value unit: must be ...".
  std::vector<std::string> validate() const;

  /// Motor torque s·KT·Id with s = sign(ω) (+1 at ω = 0).
  double motor_torque_nm(double equivalent_current_a, double speed_rad_s) const;
  /// [Zheng2012, eq. 4] The torque the cutting force takes, KBlf·Fc =
  /// s·KT·Id − X·ω − Tnzm·sign(ω) − J·ε.
  double load_torque_nm(double equivalent_current_a, double speed_rad_s, double accel_rad_s2) const;
  /// Fc = load_torque_nm / KBlf.
  double cutting_force_n(double equivalent_current_a, double speed_rad_s,
                         double accel_rad_s2) const;
  /// The equivalent current that the balance needs for force Fc at speed ω and
  /// acceleration ε: |J·ε + X·ω + Tnzm·sign(ω) + KBlf·Fc| / KT (for synthesising logs).
  double equivalent_current_a(double cutting_force_n, double speed_rad_s,
                              double accel_rad_s2) const;
};

/// The source's preset for axis 'x', 'y' or 'z' (either case) [Zheng2012, final equations],
/// its printed numbers read in kgf·cm throughout (docs/models/monitor.md §2; the SI reading
/// gave a friction torque above the motor's rated torque): J = 1.667e-3 / 1.383e-3 / 1.863e-3
/// kg·m², KT = 0.1590 / 0.1596 / 0.1598 N·m/A, X = 0.02062 / 0.01539 / 0.02433 N·m·s/rad,
/// Tnzm = 1.530 / 1.430 / 1.756 N·m, KBlf = 6.198e-4 / 5.806e-4 / 3.834e-4 m (the printed
/// value × 0.0980665); measure kRms. Throws InvalidInput for another axis.
AxisModel zheng2012_axis(char axis);

/// sign(x) as used by the balance: +1, −1, or 0 at 0.
inline double motion_sign(double x) { return x > 0.0 ? 1.0 : (x < 0.0 ? -1.0 : 0.0); }

}  // namespace cutdyn
