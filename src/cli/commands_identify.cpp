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
namespace {}  // namespace

int run_identify(const IdentifyArgs& args, std::ostream& out, std::ostream& err) {
  check_outputs(args.outputs, args.force_files);
  const io::Case c =
      load_case(args.case_path, "milling-insperger", err, output_flags(args.outputs));
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
