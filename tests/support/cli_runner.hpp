// Runs the `cutdyn` command line in-process (cli::run) and captures what it prints.
#pragma once

#include <sstream>
#include <string>
#include <vector>

#include "cli/app.hpp"

namespace cutdyn::testing {

struct CliResult {
  int code;
  std::string out;
  std::string err;
};

inline CliResult run_cutdyn(const std::vector<std::string>& args) {
  std::ostringstream out, err;
  const int code = cli::run(args, out, err);
  return {code, out.str(), err.str()};
}

}  // namespace cutdyn::testing
