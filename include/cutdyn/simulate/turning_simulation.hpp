// Time-domain simulation of regenerative turning, conventional or vibration-assisted
// [Chikishev2018, eq. 8]; docs/models/turning.md §6.
//
//     M·q̈ + C·q̇ + K·q = F(t),   y = Σ q,
//     F(t) = g(t)·Kf·w·h(t),   h(t) = h0 + S(t − τ) − y(t)   while h > 0, else F = 0,
//
// with S the surface the tool left one revolution earlier: S(t) = y(t) while the tool is in
// the material (h > 0), and S(t) = S(t − τ) + h0 when it has jumped out (the older surface
// stays). Each mode is advanced exactly over a step with the force linear between the steps
// (first-order hold); the contact window enters through its exact mean over the step. The
// step divides the revolution, so the delay needs no interpolation.
//
// The cut is run twice in step, with and without the initial displacement: the forced
// response (to the vibration's pulses, the start) is the same in both, so their difference is
// the free regenerative response to the displacement alone, and its growth rate — a property
// of the cut, not of the run's length — decides chatter. A runaway growth stops the run.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "cutdyn/simulate/simulation_status.hpp"
#include "cutdyn/stability/turning.hpp"

namespace cutdyn {

struct TurningSimulationOptions {
  double rpm = 0.0;
  double depth_m = 0.0;  // width of cut w
  double feed_m = 0.0;   // h0, uncut chip thickness per revolution
  double duration_s = 1.0;
  /// Added to the static deflection at t = 0 in the reported run (not in its twin); > 0.
  double initial_displacement_m = 1e-6;
  /// Step as a fraction of the shortest structural period (and at most 1/16 of the
  /// vibration period).
  double max_step_fraction = 1.0 / 256.0;
  int max_recorded_samples = 20000;  // traces are thinned to at most this many samples
  /// Called at every hundredth of the run, (done, 100), from the simulating thread; it may
  /// throw to stop the run (a front end's cancel), and the exception passes out unchanged.
  std::function<void(int, int)> progress;

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
  /// Per revolution: half the peak-to-peak of the difference between the run with the initial
  /// displacement and the run without (the free regenerative response).
  std::vector<double> perturbation_amplitude_m;
  /// Exponential growth rate of that difference (1/s), from the third revolution (the first in
  /// runs of under six) until the tool first leaves the cut in either run or the difference has
  /// fallen 1e9-fold: ln|μ| per revolution of the largest multiplier present in its samples at
  /// four phases of each revolution (matrix pencil, cutdyn/simulate/growth_estimate.hpp), or,
  /// where a few multipliers do not explain them, least squares on the logarithm of its
  /// per-revolution amplitude.
  double growth_rate_per_s = 0.0;
  /// The multipliers explained the samples (`growth_components` of them), or the slope's two
  /// halves agree in sign with it. When false the verdict is uncertain: a longer run settles it.
  bool growth_settled = false;
  int growth_components = 0;
  bool lost_contact = false;         // h <= 0 happened (the tool jumped out of the cut)
  double contact_loss_time_s = 0.0;  // first time it did
  /// growth_rate_per_s > 0, or a runaway (or, when the tool left the cut before two
  /// revolutions could be fitted, that loss of contact).
  bool chatter = false;
  /// kRunaway: |y − static deflection| passed 1000 × (h0 + initial displacement) in either
  /// run; the run stopped at stop_time_s and the traces end there.
  SimulationStatus status = SimulationStatus::kCompleted;
  double stop_time_s = 0.0;
  double static_deflection_m = 0.0;
  double duty_cycle = 1.0;
  double step_s = 0.0;
  long long steps = 0;

  std::string verdict() const {
    return simulation_verdict(chatter, status, stop_time_s, growth_settled);
  }
};

TurningSimulationResult simulate_turning(const TurningProcess& model,
                                         const TurningSimulationOptions& options);

}  // namespace cutdyn
