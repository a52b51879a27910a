// `cutdyn drive`: the feed drives under the simulated milling load ([Ermolaev2020];
// docs/models/feed-drive.md). The job is the library's (cutdyn/app/drive.hpp); this file
// builds the cut from the flags and renders the Report.

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/milling_setup.hpp"
#include "cutdyn/app/drive.hpp"
#include "cutdyn/app/render.hpp"
#include "cutdyn/app/report_json.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/io/output.hpp"
#include "cutdyn/io/plot.hpp"

namespace cutdyn::cli {
namespace {

constexpr const char* kDefaultDriveCase = "ermolaev2020";

// Each axis' warnings on stderr, "cutdyn: warning: SOURCE: [PREFIX]axis x: …".
void warn(std::ostream& err, const std::string& source, const std::string& prefix,
          const app::DriveReport& run) {
  if (run.chatter)
    err << "cutdyn: warning: " << source << ": " << prefix << app::chatter_warning(run) << "\n";
  for (const app::DriveAxisReport& a : run.axes)
    for (const std::string& w : a.drive.warnings)
      err << "cutdyn: warning: " << source << ": " << prefix << "axis " << a.axis.name << ": " << w
          << "\n";
}

// The flags' speed and depth for the drive's cut.
app::SimulateRequest drive_request(const DriveArgs& args) {
  app::SimulateRequest r;
  r.rpm = args.rpm;
  if (args.depth_mm) r.depth_m = units::mm_to_m(*args.depth_mm);
  r.names = flag_names();
  return r;
}

void write_sweep_files(const DriveArgs& args, const app::DriveSweepReport& sweep, const io::Case& c,
                       std::size_t column, io::OutputTransaction& outputs) {
  const auto& names = app::drive_metric_names();
  if (!args.outputs.csv.empty()) write_csv(outputs, args.outputs.csv, app::sweep_table(sweep));
  if (!args.outputs.json.empty())
    io::write_json(outputs.open(args.outputs.json), app::to_json(c, sweep, names[column]));
  if (!args.outputs.plot.empty())
    io::write_plot(app::figure(c, sweep, column), args.outputs.plot, outputs);
}

int run_sweep(const DriveArgs& args, const io::Case& c, std::ostream& out, std::ostream& err) {
  const Sweep spec = parse_sweep(args.sweep);
  const std::size_t column = metric_column(args.metric, "epsilon_um", app::drive_metric_names());
  const app::DriveSweepReport sweep = app::run_drive_sweep(
      c, spec, drive_request(args), {args.seed}, args.threads, progress_reporter(err, "sweep"));
  for (std::size_t i = 0; i < sweep.runs.size(); ++i)
    warn(err, c.source, sweep.key + " = " + human(sweep.values[i]) + ", ", sweep.runs[i]);
  app::write_text(out, c, sweep, column);
  io::OutputTransaction outputs;
  write_sweep_files(args, sweep, c, column, outputs);
  commit_outputs(outputs, args.outputs, out);
  return 0;
}

// The traces of each axis over the last summary revolutions (CSV), and their figure.
void write_traces(const DriveArgs& args, const app::DriveReport& run,
                  io::OutputTransaction& outputs) {
  if (!args.outputs.csv.empty()) write_csv(outputs, args.outputs.csv, app::trace_table(run));
  if (!args.outputs.plot.empty()) io::write_plot(app::figure(run), args.outputs.plot, outputs);
}

}  // namespace

int run_drive(const DriveArgs& args, std::ostream& out, std::ostream& err) {
  std::vector<OutputFlag> files = output_flags(args.outputs);
  files.push_back({"--currents", args.currents});
  const io::Case c = load_case(args.case_path, kDefaultDriveCase, err, files);
  if (!args.sweep.empty()) {
    if (!args.currents.empty())
      throw InvalidInput({"--currents: not with --sweep"}, "command line");
    return run_sweep(args, c, out, err);
  }
  if (!args.metric.empty()) throw InvalidInput({"--metric: only with --sweep"}, "command line");
  const app::DriveReport run = app::run_drive(c, drive_request(args), {args.seed});
  if (!args.currents.empty()) app::require_motors(run, c.source);
  app::write_text(out, c, run);
  warn(err, c.source, "", run);

  io::OutputTransaction outputs;
  write_traces(args, run, outputs);
  if (!args.currents.empty()) app::write_current_log(outputs.open(args.currents), run, c.source);
  if (!args.outputs.json.empty())
    io::write_json(outputs.open(args.outputs.json), app::to_json(c, run));
  outputs.commit();
  for (const std::string* f :
       {&args.outputs.csv, &args.currents, &args.outputs.json, &args.outputs.plot})
    if (!f->empty()) out << "  wrote " << *f << "\n";
  return 0;
}

}  // namespace cutdyn::cli
