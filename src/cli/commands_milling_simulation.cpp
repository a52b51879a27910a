// `cutdyn simulate` for milling: the time-domain simulation, force laws after
// [Ermolaev2020] (docs/models/milling-simulation.md).
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

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

using nlohmann::json;
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
  const std::string name = metric.empty() ? fallback : metric;
  const auto chosen = std::find(names.begin(), names.end(), name);
  if (chosen == names.end()) {
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
    throw InvalidInput({"--metric = \"" + name + "\": must be one of " + list}, "command line");
  }
  return static_cast<std::size_t>(chosen - names.begin());
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
  const Sweep& sweep = job.sweep;
  const auto& results = job.results;
  const auto metrics = app::milling_metrics;

  app::write_text(out, c, job, column);

  io::OutputTransaction outputs;
  if (!args.outputs.csv.empty()) {
    std::vector<std::string> header{sweep.key};
    header.insert(header.end(), names.begin(), names.end());
    header.push_back("chatter");
    io::CsvWriter csv(outputs.open(args.outputs.csv), header);
    for (std::size_t i = 0; i < results.size(); ++i) {
      std::vector<io::CsvCell> row{sweep.values[i]};
      for (double m : metrics(results[i])) {
        if (std::isnan(m))
          row.emplace_back(std::string());
        else
          row.emplace_back(m);
      }
      row.emplace_back(results[i].chatter ? 1LL : 0LL);
      csv.row(row);
    }
  }
  if (!args.outputs.json.empty()) {
    json points = json::array();
    for (std::size_t i = 0; i < results.size(); ++i) {
      json p{{"value", sweep.values[i]},
             {"chatter", results[i].chatter},
             {"status", to_string(results[i].status)}};
      const auto m = metrics(results[i]);
      for (std::size_t k = 0; k < names.size(); ++k)
        p[names[k]] = std::isnan(m[k]) ? json() : json(m[k]);
      points.push_back(std::move(p));
    }
    json doc{{"command", "simulate"},      {"schema_version", kJsonSchemaVersion},
             {"case", io::to_json(c)},     {"source", c.source},
             {"sweep", sweep.key},         {"metric", metric},
             {"points", std::move(points)}};
    io::write_json(outputs.open(args.outputs.json), doc);
  }
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
    const app::ReportTable table = app::trace_table(job);
    io::CsvWriter csv(outputs.open(args.outputs.csv), table.columns);
    for (const auto& row : table.rows) csv.row(row);
  }
  if (!args.outputs.json.empty())
    io::write_json(outputs.open(args.outputs.json), app::to_json(c, job));
  if (!args.outputs.plot.empty()) io::write_plot(app::figure(job), args.outputs.plot, outputs);
  commit_outputs(outputs, args.outputs, out);
  return 0;
}

}  // namespace cutdyn::cli
