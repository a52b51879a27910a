#include <cerrno>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "cli/app.hpp"

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  const int code = cutdyn::cli::run(args, std::cout, std::cerr);
  // The reader of the standard output closed it (`monitor estimate ... | head -1`): the run
  // ended quietly on purpose, with its own status.
  if (code == cutdyn::cli::kExitOutputClosed) return code;
  // A report that could not be written (a full disk, a closed file) is a failure too. A
  // command that failed has said why (`monitor estimate` names the failed standard output
  // itself): its status stands, without a second message.
  if (!std::cout.flush() && code == 0) {
    std::cerr << "cutdyn: error: cannot write standard output (" << std::strerror(errno) << ")\n";
    return 1;
  }
  return code;
}
