// One turning process, described once: the tool's modes in the feed direction x, the
// feed-direction cutting coefficient and, for vibration-assisted cutting, the vibration
// ([Chikishev2018]; docs/models/turning.md). The stability methods (stability/turning.hpp) and
// the time-domain simulation (simulate/turning_simulation.hpp) both take it; the case file's
// [[modes]], [cutting] and [vibration] tables are read into it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cutdyn/forces/duty_cycle.hpp"
#include "cutdyn/modal/measured_frf.hpp"
#include "cutdyn/modal/modal_model.hpp"

namespace cutdyn {

/// Ultrasonic vibration along the cutting direction ([vibration]).
struct VibrationAssist {
  double frequency_hz = 0.0;
  std::optional<double> amplitude_m;           // needed unless duty_cycle is fixed
  std::optional<double> workpiece_diameter_m;  // duty cycle from the cutting speed
  std::optional<double> duty_cycle;            // fixed duty cycle, 0 < r <= 1

  std::vector<std::string> validate() const;
  /// The duty cycle at spindle speed `rpm`: the fixed one, or from v = π·D·n/60.
  DutyCycle at_rpm(double rpm) const;
};

struct TurningProcess {
  ModalModel modal;    // modes in direction x
  /// A measured receptance in x, beside or instead of `modal` (as MillingProcess::measured).
  std::optional<MeasuredStructure> measured;
  double kf_pa = 0.0;  // feed-direction cutting coefficient, N/m²
  std::optional<VibrationAssist> vibration;

  /// Problems naming the member; empty when a stability analysis or a simulation can run
  /// (modes in x only, each damped; Kf > 0; a vibration whose duty cycle can be had).
  std::vector<std::string> validate() const;
  /// The modes the time-domain methods use: `modal` and the modes fitted to `measured`.
  ModalModel structure_modes() const;
  /// The same process without the vibration.
  TurningProcess conventional() const;
};

}  // namespace cutdyn
