#include "cutdyn/monitor/axis_model.hpp"

#include <cmath>

#include "cutdyn/core/error.hpp"

namespace cutdyn {

std::vector<std::string> AxisModel::validate() const {
  Validator v;
  v.require(inertia_kg_m2 >= 0.0, "inertia_kg_m2", inertia_kg_m2, "kg·m²", "must be >= 0");
  v.require_positive("torque_constant_nm_per_a", torque_constant_nm_per_a, "N·m/A");
  v.require(viscous_nm_s_per_rad >= 0.0, "viscous_nm_s_per_rad", viscous_nm_s_per_rad, "N·m·s/rad",
            "must be >= 0");
  v.require(friction_nm >= 0.0, "friction_nm", friction_nm, "N·m", "must be >= 0");
  v.require_positive("force_gain_m", force_gain_m, "m");
  return v.problems();
}

double AxisModel::motor_torque_nm(double id, double w) const {
  return (w < 0.0 ? -1.0 : 1.0) * torque_constant_nm_per_a * id;
}

double AxisModel::load_torque_nm(double id, double w, double eps) const {
  // [Zheng2012, eq. 4], friction opposing motion.
  return motor_torque_nm(id, w) - viscous_nm_s_per_rad * w - friction_nm * motion_sign(w) -
         inertia_kg_m2 * eps;
}

double AxisModel::cutting_force_n(double id, double w, double eps) const {
  return load_torque_nm(id, w, eps) / force_gain_m;
}

double AxisModel::equivalent_current_a(double fc, double w, double eps) const {
  const double torque = inertia_kg_m2 * eps + viscous_nm_s_per_rad * w +
                        friction_nm * motion_sign(w) + force_gain_m * fc;
  return std::abs(torque) / torque_constant_nm_per_a;
}

AxisModel zheng2012_axis(char axis) {
  // [Zheng2012, final equations] as printed, read in kgf·cm throughout (the decision
  // of 2026-11-23; docs/models/monitor.md §2 has the arithmetic): J kgf·cm·s², KT kgf·cm/A,
  // X kgf·cm·s/rad, Tnzm kgf·cm, KBlf kgf·cm per newton of force; 1 kgf·cm = 0.0980665 N·m.
  constexpr double kgf_cm = 0.0980665;
  double printed[5];
  switch (axis) {
    case 'x':
    case 'X':
      printed[0] = 0.017, printed[1] = 1.621, printed[2] = 0.2103, printed[3] = 15.60,
      printed[4] = 0.00632;
      break;
    case 'y':
    case 'Y':
      printed[0] = 0.0141, printed[1] = 1.627, printed[2] = 0.1569, printed[3] = 14.58,
      printed[4] = 0.00592;
      break;
    case 'z':
    case 'Z':
      printed[0] = 0.019, printed[1] = 1.629, printed[2] = 0.2481, printed[3] = 17.91,
      printed[4] = 0.00391;
      break;
    default:
      throw InvalidInput({"axis = \"" + std::string(1, axis) +
                          "\": the zheng2012 preset has the axes x, y and z"});
  }
  return {printed[0] * kgf_cm, printed[1] * kgf_cm, printed[2] * kgf_cm,
          printed[3] * kgf_cm, printed[4] * kgf_cm, CurrentMeasure::kRms};
}

}  // namespace cutdyn
