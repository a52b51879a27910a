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
  // [Zheng2012, table 2 and the final equations], read as SI (models.md S3 decision).
  AxisModel m;
  m.measure = CurrentMeasure::kRms;
  switch (axis) {
    case 'x':
    case 'X':
      m = {0.017, 1.621, 0.2103, 15.60, 0.00632, CurrentMeasure::kRms};
      break;
    case 'y':
    case 'Y':
      m = {0.0141, 1.627, 0.1569, 14.58, 0.00592, CurrentMeasure::kRms};
      break;
    case 'z':
    case 'Z':
      m = {0.019, 1.629, 0.2481, 17.91, 0.00391, CurrentMeasure::kRms};
      break;
    default:
      throw InvalidInput({"axis = \"" + std::string(1, axis) +
                          "\": the zheng2012 preset has the axes x, y and z"});
  }
  return m;
}

}  // namespace cutdyn
