// How a time-domain simulation ended, and the verdict the front ends print.
#pragma once

#include <string>

namespace cutdyn {

enum class SimulationStatus {
  kCompleted,  // integrated over the whole requested duration
  kRunaway,    // stopped early: the vibration grew past the runaway bound (chatter)
};

/// "completed" or "runaway".
const char* to_string(SimulationStatus status);

/// The verdict of a run: "stable", "chatter", or "chatter (runaway growth, stopped at t = …
/// s)"; a completed run whose growth estimate has not settled adds " (uncertain: the growth
/// has not settled; run longer)". One rule for every front end.
std::string simulation_verdict(bool chatter, SimulationStatus status, double stop_time_s,
                               bool settled = true);

}  // namespace cutdyn
