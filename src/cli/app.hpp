// The `cutdyn` command line as a function, so that tests run it in-process.
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace cutdyn::cli {

/// Runs `cutdyn args...` (args without the program name). Text for people goes to `out`,
/// errors to `err` as "cutdyn: error: <where>: <what>". Returns the exit code: 0 success,
/// 2 bad usage or bad input, 1 anything else.
int run(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace cutdyn::cli
