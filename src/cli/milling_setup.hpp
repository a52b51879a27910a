// The milling cut of a case, as `cutdyn simulate` and `cutdyn drive` run it.
#pragma once

#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "cutdyn/app/simulate.hpp"
#include "cutdyn/io/case_file.hpp"
#include "cutdyn/simulate/milling_simulation.hpp"

namespace cutdyn::cli {

/// The cut of the case, with the speed, depth and length from the flags or [simulate]
/// (app::milling_setup with the flags' names).
using SimulationSetup = app::MillingSetup;
app::SimulateRequest simulate_request(const SimulateArgs& args);
/// Every problem with the case or the flags throws cutdyn::InvalidInput.
SimulationSetup milling_setup(const SimulateArgs& args, const io::Case& c);

/// A sweep of one case key over FROM:STEP:TO (--sweep).
using app::Sweep;
/// "KEY=FROM:STEP:TO" (MATLAB's colon notation), at most 10 000 values; a bad spec throws
/// cutdyn::InvalidInput at "command line".
Sweep parse_sweep(const std::string& spec);

/// The column of `--metric` (`fallback` when not given) among `names`; an unknown name throws
/// cutdyn::InvalidInput listing them.
std::size_t metric_column(const std::string& metric, const std::string& fallback,
                          const std::vector<std::string>& names);

}  // namespace cutdyn::cli
