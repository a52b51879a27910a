// The `cutdyn` command line as a function, so that tests run it in-process.
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace cutdyn::cli {

/// `monitor estimate` writing to standard output, whose reader closed it (`| head -1`): 128 +
/// SIGPIPE, the status the shell reports for a program that SIGPIPE ended; no message.
inline constexpr int kExitOutputClosed = 141;

/// Runs `cutdyn args...` (args without the program name). Text for people goes to `out`,
/// errors to `err` as "cutdyn: error: <where>: <what>". Returns the exit code: 0 success,
/// 2 bad usage or bad input, 1 anything else, kExitOutputClosed when `monitor estimate`
/// stopped because the reader of its standard output closed it.
int run(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace cutdyn::cli
