// Phase currents of a permanent-magnet synchronous feed motor under field-oriented control
// (i_d = 0): the torque sets the current vector's magnitude, the shaft angle its phase
// (docs/models/feed-drive.md). With the equivalent current I = |Te|/KT (CurrentMeasure, the
// same measure as KT) the phase peak is Î = I (space vector) or √2·I (RMS), and
//     iu = −Î·sin θe,  iv = −Î·sin(θe − 2π/3),  iw = −Î·sin(θe + 2π/3),   θe = p·θm,
// with Î signed like the torque. Optional white noise on each phase and a sensor offset; the noise
// is drawn from the stream (seed, stream) — std::seed_seq mixes both, so that the axes of one run
// (stream = the axis' index) have independent noise and another seed gives another run.
#pragma once

#include <string>
#include <vector>

#include "cutdyn/drive/equivalent_current.hpp"

namespace cutdyn {

struct PmsmMotor {
  int pole_pairs = 4;
  double torque_constant_nm_per_a = 1.0;  // KT for `measure`
  CurrentMeasure measure = CurrentMeasure::kSpaceVector;
  double noise_a = 0.0;            // σ of white noise on each phase
  double offset_a[3] = {0, 0, 0};  // sensor offsets of u, v, w
  unsigned seed = 1;               // of the noise ([[drives]] seed, --seed)
  unsigned stream = 0;             // the axis' own stream of the seed (its index)

  std::vector<std::string> validate() const;
};

struct PhaseCurrents {
  std::vector<double> time_s, iu_a, iv_a, iw_a, speed_rad_s;
  /// The electrical angle θe = p·θm the currents were made with, wrapped into [0, 2π).
  std::vector<double> rotor_angle_rad;
};

/// The phase currents for the motor torque and speed traces (equal lengths, time increasing);
/// the shaft angle starts at `initial_angle_rad`.
PhaseCurrents motor_currents(const PmsmMotor& motor, const std::vector<double>& time_s,
                             const std::vector<double>& torque_nm,
                             const std::vector<double>& speed_rad_s,
                             double initial_angle_rad = 0.0);

}  // namespace cutdyn
