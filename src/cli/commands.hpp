// The commands of the `cutdyn` program. Each returns the exit code; errors are thrown
// (cutdyn::InvalidInput → exit 2, anything else → exit 1) and reported by app.cpp.
#pragma once

#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace cutdyn::io {
struct Case;
}

namespace cutdyn::cli {

struct Outputs {
  std::string csv;   // --out
  std::string json;  // --json
  std::string plot;  // --plot
};

struct LobesArgs {
  std::string case_path;
  Outputs outputs;
  std::string method;  // empty: the case's [lobes].method
  int threads = 0;
  std::optional<double> target_depth_mm;  // list the speed ranges stable at this depth
};
int run_lobes(const LobesArgs& args, std::ostream& out, std::ostream& err);

struct CheckArgs {
  std::string case_path;
  double rpm = 0.0;
  double depth_mm = 0.0;
  std::string json;
  std::string method;
};
int run_check(const CheckArgs& args, std::ostream& out, std::ostream& err);

struct SimulateArgs {
  std::string case_path;
  Outputs outputs;
  std::optional<double> rpm;
  std::optional<double> depth_mm;
  std::optional<double> duration_s;
  std::string sweep;   // "KEY=FROM:STEP:TO": vary one case key (milling)
  std::string metric;  // the summary metric a sweep tabulates and plots
  int threads = 0;
};
int run_simulate(const SimulateArgs& args, std::ostream& out, std::ostream& err);

struct ForceArgs {
  std::string case_path;
  std::string json;
  std::string plot;
};
int run_force(const ForceArgs& args, std::ostream& out, std::ostream& err);

struct DriveArgs {
  std::string case_path;
  Outputs outputs;  // --out: traces per axis; --json; --plot: speed and position error
  std::optional<double> rpm;
  std::optional<double> depth_mm;
  std::string currents;  // --currents F.csv: synthesised motor phase currents
  std::string sweep;     // KEY=FROM:STEP:TO
  std::string metric;
  int threads = 0;
  std::optional<int> seed;  // --seed: the current noise's seed for every axis (else the case's)
};
int run_drive(const DriveArgs& args, std::ostream& out, std::ostream& err);

struct PlanArgs {
  std::string case_path;
  std::string json;
  std::string plot;                     // the trade-off (needs [limits])
  std::optional<double> axial_feed_mm;  // a fixed S0 (else the largest)
};
int run_plan(const PlanArgs& args, std::ostream& out, std::ostream& err);

/// The milling half of `simulate` (the command dispatches on the case's process).
int run_simulate_milling(const SimulateArgs& args, const io::Case& c, std::ostream& out,
                         std::ostream& err);

// ---- monitor: cutting force from servo-motor currents (docs/models/monitor.md) ----------

/// `cutdyn monitor calibrate`: steps 1 (idle logs) and 2 (loaded logs) per axis.
struct MonitorCalibrateArgs {
  std::vector<std::string> idle;     // --idle: no-cut logs at constant speeds
  std::vector<std::string> loaded;   // --loaded: logs with a reference force column
  std::string base;                  // --base: a calibration file or "zheng2012"
  std::vector<std::string> kt;       // --kt [AXIS=]VALUE, N·m/A
  std::vector<std::string> inertia;  // --inertia [AXIS=]VALUE, kg·m²
  std::string measure;               // --measure rms|space-vector
  std::string force_column = "force_n";
  double window_s = 0.05;
  double steady_tolerance = 0.01;
  double standstill_rad_s = 0.5;
  std::string on_bad_line = "stop";
  std::string out;  // --out calib.json (required)
};
int run_monitor_calibrate(const MonitorCalibrateArgs& args, std::ostream& out, std::ostream& err);

/// `cutdyn monitor estimate` and `cutdyn monitor teach` share the estimator's settings.
struct MonitorEstimatorArgs {
  std::string calib;  // --calib C.json (or "zheng2012")
  double bandwidth_hz = 50.0;
  double standstill_rad_s = 0.5;
  std::string on_bad_line = "stop";
};

struct MonitorEstimateArgs {
  MonitorEstimatorArgs estimator;
  std::string input = "-";  // INPUT.csv, or - for standard input
  std::string out;          // --out F.csv (else standard output, line by line)
  std::string band;         // --band B.json: add level/limits/alarm columns
  std::string alarms;       // --alarms F.csv: the alarm events
  double tooth_frequency_hz = 0.0;  // --tooth-frequency-hz: report the filter there (0: not)
  std::string json;                 // --json F.json: the summary (filter, warnings) as JSON
  double persist_s = 0.005;
  double wear_fraction = 0.15;
  double wear_time_constant_s = 0.5;
};
int run_monitor_estimate(const MonitorEstimateArgs& args, std::ostream& out, std::ostream& err);

struct MonitorTeachArgs {
  MonitorEstimatorArgs estimator;
  std::vector<std::string> inputs;  // reference runs (one cycle each)
  std::string out;                  // --out band.json (required)
  // A milling cut's spindle speed and teeth (both or neither): the level is then averaged
  // over the tooth period (BandOptions::for_milling); the options below, where given, win.
  std::optional<double> rpm;
  std::optional<int> teeth;
  double bin_s = 0.01;
  std::optional<double> smoothing_s;
  double k_sigma = 3.0;
  double relative_margin = 0.1;
  double absolute_margin_n = 0.0;
  double peak_margin = 0.05;
  double cutting_fraction = 0.2;
  std::optional<double> phase_tolerance_s;
  std::optional<double> average_s;
};
int run_monitor_teach(const MonitorTeachArgs& args, std::ostream& out, std::ostream& err);

/// Registers `monitor` (calibrate, estimate, teach) on `app`. The returned function runs the
/// subcommand that was parsed and returns its exit code, or −1 if `monitor` was not used.
std::function<int(std::ostream&, std::ostream&)> add_monitor_command(CLI::App& app);

}  // namespace cutdyn::cli
