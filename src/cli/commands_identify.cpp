// `cutdyn identify`: milling cutting and edge coefficients from the mean forces of test cuts
// (the average-force method of [Altintas2012, ch. 2]; docs/models/identification.md).
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cutdyn/app/identify.hpp"
#include "cutdyn/app/render.hpp"
#include "cutdyn/io/output.hpp"
#include "cutdyn/io/plot.hpp"

namespace cutdyn::cli {
namespace {

// An output that names an input would overwrite it: refused before any work.
void check_outputs_are_not_inputs(const IdentifyArgs& args) {
  namespace fs = std::filesystem;
  std::vector<std::string> inputs = args.force_files;
  std::error_code ec;  // a path that cannot be resolved names no input
  if (fs::is_regular_file(args.case_path, ec)) inputs.push_back(args.case_path);
  const auto same = [&](const std::string& a, const std::string& b) {
    const fs::path x = fs::weakly_canonical(a, ec);
    if (ec) return false;
    const fs::path y = fs::weakly_canonical(b, ec);
    return !ec && x == y;
  };
  Validator v;
  const auto check = [&](const char* flag, const std::string& path) {
    if (path.empty() || path == "-") return;
    for (const std::string& input : inputs)
      if (same(path, input))
        v.add(std::string(flag) + " = " + path + ": it is an input of the command (" + input +
              ") and would be overwritten");
  };
  check("--out", args.outputs.csv);
  check("--json", args.outputs.json);
  check("--plot", args.outputs.plot);
  v.throw_if_any("command line");
}

}  // namespace

int run_identify(const IdentifyArgs& args, std::ostream& out, std::ostream& err) {
  check_outputs(args.outputs);
  check_outputs_are_not_inputs(args);
  const io::Case c = load_case(args.case_path, "milling-insperger", err);
  app::IdentifyRequest request;
  for (const std::string& f : args.force_files) request.force_files.emplace_back(f);
  request.names = flag_names();
  const app::IdentifyJobReport r = app::run_identify(c, request);
  app::write_text(out, c, r);
  for (const std::string& w : r.warnings)
    err << "cutdyn: warning: " << c.source << ": " << w << "\n";
  io::OutputTransaction outputs;
  if (!args.outputs.csv.empty()) outputs.open(args.outputs.csv) << app::cutting_table_toml(c, r);
  if (!args.outputs.json.empty())
    io::write_json(outputs.open(args.outputs.json), app::to_json(c, r));
  if (!args.outputs.plot.empty()) io::write_plot(app::figure(r), args.outputs.plot, outputs);
  commit_outputs(outputs, args.outputs, out);
  return 0;
}

}  // namespace cutdyn::cli
