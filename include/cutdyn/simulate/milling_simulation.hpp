// Time-domain simulation of milling ([Ermolaev2020]; docs/models/milling-simulation.md).
//
// z teeth (even or uneven pitch), each cut into N axial slices lagging the tooth tip by
// their share of the helix lag φN = 2B·tanβ/d; every slice has its own engagement window and
// chip thickness. The chip comes from the stored surface: each slice keeps, per angle bin of
// one revolution, the surface the last cutting tooth left there (feed motion plus the cutter's
// displacement), so the chip is the feed since that tooth plus the regeneration, and a tooth
// that has left the cut leaves the older surface in place. Force laws: the S1 law (chip-
// formation lag T2, flank contact P0·e^(−X/T1), angles φrez and φskv) or the linear
// mechanistic law (Kt, Kr and edge coefficients). The cutter's modes in x (feed) and y are
// advanced exactly with the force linear between steps (first-order hold). The run starts on
// the periodic forced vibration of the steady cut with a small displacement added; the growth
// of that perturbation over the periods decides chatter, and a runaway growth stops the run.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cutdyn/process/milling.hpp"
#include "cutdyn/simulate/simulation_status.hpp"

namespace cutdyn {

/// One cut of a milling process: the process at a spindle speed, feed and axial depth.
struct MillingCut {
  MillingProcess process;  // its modes may be empty: a rigid cutter
  double spindle_rad_s = 0.0;
  double feed_per_tooth_m = 0.0;
  double width_m = 0.0;      // B, the axial depth of cut
  bool regenerative = true;  // false: chip = s_z·sin θ from the feed alone (force studies)

  std::vector<std::string> validate() const;
  /// φN = 2B·tanβ/d: the lag between the flute's two extreme sections.
  double lag_angle() const { return process.tool.lag_angle(width_m); }
};

struct MillingSimulationOptions {
  /// Raised, when the chip is regenerative, to put 64 steps in the shortest mode period.
  int steps_per_tooth = 256;
  double revolutions = 30.0;         // simulated
  double summary_revolutions = 2.0;  // the last ones, for the summary
  int slices = 0;  // 0: automatic — slice lag = one angle step (≤ 1000 slices, ≤ 8e6 slice-bins)
  bool closed_form_helix = false;    // [Ermolaev2020] eqs. 8–9 instead of slices
  int max_recorded_samples = 20000;  // traces are thinned to at most this many samples
  /// Displacement added in x and y at t = 0 to the periodic forced vibration, as a fraction of
  /// the feed per tooth (> 0): the disturbance whose growth or decay decides chatter. Not added
  /// when the chip comes from the feed alone (no chatter to decide).
  double perturbation = 1e-3;
  /// Called at every hundredth of the run, (done, 100), from the simulating thread; it may
  /// throw to stop the run (a front end's cancel), and the exception passes out unchanged.
  std::function<void(int, int)> progress;

  std::vector<std::string> validate() const;
};

struct MillingSimulationResult {
  // Traces (thinned): forces on the cutter, its displacement, engaged teeth (slices in cut,
  // as a fraction of the flute length, summed over the teeth).
  std::vector<double> time_s, fx_n, fy_n, force_n, x_m, y_m, teeth_in_cut;
  /// ΣP: the teeth's cutting forces alone, summed as scalars (no flank contact): c·U of the S1
  /// law, Ft of the mechanistic law — the spindle torque over the radius when φrez = 0.
  std::vector<double> cutting_force_n;
  // Summary over the last summary_revolutions.
  /// ΔP = (Pmax − Pmin)/(|Pmax| + |Pmin|) (= (Pmax − Pmin)/(Pmax + Pmin) for a force that keeps
  /// its sign; 1 when it reaches zero or reverses), of P = |F|, the resultant on the cutter.
  double force_pulsation = 0.0;
  /// The same of ΣP, the cutting forces alone ([Ermolaev2020] figs. 6a and 6b: "about 90 % of
  /// the force is P, so only its influence is considered").
  double cutting_force_pulsation = 0.0;
  double mean_cutting_force_n = 0.0;
  double mean_force_n = 0.0, peak_force_n = 0.0, min_force_n = 0.0;
  double mean_fx_n = 0.0, mean_fy_n = 0.0;
  double mean_teeth_in_cut = 0.0;
  double vibration_pp_x_m = 0.0, vibration_pp_y_m = 0.0;
  /// Once-per-period (tooth period; revolution for uneven pitch) samples of the displacement:
  /// mean |change| between consecutive samples over the second half of the run, divided by
  /// the peak-to-peak vibration. Near 0 for a periodic (forced) vibration.
  double chatter_indicator = 0.0;
  /// Growth of the perturbation per period (tooth period; revolution with uneven pitch), ln
  /// units, from x(t) − x(t − period) (the free response: the forced vibration repeats) over the
  /// run before it fell 1e9-fold or grew to 10 % of the feed per tooth: ln|μ| of the largest
  /// Floquet multiplier present in its samples at four phases of each period (matrix pencil,
  /// cutdyn/simulate/growth_estimate.hpp), or, where a few multipliers do not explain them, the
  /// least-squares slope of its log-amplitude (√Σ(q² + (q̇/ωn)²) averaged over each period) over
  /// the second half of those periods. Zero without regeneration.
  double growth_per_period = 0.0;
  /// The multipliers explained the samples (`growth_components` of them), or the slope's two
  /// halves agree in sign with it. When false the run is too short to tell the decisive root
  /// from its neighbours: the verdict is uncertain (a longer run settles it).
  bool growth_settled = false;
  int growth_components = 0;
  double growth_rate_per_s = 0.0;  // the same per second
  /// Fraction of the slice passes inside the window (away from its zero-chip edges,
  /// |sin θ| >= 0.05) in which the tooth was out of the cut (chip <= 0).
  double contact_loss = 0.0;
  /// Regenerative chip and a growing perturbation (growth_per_period > 0), or a runaway.
  bool chatter = false;
  /// kRunaway: the displacement passed 1000 × (feed per tooth + peak forced vibration) and
  /// the run stopped at stop_time_s; the traces end there and the summary covers the part of
  /// the summary revolutions reached, or else the last one to two revolutions before the stop.
  SimulationStatus status = SimulationStatus::kCompleted;
  double stop_time_s = 0.0;  // the time integrated up to
  /// Cutter displacement along the wall normal when a tooth passes the angle that finishes
  /// the wall (π in down-milling, 0 in up-milling), averaged; > 0 is an overcut.
  std::optional<double> surface_location_error_m;
  // Discretization used.
  double step_s = 0.0;
  long long steps = 0;  // integrated (fewer than asked after a runaway)
  int slices = 1;
  int steps_per_revolution = 0;

  std::string verdict() const {
    return simulation_verdict(chatter, status, stop_time_s, growth_settled);
  }
};

/// Throws cutdyn::InvalidInput for an invalid cut or options, naming every problem.
MillingSimulationResult simulate_milling(const MillingCut& cut,
                                         const MillingSimulationOptions& options);

}  // namespace cutdyn
