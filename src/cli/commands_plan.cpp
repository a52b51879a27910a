// `cutdyn plan`: two-edge face milling of a large bore ([Zenkin2012];
// docs/models/bore-milling.md).
#include <optional>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cutdyn/app/plan.hpp"
#include "cutdyn/app/render.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/io/output.hpp"
#include "cutdyn/io/plot.hpp"

namespace cutdyn::cli {

int run_plan(const PlanArgs& args, std::ostream& out, std::ostream& err) {
  const io::Case c =
      load_case(args.case_path, "bore-plan", err, {{"--json", args.json}, {"--plot", args.plot}});
  if (!args.plot.empty() && c.bore && !c.bore_limits)
    throw InvalidInput({"--plot: the trade-off needs the [limits] table"}, c.source);
  app::PlanRequest request;
  if (args.axial_feed_mm) request.axial_feed_m = units::mm_to_m(*args.axial_feed_mm);
  request.names = flag_names();
  request.axial_feed_name = "--axial-feed-mm";
  const app::PlanJobReport job = app::run_plan(c, request);
  app::write_text(out, c, job);
  for (const std::string& w : job.warnings)
    err << "cutdyn: warning: " << job.where << ": " << w << "\n";
  io::OutputTransaction outputs;
  if (!args.json.empty()) io::write_json(outputs.open(args.json), app::to_json(c, job));
  if (!args.plot.empty()) io::write_plot(app::figure(job), args.plot, outputs);
  commit_outputs(outputs, {"", args.json, args.plot}, out);
  return 0;
}

}  // namespace cutdyn::cli
