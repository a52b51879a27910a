// Phase currents of a permanent-magnet synchronous feed motor under field-oriented control
// (i_d = 0): the torque sets the current vector's magnitude, the shaft angle its phase
// (docs/models/feed-drive.md). With the equivalent current I = |Te|/KT (CurrentMeasure, the
// same measure as KT) the phase peak is Î = I (space vector) or √2·I (RMS), and
//     iu = −Î·sin θe,  iv = −Î·sin(θe − 2π/3),  iw = −Î·sin(θe + 2π/3),   θe = p·θm,
// with Î signed like the torque. Optional white noise on each phase and a sensor offset.
#pragma once

#include <string>
#include <vector>

#include "cutdyn/monitor/equivalent_current.hpp"

namespace cutdyn {

struct PmsmMotor {
  int pole_pairs = 4;
  double torque_constant_nm_per_a = 1.0;  // KT for `measure`
  CurrentMeasure measure = CurrentMeasure::kSpaceVector;
  double noise_a = 0.0;            // σ of white noise on each phase
  double offset_a[3] = {0, 0, 0};  // sensor offsets of u, v, w
  unsigned seed = 1;               // of the noise

  std::vector<std::string> validate() const;
};

struct PhaseCurrents {
  std::vector<double> time_s, iu_a, iv_a, iw_a, speed_rad_s;
};

/// The phase currents for the motor torque and speed traces (equal lengths, time increasing);
/// the shaft angle starts at `initial_angle_rad`.
PhaseCurrents motor_currents(const PmsmMotor& motor, const std::vector<double>& time_s,
                             const std::vector<double>& torque_nm,
                             const std::vector<double>& speed_rad_s,
                             double initial_angle_rad = 0.0);

}  // namespace cutdyn
