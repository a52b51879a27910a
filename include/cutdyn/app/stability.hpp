// The stability jobs: `lobes` (the lobe diagram of a case, its lowest depth, stable pockets and
// the recommended speed at a target depth) and `check` (one speed and depth: the verdict and
// its margin). A job takes a case and a request and returns a report of what it used and
// found; the front ends only render reports. Turning and milling, chosen by the case.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cutdyn/app/request.hpp"
#include "cutdyn/io/case_file.hpp"
#include "cutdyn/stability/advice.hpp"
#include "cutdyn/stability/lobes.hpp"
#include "cutdyn/stability/turning.hpp"

namespace cutdyn::app {

struct LobesRequest {
  std::string method;                    // a stability method name; empty: the case's [lobes]
  int threads = 0;                       // 0: all cores
  std::optional<double> target_depth_m;  // list the speed ranges stable at this depth
  std::function<void(int, int)> progress;
  RequestNames names;
};

struct LobesJobReport {
  std::string description;  // one line about the model actually used (Kt given or predicted…)
  ModalModel fitted_modes;  // the modes fitted to the case's [[frf]] tables (none without)
  std::string method;       // the method resolved ("auto" never appears here)
  double depth_max_m = 0.0;
  LobesReport lobes;  // the boundary at each speed; lobes.message if the trace fell short
  // Vibration-assisted turning: the conventional lobes at the same speeds (closed form).
  std::vector<CriticalDepth> reference;
  std::string reference_label;
  bool duty_cycle = false;           // the points carry the duty cycle (vibration-assisted turning)
  std::string title;                 // of a figure
  std::string label;                 // of the main curve
  std::size_t lowest = 0;            // index of the lowest critical depth
  std::vector<std::size_t> pockets;  // stable pockets (local maxima), at most 3
  std::optional<double> target_depth_m;
  std::vector<SpeedRange> stable_ranges;  // at the target depth
  SpeedAdvice advice;                     // the recommended speed at the target depth
  std::vector<std::string> warnings;      // where the method is weak
};

/// Throws cutdyn::InvalidInput naming the case or the request for anything it cannot run.
LobesJobReport run_lobes(const io::Case& c, const LobesRequest& request);

/// Throws InvalidInput (where() unset) when a milling cutter of `teeth` at `rpm` is outside
/// the speeds the full discretization and the regenerative simulation take: one tooth period
/// spanning more than 500 periods of the highest mode (`top_mode_hz`); their work grows with
/// it (a simulation at 30 rpm of a 922 Hz mode needed more memory than the machine had).
void check_milling_speed(int teeth, double top_mode_hz, double rpm);

struct CheckRequest {
  double rpm = 0.0;
  double depth_m = 0.0;
  std::string method;  // empty: the case's [lobes]
  RequestNames names;
};

struct CheckJobReport {
  std::string description;
  ModalModel fitted_modes;  // the modes fitted to the case's [[frf]] tables (none without)
  std::string method;
  double rpm = 0.0, depth_m = 0.0;
  CriticalDepth boundary;
  int lobe = 0;
  bool stable = false;  // the depth asked lies below the critical depth (or none was found)
  // (critical − asked)/critical: a lower bound when no boundary was found, none when the
  // process chatters at any depth (critical depth 0).
  std::optional<double> margin;
  std::optional<double> duty_cycle;  // turning: 1 conventional, < 1 vibration-assisted
  struct Conventional {
    CriticalDepth boundary;
    bool stable = false;
  };
  std::optional<Conventional> conventional;  // vibration-assisted turning, for comparison
  std::vector<std::string> warnings;         // where the method is weak at this speed
};

/// Throws cutdyn::InvalidInput naming the case or the request ("command line" for the speed
/// and depth) for anything it cannot run.
CheckJobReport run_check(const io::Case& c, const CheckRequest& request);

/// One line about the turning model actually used: modes, Kt (and whether Oxley's theory
/// predicted it), the vibration.
std::string describe_turning(const io::Case& c, const TurningProcess& m);
/// The stability options of the case's [lobes] table for `method`.
TurningStabilityOptions turning_stability_options(const io::Case& c, TurningMethod method);

}  // namespace cutdyn::app
