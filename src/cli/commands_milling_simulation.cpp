// `cutdyn simulate` for milling: the time-domain simulation, force laws after
// [Ermolaev2020] (docs/models/milling-simulation.md).
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/milling_setup.hpp"
#include "cutdyn/app/render.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/io/output.hpp"
#include "cutdyn/io/plot.hpp"
#include "cutdyn/simulate/milling_simulation.hpp"

namespace cutdyn::cli {
namespace {

using units::mm_to_m;

}  // namespace

app::SimulateRequest simulate_request(const SimulateArgs& args) {
  app::SimulateRequest r;
  r.rpm = args.rpm;
  if (args.depth_mm) r.depth_m = mm_to_m(*args.depth_mm);
  r.duration_s = args.duration_s;
  r.names = flag_names();
  return r;
}

SimulationSetup milling_setup(const SimulateArgs& args, const io::Case& c) {
  return app::milling_setup(c, simulate_request(args));
}

// The column of --metric among `names`.
std::size_t metric_column(const std::string& metric, const std::string& fallback,
                          const std::vector<std::string>& names) {
  return app::metric_index(names, metric, fallback, "--metric", "command line");
}

Sweep parse_sweep(const std::string& spec) {
  return app::parse_sweep(spec, "--sweep", "command line");
}

namespace {

int run_sweep(const SimulateArgs& args, const io::Case& c, std::ostream& out, std::ostream& err) {
  const auto& names = app::milling_metric_names();
  const std::size_t column = metric_column(args.metric, "force_pulsation", names);
  const std::string& metric = names[column];
  const app::MillingSweepJobReport job =
      app::sweep_milling_case(c, parse_sweep(args.sweep), simulate_request(args), args.threads,
                              progress_reporter(err, "sweep"));
  app::write_text(out, c, job, column);

  io::OutputTransaction outputs;
  if (!args.outputs.csv.empty()) {
    write_csv(outputs, args.outputs.csv, app::sweep_table(job));
  }
  if (!args.outputs.json.empty())
    io::write_json(outputs.open(args.outputs.json), app::to_json(c, job, metric));
  if (!args.outputs.plot.empty())
    io::write_plot(app::figure(c, job, column), args.outputs.plot, outputs);
  commit_outputs(outputs, args.outputs, out);
  return 0;
}

}  // namespace

int run_simulate_milling(const SimulateArgs& args, const io::Case& c, std::ostream& out,
                         std::ostream& err) {
  if (!args.sweep.empty()) return run_sweep(args, c, out, err);
  if (!args.metric.empty()) throw InvalidInput({"--metric: only with --sweep"}, "command line");
  const app::MillingSimulationJobReport job = app::simulate_milling_case(c, simulate_request(args));
  app::write_text(out, c, job);
  for (const std::string& w : job.warnings)
    err << "cutdyn: warning: " << c.source << ": " << w << "\n";
  io::OutputTransaction outputs;
  if (!args.outputs.csv.empty()) {
    write_csv(outputs, args.outputs.csv, app::trace_table(job));
  }
  if (!args.outputs.json.empty())
    io::write_json(outputs.open(args.outputs.json), app::to_json(c, job));
  if (!args.outputs.plot.empty()) io::write_plot(app::figure(job), args.outputs.plot, outputs);
  commit_outputs(outputs, args.outputs, out);
  return 0;
}

}  // namespace cutdyn::cli
