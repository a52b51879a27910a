#include "cutdyn/process/turning.hpp"

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn {

std::vector<std::string> VibrationAssist::validate() const {
  Validator v("vibration");
  v.require_positive("frequency_hz", frequency_hz, "Hz");
  if (duty_cycle) {
    v.require(*duty_cycle > 0.0 && *duty_cycle <= 1.0, "duty_cycle", *duty_cycle, "",
              "must be greater than 0 and at most 1");
    return v.problems();
  }
  if (!amplitude_m)
    v.add("vibration.amplitude_m: missing (needed unless duty_cycle is fixed)");
  else
    v.require_positive("amplitude_m", *amplitude_m, "m");
  if (!workpiece_diameter_m)
    v.add("vibration: give duty_cycle, or workpiece_diameter_m to compute it from the speed");
  else
    v.require_positive("workpiece_diameter_m", *workpiece_diameter_m, "m");
  return v.problems();
}

DutyCycle VibrationAssist::at_rpm(double rpm) const {
  if (duty_cycle) return fixed_duty_cycle(*duty_cycle, frequency_hz);
  const double v = units::kPi * workpiece_diameter_m.value_or(0.0) * rpm / 60.0;
  return cutdyn::duty_cycle(v, frequency_hz, amplitude_m.value_or(0.0));
}

ModalModel TurningProcess::structure_modes() const { return with_fitted_modes(modal, measured); }

std::vector<std::string> TurningProcess::validate() const {
  Validator v;
  if (!measured || !modal.modes.empty()) v.merge(modal.validate());
  if (measured && measured->fitted.modes.empty())
    v.add("measured: no modes fitted to the measured FRF (the time-domain methods need them)");
  for (std::size_t i = 0; i < modal.modes.size(); ++i) {
    if (modal.modes[i].direction != Direction::kX)
      v.add("modes[" + std::to_string(i) +
            "].direction = y: turning models the feed direction x only");
    v.require(modal.modes[i].damping_ratio > 0.0, "modes[" + std::to_string(i) + "].damping_ratio",
              modal.modes[i].damping_ratio, "", "must be positive for a stability analysis");
  }
  v.require_positive("kf_pa", kf_pa, "N/m²");
  if (vibration) v.merge(vibration->validate());
  return v.problems();
}

TurningProcess TurningProcess::conventional() const {
  TurningProcess p = *this;
  p.vibration.reset();
  return p;
}

}  // namespace cutdyn
