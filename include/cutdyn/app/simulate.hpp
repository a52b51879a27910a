// The simulation jobs: `simulate` for turning (conventional, and vibration-assisted beside its
// conventional twin) and for milling (one cut, or a sweep of one case key), each with the
// stability prediction at the same speed for comparison.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cutdyn/app/request.hpp"
#include "cutdyn/io/case_file.hpp"
#include "cutdyn/simulate/milling_simulation.hpp"
#include "cutdyn/simulate/turning_simulation.hpp"
#include "cutdyn/stability/milling.hpp"
#include "cutdyn/stability/turning.hpp"

namespace cutdyn::app {

/// Overrides of the case's [simulate] table.
struct SimulateRequest {
  std::optional<double> rpm, depth_m, duration_s;
  RequestNames names;
  /// The simulations' progress (MillingSimulationOptions::progress): a front end's way to stop
  /// one long run.
  std::function<void(int, int)> progress;
  /// Where an error about the speed, depth or duration is: the request's names when it gave
  /// any of them, else the case.
  std::string where(const io::Case& c) const;
};

// ---- turning ----------------------------------------------------------------------------

struct TurningSimulationRun {
  std::string name;  // "conventional" or "vibration-assisted"
  TurningSimulationResult result;
  TurningBoundary predicted;  // the critical depth at this speed (closed form / full disc.)
};

struct TurningSimulationJobReport {
  std::string description;  // the model actually used
  TurningSimulationOptions options;
  std::vector<TurningSimulationRun> runs;  // the case's process first
  std::vector<std::string> warnings;       // e.g. a growth that has not settled
};

TurningSimulationJobReport simulate_turning_case(const io::Case& c, const SimulateRequest& r);

// ---- milling ----------------------------------------------------------------------------

/// The cut of a milling case with the speed, depth and length from the request or
/// [simulate]; `where` names the place an error about them belongs.
struct MillingSetup {
  MillingCut cut;
  MillingSimulationOptions options;
  double rpm = 0.0;
  std::string where;
};
MillingSetup milling_setup(const io::Case& c, const SimulateRequest& r);

struct MillingSimulationJobReport {
  MillingSetup setup;
  MillingSimulationResult result;
  bool s1_law = false;  // the force law of [force_law] (S1), else the mechanistic one
  // The lobes' critical depth at this speed (mechanistic law with regeneration and modes).
  std::optional<MillingBoundary> predicted;
  std::vector<std::string> warnings;
};

MillingSimulationJobReport simulate_milling_case(const io::Case& c, const SimulateRequest& r);

/// The summary metrics of a milling simulation a sweep can tabulate, by name: force_pulsation,
/// mean_force_n, peak_force_n, min_force_n, mean_teeth_in_cut, vibration_pp_x_um,
/// vibration_pp_y_um, chatter_indicator, contact_loss, surface_location_error_um (NaN where
/// the cut has none), cutting_force_pulsation, mean_cutting_force_n.
const std::vector<std::string>& milling_metric_names();
std::vector<double> milling_metrics(const MillingSimulationResult& r);

/// The index of the metric `metric` (`fallback` when empty) among `names`; an unknown name
/// throws InvalidInput at `where` naming `flag` and listing them.
std::size_t metric_index(const std::vector<std::string>& names, const std::string& metric,
                         const std::string& fallback, const std::string& flag,
                         const std::string& where);

/// One case key over a list of values: "KEY=FROM:STEP:TO" in MATLAB's colon notation.
struct Sweep {
  std::string key;
  std::vector<double> values;
};
/// The most values a sweep may take.
inline constexpr std::size_t kMaxSweepValues = 10000;
/// Throws InvalidInput (where "request") if `sweep` has no values or more than kMaxSweepValues.
void require_values(const Sweep& sweep);
/// At most kMaxSweepValues values, each rounded to 12 significant digits (0.1·3 = 0.3); a bad spec
/// throws InvalidInput naming `flag` at `where`.
Sweep parse_sweep(const std::string& spec, const std::string& flag = "sweep",
                  const std::string& where = "request");

struct MillingSweepJobReport {
  Sweep sweep;
  std::vector<MillingSimulationResult> results;  // one per value
};

/// Every varied case is read and checked before any simulation runs; the runs share
/// `threads` (0: all cores).
MillingSweepJobReport sweep_milling_case(const io::Case& c, const Sweep& sweep,
                                         const SimulateRequest& r, int threads,
                                         const std::function<void(int, int)>& progress = {});

}  // namespace cutdyn::app
