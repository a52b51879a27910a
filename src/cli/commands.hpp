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

// ---- identify: milling coefficients from measured forces (docs/models/identification.md) --

struct IdentifyArgs {
  std::string case_path;
  std::vector<std::string> force_files;  // FORCES.csv...
  Outputs outputs;  // --out: the [cutting] table (TOML); --json; --plot: force against feed
};
int run_identify(const IdentifyArgs& args, std::ostream& out, std::ostream& err);

// ---- fit: modes fitted to a measured FRF (docs/models/modal-fitting.md) --------------------

struct FitArgs {
  std::string file;
  std::string modes = "auto";  // --modes N | auto
  std::string band;            // --band LO:HI (Hz)
  std::string direction;       // empty: the file's (UFF), else x
  std::string format;          // --format frf|csv|uff; empty: from the content
  std::string units;           // --units "Hz, mm/N" (CutPro text); empty: the file's header
  Outputs outputs;             // --out: [[modes]] tables (TOML); --json; --plot
};
int run_fit(const FitArgs& args, std::ostream& out, std::ostream& err);

/// The milling half of `simulate` (the command dispatches on the case's process).
int run_simulate_milling(const SimulateArgs& args, const io::Case& c, std::ostream& out,
                         std::ostream& err);

// ---- monitor: cutting force from servo-motor currents (docs/models/monitor.md) ----------
// The jobs and their options are the library's (cutdyn/app/monitor.hpp).

/// Registers `monitor` (calibrate, estimate, teach) on `app`. The returned function runs the
/// subcommand that was parsed and returns its exit code, or −1 if `monitor` was not used.
std::function<int(std::ostream&, std::ostream&)> add_monitor_command(CLI::App& app);
/// `cutdyn serve` (commands_serve.cpp), the same way.
std::function<int(std::ostream&, std::ostream&)> add_serve_command(CLI::App& app);
/// `cutdyn sweep` (commands_sweep.cpp), the same way.
std::function<int(std::ostream&, std::ostream&)> add_sweep_command(CLI::App& app);

}  // namespace cutdyn::cli
