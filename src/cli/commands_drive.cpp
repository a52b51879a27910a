// `cutdyn drive`: the feed drives under the simulated milling load ([Ermolaev2020];
// docs/models/feed-drive.md). The job is the library's (cutdyn/app/drive.hpp); this file
// builds the cut from the flags and renders the Report.
#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/milling_setup.hpp"
#include "cutdyn/app/drive.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/io/output.hpp"
#include "cutdyn/io/plot.hpp"

namespace cutdyn::cli {
namespace {

using nlohmann::json;
using units::m_to_mm;
using units::m_to_um;

constexpr const char* kDefaultDriveCase = "ermolaev2020";

// Each axis' warnings on stderr, "cutdyn: warning: SOURCE: [PREFIX]axis x: …".
void warn(std::ostream& err, const std::string& source, const std::string& prefix,
          const app::DriveReport& run) {
  for (const app::DriveAxisReport& a : run.axes)
    for (const std::string& w : a.drive.warnings)
      err << "cutdyn: warning: " << source << ": " << prefix << "axis " << a.axis.name << ": "
          << w << "\n";
}

// The flags' speed and depth for the drive's cut.
app::SimulateRequest drive_request(const DriveArgs& args) {
  app::SimulateRequest r;
  r.rpm = args.rpm;
  if (args.depth_mm) r.depth_m = units::mm_to_m(*args.depth_mm);
  r.names = flag_names();
  return r;
}

void print_sweep(const app::DriveSweepReport& sweep, const io::Case& c, std::size_t column,
                 std::ostream& out) {
  const std::string& metric = app::drive_metric_names()[column];
  out << "cutdyn drive: " << c.source << ", sweep of " << sweep.key << " over "
      << sweep.values.size() << " values\n";
  out << fmt::format("  {:>14}", sweep.key);
  for (const app::DriveAxisReport& a : sweep.runs.front().axes)
    out << fmt::format("  {:>16}", a.axis.name + ": " + metric);
  out << "\n";
  for (std::size_t i = 0; i < sweep.runs.size(); ++i) {
    out << fmt::format("  {:>14}", human(sweep.values[i]));
    for (const app::DriveAxisReport& a : sweep.runs[i].axes)
      out << fmt::format("  {:>16}", human(app::drive_metrics(a)[column], 4));
    out << "\n";
  }
}

json sweep_json(const app::DriveSweepReport& sweep, const io::Case& c, const std::string& metric) {
  const auto& names = app::drive_metric_names();
  json points = json::array();
  for (std::size_t i = 0; i < sweep.runs.size(); ++i) {
    json axes = json::array();
    for (const app::DriveAxisReport& a : sweep.runs[i].axes) {
      json p{{"axis", a.axis.name}, {"steady_state", a.drive.steady}, {"warnings", a.drive.warnings}};
      const auto m = app::drive_metrics(a);
      for (std::size_t k = 0; k < names.size(); ++k) p[names[k]] = m[k];
      axes.push_back(std::move(p));
    }
    points.push_back({{"value", sweep.values[i]}, {"axes", std::move(axes)}});
  }
  return {{"command", "drive"}, {"schema_version", kJsonSchemaVersion}, {"case", io::to_json(c)}, {"source", c.source},
          {"sweep", sweep.key}, {"metric", metric},       {"points", std::move(points)}};
}

void write_sweep_files(const DriveArgs& args, const app::DriveSweepReport& sweep,
                       const io::Case& c, std::size_t column, io::OutputTransaction& outputs) {
  const auto& names = app::drive_metric_names();
  if (!args.outputs.csv.empty()) {
    std::vector<std::string> header{sweep.key, "axis"};
    header.insert(header.end(), names.begin(), names.end());
    io::CsvWriter csv(outputs.open(args.outputs.csv), header);
    for (std::size_t i = 0; i < sweep.runs.size(); ++i)
      for (const app::DriveAxisReport& a : sweep.runs[i].axes) {
        std::vector<io::CsvCell> row{sweep.values[i], a.axis.name};
        for (double m : app::drive_metrics(a)) row.emplace_back(m);
        csv.row(row);
      }
  }
  if (!args.outputs.json.empty())
    io::write_json(outputs.open(args.outputs.json), sweep_json(sweep, c, names[column]));
  if (!args.outputs.plot.empty()) {
    io::PlotSpec spec;
    spec.title = fmt::format("{} against {}", names[column], sweep.key);
    spec.x_label = sweep.key;
    spec.y_label = names[column];
    for (std::size_t k = 0; k < sweep.runs.front().axes.size(); ++k) {
      io::PlotSeries series{"axis " + sweep.runs.front().axes[k].axis.name, {}, {}, "linespoints"};
      for (std::size_t i = 0; i < sweep.runs.size(); ++i) {
        series.x.push_back(sweep.values[i]);
        series.y.push_back(app::drive_metrics(sweep.runs[i].axes[k])[column]);
      }
      spec.series.push_back(std::move(series));
    }
    io::write_plot(spec, args.outputs.plot, outputs);
  }
}

int run_sweep(const DriveArgs& args, const io::Case& c, std::ostream& out, std::ostream& err) {
  const Sweep spec = parse_sweep(args.sweep);
  const std::size_t column = metric_column(args.metric, "epsilon_um", app::drive_metric_names());
  const app::DriveSweepReport sweep = app::run_drive_sweep(
      c, spec, drive_request(args),
      {args.seed}, args.threads, progress_reporter(err, "sweep"));
  for (std::size_t i = 0; i < sweep.runs.size(); ++i)
    warn(err, c.source, sweep.key + " = " + human(sweep.values[i]) + ", ", sweep.runs[i]);
  print_sweep(sweep, c, column, out);
  io::OutputTransaction outputs;
  write_sweep_files(args, sweep, c, column, outputs);
  commit_outputs(outputs, args.outputs, out);
  return 0;
}

void print_run(const app::DriveReport& run, const io::Case& c, std::ostream& out) {
  const app::DriveCut& s = run.cut;
  out << "cutdyn drive: " << c.source << " at " << human(s.rpm) << " rpm, depth "
      << human(m_to_mm(s.cut.width_m)) << " mm, feed " << human(m_to_mm(s.cut.feed_per_tooth_m))
      << " mm/tooth; summaries over each axis' periodic steady state, traces of the last "
      << human(s.options.summary_revolutions) << " revolutions\n";
  for (const app::DriveAxisReport& a : run.axes) {
    const FeedDriveResult& d = a.drive;
    out << fmt::format("  axis {} ({} drive, {:.4g} mm/s):\n", a.axis.name,
                       a.axis.drive.model == FeedDrive::Model::kDynamic ? "dynamic" : "static",
                       1e3 * a.feed_speed_m_per_s);
    if (d.steady)
      out << fmt::format("    steady state    from t = {} s: {} revolutions summarised\n",
                         human(d.steady_from_s), d.steady_periods);
    for (const std::string& w : d.warnings) out << "    warning: " << w << "\n";
    out << fmt::format("    load torque     mean {} N·m, ripple ±{} N·m\n",
                       human(d.mean_load_torque_nm), human(d.torque_ripple_nm));
    out << fmt::format("    motor speed     {} rad/s commanded, mean {} rad/s, ripple ±{} rad/s\n",
                       human(d.commanded_speed_rad_s), human(d.mean_speed_rad_s),
                       human(d.speed_ripple_rad_s));
    if (d.moving) {
      out << fmt::format("    kδ              {} → {}\n", human(d.k_delta, 3),
                         describe(d.k_delta_verdict));
      out << fmt::format("    δ               {} % → {}\n", human(100.0 * d.static_error, 3),
                         d.static_error_ok ? "within 10 %" : "ABOVE 10 %");
    } else {
      out << "    kδ, δ           – (the axis does not move)\n";
    }
    out << fmt::format("    position error  {} µm peak-to-peak (drive), cutter {} µm, ε {} µm\n",
                       human(m_to_um(a.drive_pp_m), 3), human(m_to_um(a.cutter_pp_m), 3),
                       human(m_to_um(a.epsilon_pp_m), 3));
  }
}

json run_json(const app::DriveReport& run, const io::Case& c) {
  json axes = json::array();
  for (const app::DriveAxisReport& a : run.axes) {
    const FeedDriveResult& d = a.drive;
    axes.push_back({{"axis", a.axis.name},
                    {"feed_speed_mm_per_s", 1e3 * a.feed_speed_m_per_s},
                    {"commanded_speed_rad_s", d.commanded_speed_rad_s},
                    {"mean_load_torque_nm", d.mean_load_torque_nm},
                    {"torque_ripple_nm", d.torque_ripple_nm},
                    {"mean_speed_rad_s", d.mean_speed_rad_s},
                    {"speed_ripple_rad_s", d.speed_ripple_rad_s},
                    {"steady_state", d.steady},
                    {"steady_from_s", d.steady_from_s},
                    {"steady_revolutions", d.steady_periods},
                    {"warnings", d.warnings},
                    {"k_delta", d.moving ? json(d.k_delta) : json()},
                    {"k_delta_verdict", d.moving ? json(to_string(d.k_delta_verdict)) : json()},
                    {"static_error", d.moving ? json(d.static_error) : json()},
                    {"static_error_ok", d.static_error_ok},
                    {"drive_error_um", m_to_um(a.drive_pp_m)},
                    {"cutter_error_um", m_to_um(a.cutter_pp_m)},
                    {"epsilon_um", m_to_um(a.epsilon_pp_m)}});
  }
  return {{"command", "drive"}, {"schema_version", kJsonSchemaVersion},
          {"case", io::to_json(c)},
          {"source", c.source},
          {"spindle_rpm", run.cut.rpm},
          {"axes", std::move(axes)}};
}

// The traces of each axis over the last summary revolutions (CSV), and the figure of ε and
// the motor speed.
void write_traces(const DriveArgs& args, const app::DriveReport& run,
                  io::OutputTransaction& outputs) {
  const auto in_traces = [&](double t) { return t >= run.traces_from_s - 1e-12; };
  if (!args.outputs.csv.empty()) {
    io::CsvWriter csv(outputs.open(args.outputs.csv),
                      {"axis", "time_s", "axis_force_n", "load_torque_nm", "speed_rad_s",
                       "position_error_um", "epsilon_um"});
    for (const app::DriveAxisReport& a : run.axes)
      for (std::size_t i = 0; i < a.drive.time_s.size(); ++i)
        if (in_traces(a.drive.time_s[i]))
          csv.row({a.axis.name, a.drive.time_s[i], a.drive.axis_force_n[i],
                   a.drive.load_torque_nm[i], a.drive.speed_rad_s[i],
                   m_to_um(a.drive.position_error_m[i]), m_to_um(a.epsilon_m[i])});
  }
  if (args.outputs.plot.empty()) return;
  io::PlotSpec spec;
  spec.title = fmt::format("Relative motion error at {} rpm", human(run.cut.rpm));
  spec.x_label = "time (s)";
  spec.y_label = "error along the axis (µm)";
  spec.y2_label = "motor speed (rad/s)";
  for (const app::DriveAxisReport& a : run.axes) {
    io::PlotSeries e{"ε, axis " + a.axis.name, {}, {}, "lines"};
    io::PlotSeries w{"speed, axis " + a.axis.name, {}, {}, "lines", true};
    for (std::size_t i = 0; i < a.drive.time_s.size(); ++i) {
      if (!in_traces(a.drive.time_s[i])) continue;
      e.x.push_back(a.drive.time_s[i]);
      e.y.push_back(m_to_um(a.epsilon_m[i]));
      w.x.push_back(a.drive.time_s[i]);
      w.y.push_back(a.drive.speed_rad_s[i]);
    }
    spec.series.push_back(std::move(e));
    spec.series.push_back(std::move(w));
  }
  io::write_plot(spec, args.outputs.plot, outputs);
}

}  // namespace

int run_drive(const DriveArgs& args, std::ostream& out, std::ostream& err) {
  check_outputs(args.outputs);
  if (!args.currents.empty()) check_outputs({args.currents, "", ""});
  const io::Case c = load_case(args.case_path, kDefaultDriveCase, err);
  if (!args.sweep.empty()) {
    if (!args.currents.empty())
      throw InvalidInput({"--currents: not with --sweep"}, "command line");
    return run_sweep(args, c, out, err);
  }
  if (!args.metric.empty()) throw InvalidInput({"--metric: only with --sweep"}, "command line");
  const app::DriveReport run = app::run_drive(c, drive_request(args), {args.seed});
  if (!args.currents.empty()) app::require_motors(run, c.source);
  print_run(run, c, out);
  warn(err, c.source, "", run);

  io::OutputTransaction outputs;
  write_traces(args, run, outputs);
  if (!args.currents.empty()) app::write_current_log(outputs.open(args.currents), run, c.source);
  if (!args.outputs.json.empty()) io::write_json(outputs.open(args.outputs.json), run_json(run, c));
  outputs.commit();
  for (const std::string* f :
       {&args.outputs.csv, &args.currents, &args.outputs.json, &args.outputs.plot})
    if (!f->empty()) out << "  wrote " << *f << "\n";
  return 0;
}

}  // namespace cutdyn::cli
