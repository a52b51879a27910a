// The drive job ([Ermolaev2020]; docs/models/feed-drive.md): the case's feed drives under the
// force of its simulated milling cut. The cut is simulated over its whole length; each
// [[drives]] axis takes its share of the feed and the projection of the cutter's force, and is
// summarised over its periodic steady state at the spindle revolution. A front end builds
// the cut (the speed, depth and length it is asked for) and renders the Report.
#pragma once

#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "cutdyn/app/simulate.hpp"
#include "cutdyn/drive/feed_drive.hpp"
#include "cutdyn/drive/motor_currents.hpp"
#include "cutdyn/io/case_file.hpp"
#include "cutdyn/simulate/milling_simulation.hpp"

namespace cutdyn::app {

/// The milling cut a drive run simulates (the simulate job's cut of the case).
using DriveCut = MillingSetup;

struct DriveOptions {
  std::optional<int> seed;  // the current noise's seed for every axis (else the case's)
};

/// One axis under the cut.
struct DriveAxisReport {
  FeedAxis axis;                    // as run: pointing along the feed, its noise stream set
  double feed_speed_m_per_s = 0.0;  // its share of the feed velocity
  FeedDriveResult drive;
  std::vector<double> cutter_m;   // the cutter's deflection along the axis
  std::vector<double> epsilon_m;  // drive position error + cutter deflection
  // Peak-to-peak over the last summary revolutions, within the drive's steady window.
  double drive_pp_m = 0.0, cutter_pp_m = 0.0, epsilon_pp_m = 0.0;
  /// A speed loop with an integrator: the largest deviation of the table-cutter position from
  /// the programme over the same window, the cutter's deflection minus the drive's load lag
  /// (signed; none for the static characteristic or a P-only loop, which drift).
  std::optional<double> program_error_m;
};

struct DriveReport {
  DriveCut cut;
  DriveOptions options;
  std::vector<DriveAxisReport> axes;
  double traces_from_s = 0.0;  // the traces worth showing: the last summary revolutions
  /// The simulation's verdict on the cut the drives carry (as `cutdyn simulate` gives it):
  /// where it chatters, the ripples and ε are those of a chattering cut.
  bool chatter = false;
  std::string verdict;
};

/// "the cut chatters at N rpm, depth D mm (the simulation's verdict: …): …" for a run whose
/// cut chatters; empty otherwise.
std::string chatter_warning(const DriveReport& run);

/// Throws InvalidInput unless the case is a milling case with at least one [[drives]] table.
void require_drive_case(const io::Case& c);

/// The drives of case `c` under `cut`. Throws InvalidInput for a drive that cannot run.
DriveReport run_drive(const io::Case& c, const DriveCut& cut, const DriveOptions& options = {});
/// The same under the case's own cut at the request's (or [simulate]'s) speed and depth.
DriveReport run_drive(const io::Case& c, const SimulateRequest& request,
                      const DriveOptions& options = {});

/// The metrics of an axis a sweep tabulates, and their names: epsilon_um, drive_error_um,
/// cutter_error_um, k_delta, static_error, torque_ripple_nm, speed_ripple_rad_s, load_lag_um and
/// program_error_um (NaN without a speed-loop integrator).
const std::vector<std::string>& drive_metric_names();
std::vector<double> drive_metrics(const DriveAxisReport& a);

/// The phase currents of an axis' motor over the traces from `from_s` (the axis needs its
/// motor: pole_pairs, torque_constant_nm_per_a).
PhaseCurrents axis_currents(const DriveAxisReport& a, double from_s);

/// Throws InvalidInput (naming `source`) unless every axis has its motor (pole_pairs,
/// torque_constant_nm_per_a): what the phase currents need.
void require_motors(const DriveReport& report, const std::string& source);

/// The current log of the run's traces (the last summary revolutions) as `monitor` reads it
/// (docs/models/monitor.md §6): per axis a comment with its motor (axis, measure,
/// torque_constant_nm_per_a, pole_pairs), then time_s,axis,iu_a,iv_a,iw_a,speed_rad_s,
/// rotor_angle_rad. Throws as require_motors does.
void write_current_log(std::ostream& out, const DriveReport& report, const std::string& source);

/// A sweep of one case key: the case with each value, its cut from `cut_of` (all built, and
/// so checked, before any runs), then the runs on `threads` threads (0: all).
struct DriveSweepReport {
  std::string key;
  std::vector<double> values;
  std::vector<DriveReport> runs;  // one per value
};
DriveSweepReport run_drive_sweep(const io::Case& c, const std::string& key,
                                 const std::vector<double>& values,
                                 const std::function<DriveCut(const io::Case&)>& cut_of,
                                 const DriveOptions& options = {}, int threads = 0,
                                 const std::function<void(int, int)>& progress = {});
/// The same with each case's own cut at the request's (or [simulate]'s) speed and depth.
DriveSweepReport run_drive_sweep(const io::Case& c, const Sweep& sweep,
                                 const SimulateRequest& request, const DriveOptions& options = {},
                                 int threads = 0,
                                 const std::function<void(int, int)>& progress = {});

}  // namespace cutdyn::app
