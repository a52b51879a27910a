// `cutdyn lobes`, `check`, `simulate` and `force` for turning, conventional and
// vibration-assisted.
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/milling_setup.hpp"
#include "cutdyn/app/force.hpp"
#include "cutdyn/app/render.hpp"
#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/io/output.hpp"
#include "cutdyn/io/plot.hpp"
#include "cutdyn/stability/lobes.hpp"

namespace cutdyn::cli {
namespace {

using units::mm_to_m;

constexpr std::string_view kDefaultTurningCase = "turning-ultrasonic";
constexpr std::string_view kDefaultForceCase = "ultrasonic-force";

}  // namespace

int run_lobes(const LobesArgs& args, std::ostream& out, std::ostream& err) {
  const io::Case c =
      load_case(args.case_path, kDefaultTurningCase, err, output_flags(args.outputs));
  app::LobesRequest request;  // the job checks the request (a positive target depth, …)
  request.method = args.method;
  request.threads = args.threads;
  if (args.target_depth_mm) request.target_depth_m = mm_to_m(*args.target_depth_mm);
  request.progress = progress_reporter(err, "lobes");
  request.names = flag_names();
  request.names.depth = "--target-depth-mm";
  const app::LobesJobReport r = app::run_lobes(c, request);
  if (r.lobes.status != LobesStatus::kSuccess)
    err << "cutdyn: warning: " << r.lobes.message << "\n";
  for (const std::string& w : r.warnings) err << "cutdyn: warning: " << w << "\n";
  app::write_text(out, c, r);
  io::OutputTransaction outputs;
  if (!args.outputs.csv.empty()) {
    write_csv(outputs, args.outputs.csv, app::lobes_table(r));
  }
  if (!args.outputs.json.empty())
    io::write_json(outputs.open(args.outputs.json), app::to_json(c, r));
  if (!args.outputs.plot.empty()) io::write_plot(app::figure(r), args.outputs.plot, outputs);
  commit_outputs(outputs, args.outputs, out);
  return 0;
}

int run_check(const CheckArgs& args, std::ostream& out, std::ostream& err) {
  const io::Case c = load_case(args.case_path, kDefaultTurningCase, err, {{"--json", args.json}});
  app::CheckRequest request;
  request.rpm = args.rpm;
  request.depth_m = mm_to_m(args.depth_mm);
  request.method = args.method;
  request.names = flag_names();
  const app::CheckJobReport r = app::run_check(c, request);
  app::write_text(out, c, r);  // (its warnings in the text)
  if (args.json.empty()) return 0;
  io::OutputTransaction outputs;
  io::write_json(outputs.open(args.json), app::to_json(c, r));
  outputs.commit();
  out << "  wrote " << args.json << "\n";
  return 0;
}

int run_simulate(const SimulateArgs& args, std::ostream& out, std::ostream& err) {
  const io::Case c =
      load_case(args.case_path, kDefaultTurningCase, err, output_flags(args.outputs));
  if (c.process == io::Process::kMilling) return run_simulate_milling(args, c, out, err);
  if (!args.sweep.empty() || !args.metric.empty())
    throw InvalidInput({"--sweep, --metric: sweeps take milling cases in this version"},
                       "command line");
  const app::TurningSimulationJobReport job = app::simulate_turning_case(c, simulate_request(args));
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

int run_force(const ForceArgs& args, std::ostream& out, std::ostream& err) {
  const io::Case c = load_case(args.case_path, kDefaultForceCase, err,
                               {{"--json", args.json}, {"--plot", args.plot}});
  const app::ForceJobReport r = app::run_force(c);
  app::write_text(out, c, r);

  io::OutputTransaction outputs;
  if (!args.json.empty()) io::write_json(outputs.open(args.json), app::to_json(c, r));
  if (!args.plot.empty()) io::write_plot(app::figure(c, r), args.plot, outputs);
  outputs.commit();
  for (const std::string* file : {&args.json, &args.plot})
    if (!file->empty()) out << "  wrote " << *file << "\n";
  return 0;
}

}  // namespace cutdyn::cli
