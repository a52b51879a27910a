// What every job's request shares: how the front end calls the request's inputs, so that an
// error names them as the user wrote them.
#pragma once

#include <string>

namespace cutdyn::app {

/// How a front end calls a request's inputs in error messages (the CLI: "command line",
/// "--rpm", "--depth-mm", …). A job names the case's own keys by the case.
struct RequestNames {
  std::string where = "request";
  std::string rpm = "rpm", depth = "depth_mm", duration = "duration_s", method = "method";
  // The monitor's calibration and estimate.
  std::string torque_constant = "torque_constant_nm_per_a", inertia = "inertia_kg_m2";
  std::string base = "base", idle = "idle", loaded = "loaded", measure = "measure";
  std::string bandwidth = "bandwidth_hz";
};

}  // namespace cutdyn::app
