// Time-domain simulation of regenerative turning, conventional or vibration-assisted
// [Chikishev2018, eq. 8]; docs/models/turning.md §6.
//
//     M·q̈ + C·q̇ + K·q = F(t),   y = Σ q,
//     F(t) = g(t)·Kt·w·h(t),   h(t) = h0 + S(t − τ) − y(t)   while h > 0, else F = 0,
//
// with S the surface the tool left one revolution earlier: S(t) = y(t) while the tool is in
// the material (h > 0), and S(t) = S(t − τ) + h0 when it has jumped out (the older surface
// stays). Each mode is advanced exactly over a step with the force held constant over it
// (zero-order hold); the contact window enters through its exact mean over the step. The
// step divides the revolution, so the delay needs no interpolation.
#pragma once

#include <string>
#include <vector>

#include "cutdyn/stability/turning.hpp"

namespace cutdyn {

struct TurningSimulationOptions {
  double rpm = 0.0;
  double depth_m = 0.0;  // width of cut w
  double feed_m = 0.0;   // h0, uncut chip thickness per revolution
  double duration_s = 1.0;
  double initial_displacement_m = 1e-6;  // added to the static deflection at t = 0
  /// Step as a fraction of the shortest structural period (and at most 1/16 of the
  /// vibration period).
  double max_step_fraction = 1.0 / 256.0;
  int max_recorded_samples = 20000;  // traces are thinned to at most this many samples

  std::vector<std::string> validate() const;
};

struct TurningSimulationResult {
  // Traces (thinned).
  std::vector<double> time_s;
  std::vector<double> displacement_m;    // y
  std::vector<double> force_n;           // F
  std::vector<double> chip_thickness_m;  // h (may be negative when out of the cut)
  // Per revolution: half the peak-to-peak of y.
  std::vector<double> revolution_time_s;
  std::vector<double> revolution_amplitude_m;
  /// Exponential growth rate of the per-revolution amplitude (1/s), fitted by least squares
  /// on its logarithm over the revolutions before the tool first leaves the cut.
  double growth_rate_per_s = 0.0;
  bool lost_contact = false;         // h <= 0 happened (the tool jumped out of the cut)
  double contact_loss_time_s = 0.0;  // first time it did
  bool chatter = false;              // growth_rate > 0 or lost contact
  double static_deflection_m = 0.0;
  double duty_cycle = 1.0;
  double step_s = 0.0;
  long long steps = 0;
};

TurningSimulationResult simulate_turning(const TurningModel& model,
                                         const TurningSimulationOptions& options);

}  // namespace cutdyn
