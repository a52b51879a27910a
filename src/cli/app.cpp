#include "cli/app.hpp"

#include <CLI/CLI.hpp>

namespace cutdyn::cli {

int run(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  CLI::App app{"cutdyn: machining-process dynamics", "cutdyn"};
  app.set_version_flag("--version", std::string("cutdyn ") + CUTDYN_VERSION);
  std::vector<std::string> reversed(args.rbegin(), args.rend());
  try {
    app.parse(reversed);
  } catch (const CLI::Success&) {
    out << app.help();
    return 0;
  } catch (const CLI::ParseError& e) {
    err << "cutdyn: error: command line: " << e.what() << "\n";
    return 2;
  }
  return 0;
}

}  // namespace cutdyn::cli
