#include "cutdyn/simulate/simulation_status.hpp"

#include <cstdio>

namespace cutdyn {

const char* to_string(SimulationStatus status) {
  return status == SimulationStatus::kRunaway ? "runaway" : "completed";
}

std::string simulation_verdict(bool chatter, SimulationStatus status, double stop_time_s,
                               bool settled) {
  if (status == SimulationStatus::kRunaway) {
    char text[96];
    std::snprintf(text, sizeof text, "chatter (runaway growth, stopped at t = %.4g s)",
                  stop_time_s);
    return text;
  }
  const std::string verdict = chatter ? "chatter" : "stable";
  return settled ? verdict : verdict + " (uncertain: the growth has not settled; run longer)";
}

}  // namespace cutdyn
