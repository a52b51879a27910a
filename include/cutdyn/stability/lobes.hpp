// Stability lobes: the critical depth at every spindle speed of a grid, in parallel.
#pragma once

#include <functional>
#include <span>
#include <string>
#include <vector>

#include "cutdyn/core/fields.hpp"
#include "cutdyn/stability/critical_depth.hpp"

namespace cutdyn {

struct LobesOptions {
  double rpm_min = 500.0;
  double rpm_max = 5000.0;
  int rpm_steps = 200;  // speeds on a uniform grid, both ends included
  int threads = 0;      // 0: all cores (OpenMP)
  /// Adaptive refinement: speeds are added between two neighbours of the grid where the
  /// boundary changes lobe or bifurcation type (a cusp, i.e. the peak of a stable pocket,
  /// lies between them) or the critical depth changes by more than `refine_change` of the
  /// smaller one (a lobe narrower than the grid), halving the interval up to
  /// `refine_levels` times; at most `refine_max_points` speeds in all.
  bool refine = true;
  int refine_levels = 8;
  double refine_change = 0.2;
  int refine_max_points = 20000;

  /// The members a user sets, with their keys, units and ranges (core/fields.hpp): the case
  /// file's `[lobes]` grid keys and validate() both read them.
  static std::span<const Field<LobesOptions>> fields();
  std::vector<std::string> validate() const;
  std::vector<double> speeds_rpm() const;
};

/// Per-speed boundary with the extra columns a process adds (duty cycle, lobe number, ...).
struct LobePoint {
  double rpm = 0.0;
  CriticalDepth boundary;
  double duty_cycle = 1.0;
  int lobe = 0;
};

enum class LobesStatus {
  kSuccess,
  /// At some speeds a boundary candidate could not be resolved (CriticalDepth::unresolved);
  /// those depths may be too large. `message` lists the speeds.
  kUnresolvedCrossings,
  /// At some speeds the method's approximation could not cover the case
  /// (CriticalDepth::truncated), or the full discretization's boundary did not converge as
  /// its step was halved (CriticalDepth::unconverged); `message` lists the speeds (and any
  /// unresolved ones).
  kTruncated,
};

struct LobesReport {
  LobesStatus status = LobesStatus::kSuccess;
  std::string message;            // empty on success
  std::vector<LobePoint> points;  // ascending speed
  double seconds = 0.0;
  long long evaluations = 0;
  LobesOptions options;  // as used
};

/// Calls `at_speed(rpm)` for every speed of the grid, spread over threads, then for the
/// speeds the adaptive refinement adds (LobesOptions::refine), and gathers the points in
/// ascending speed order. `progress(done, total)`, if set, is called from one thread at a
/// time as speeds complete. An exception thrown by `at_speed` is rethrown after the loop.
LobesReport trace_lobes(const std::function<LobePoint(double rpm)>& at_speed,
                        const LobesOptions& options,
                        const std::function<void(int done, int total)>& progress = {});

/// A speed's boundary computed with the points already known next to it: `near` holds the
/// nearest computed speeds (up to three; empty for the first speed of a run), nearest first.
using WarmSpeedFunction =
    std::function<LobePoint(double rpm, const std::vector<const LobePoint*>& near)>;

/// Speeds per run of trace_lobes_warm, on average.
inline constexpr int kWarmRunLength = 16;

/// The last share of the cost is cut into this many shorter runs.
inline constexpr int kWarmTailRuns = 3;

/// The first index of each run of trace_lobes_warm and, last, the number of speeds: R = about
/// n / kWarmRunLength shares (at least one) of equal estimated cost, the cost of a speed taken
/// as its period (1/rpm), as the period map's steps grow; with R > 1 the last share is cut into
/// kWarmTailRuns runs (the threads take the runs in order, and the last ones short let them
/// finish together). A function of the speeds alone.
std::vector<int> warm_run_starts(const std::vector<double>& speeds_rpm);

/// trace_lobes for a method that starts each speed from its neighbours (warm start): the
/// uniform grid is cut into runs of consecutive speeds (warm_run_starts), each run traced in
/// ascending order on one thread with `near` = the previous three speeds of the run (fewer at
/// its start, none for its first); the threads share the runs. The refinement adds speeds as
/// trace_lobes does, each with `near` = the two speeds it lies between. Whatever `at_speed`
/// does with `near`, the speeds and the order of the points are those of trace_lobes, and the
/// points do not depend on the number of threads; `progress` counts speeds.
LobesReport trace_lobes_warm(const WarmSpeedFunction& at_speed, const LobesOptions& options,
                             const std::function<void(int done, int total)>& progress = {});

/// The adaptive refinement of trace_lobes on its own: adds speeds to `points` (ascending)
/// as LobesOptions::refine describes.
void refine_lobes(const std::function<LobePoint(double rpm)>& at_speed, const LobesOptions& options,
                  std::vector<LobePoint>& points);

/// Adds to `points` (ascending) the points at every speed of `other` that it lacks, computed
/// by `at_speed` in parallel: two curves traced with their own refinement, made to share
/// their speeds.
void complete_lobes(const std::function<LobePoint(double rpm)>& at_speed,
                    const std::vector<LobePoint>& other, std::vector<LobePoint>& points,
                    int threads = 0);

/// Critical depth at one speed from a stability margin g(w) (< 0 stable, >= 0 unstable, and
/// continuous, e.g. spectral radius − 1): scans [0, depth_max] in `coarse_steps` equal steps
/// for the first unstable depth (so that an unstable island above a stable band is not
/// skipped), then Brent's method on that bracket to boundary_tolerance(): rel_tol times the
/// grid point above the boundary, and below an eighth of the first grid point, rel_tol times
/// the boundary (the first cell is narrowed by factors of 8 until its lower end is stable).
/// `evaluations` counts the calls of g.
CriticalDepth critical_depth_by_bracketing(const std::function<double(double depth_m)>& margin,
                                           double depth_max_m, int coarse_steps, double rel_tol);

/// The absolute tolerance to which critical_depth_by_bracketing finds a boundary at `depth_m`:
/// rel_tol·c·ceil(depth/c) with c = depth_max/coarse_steps, the grid point at or above it;
/// below c/8, rel_tol·t/8 with t = c/8^k the smallest such power with depth <= t (at most
/// rel_tol·depth).
double boundary_tolerance(double depth_m, double depth_max_m, int coarse_steps, double rel_tol);

}  // namespace cutdyn
