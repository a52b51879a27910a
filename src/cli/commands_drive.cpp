// `cutdyn drive`: the feed drives under the simulated milling load ([Ermolaev2020];
// docs/models/feed-drive.md). The job is the library's (cutdyn/app/drive.hpp); this file
// builds the cut from the flags and renders the Report.
#include <fmt/format.h>

#include <cctype>
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

// A metric's axis in a figure: its name in words, the unit it is drawn in ("" for a
// number without one) and the factor from the metric's value to that unit.
struct MetricAxis {
  std::string name, unit;
  double scale = 1.0;
  std::string label() const { return unit.empty() ? name : name + " (" + unit + ")"; }
};

MetricAxis drive_metric_axis(const std::string& metric) {
  if (metric == "epsilon_um") return {"relative motion error ε, peak to peak", "µm"};
  if (metric == "drive_error_um") return {"table position error, peak to peak", "µm"};
  if (metric == "cutter_error_um") return {"cutter deflection along the axis, peak to peak", "µm"};
  if (metric == "k_delta") return {"speed non-uniformity kδ", ""};
  if (metric == "static_error") return {"static speed error δ", "%", 100.0};
  if (metric == "torque_ripple_nm") return {"load torque ripple ±ΔMc", "N·m"};
  if (metric == "speed_ripple_rad_s") return {"motor speed ripple ±ΔΩ", "rad/s"};
  return {metric, ""};
}

// The metric of each axis against the swept key.
io::PlotSpec sweep_plot(const app::DriveSweepReport& sweep, const io::Case& c, std::size_t column) {
  const MetricAxis axis = drive_metric_axis(app::drive_metric_names()[column]);
  io::PlotSpec spec;
  std::string what = axis.name;
  what[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(what[0])));
  spec.title = fmt::format("{} over a sweep of {}", what, sweep.key);
  spec.x_label = io::case_key_label(c, sweep.key);
  spec.y_label = axis.label();
  for (std::size_t k = 0; k < sweep.runs.front().axes.size(); ++k) {
    io::PlotSeries series{"axis " + sweep.runs.front().axes[k].axis.name, {}, {}, "linespoints"};
    for (std::size_t i = 0; i < sweep.runs.size(); ++i) {
      series.x.push_back(sweep.values[i]);
      series.y.push_back(axis.scale * app::drive_metrics(sweep.runs[i].axes[k])[column]);
    }
    spec.series.push_back(std::move(series));
  }
  return spec;
}

void write_sweep_files(const DriveArgs& args, const app::DriveSweepReport& sweep, const io::Case& c,
                       std::size_t column, io::OutputTransaction& outputs) {
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
    io::write_json(outputs.open(args.outputs.json), app::to_json(c, sweep, names[column]));
  if (!args.outputs.plot.empty())
    io::write_plot(sweep_plot(sweep, c, column), args.outputs.plot, outputs);
}

int run_sweep(const DriveArgs& args, const io::Case& c, std::ostream& out, std::ostream& err) {
  const Sweep spec = parse_sweep(args.sweep);
  const std::size_t column = metric_column(args.metric, "epsilon_um", app::drive_metric_names());
  const app::DriveSweepReport sweep = app::run_drive_sweep(
      c, spec, drive_request(args), {args.seed}, args.threads, progress_reporter(err, "sweep"));
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

// Over the last summary revolutions, two panels: ε of each axis, and its motor speed about
// the mean (the speed ripple), on its own axis.
io::PlotFigure traces_plot(const app::DriveReport& run) {
  const auto in_traces = [&](double t) { return t >= run.traces_from_s - 1e-12; };
  io::PlotFigure figure;
  const double revolutions = run.cut.options.summary_revolutions;
  figure.title = fmt::format(
      "Feed drives at {} rpm over the last {}", human(run.cut.rpm),
      revolutions == 1.0 ? std::string("revolution") : human(revolutions) + " revolutions");
  io::PlotSpec error, speed;
  error.title = "Relative motion error ε (table position error + cutter deflection)";
  error.x_label = speed.x_label = "time (s)";
  error.y_label = "ε along the axis (µm)";
  speed.title = "Motor speed ripple: speed minus its mean";
  speed.y_label = "motor speed − mean (rad/s)";
  for (const app::DriveAxisReport& a : run.axes) {
    const FeedDriveResult& d = a.drive;
    io::PlotSeries e, w;
    e.title = fmt::format("axis {}: ε {} µm peak to peak", a.axis.name,
                          human(m_to_um(a.epsilon_pp_m), 3));
    w.title = fmt::format("axis {}: mean {} rad/s, ripple ±{} rad/s", a.axis.name,
                          human(d.mean_speed_rad_s), human(d.speed_ripple_rad_s, 3));
    for (std::size_t i = 0; i < d.time_s.size(); ++i) {
      if (!in_traces(d.time_s[i])) continue;
      e.x.push_back(d.time_s[i]);
      e.y.push_back(m_to_um(a.epsilon_m[i]));
      w.x.push_back(d.time_s[i]);
      w.y.push_back(d.speed_rad_s[i] - d.mean_speed_rad_s);
    }
    error.series.push_back(std::move(e));
    speed.series.push_back(std::move(w));
  }
  figure.panels = {std::move(error), std::move(speed)};
  return figure;
}

// The traces of each axis over the last summary revolutions (CSV), and their figure.
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
  if (!args.outputs.plot.empty()) io::write_plot(traces_plot(run), args.outputs.plot, outputs);
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
  if (!args.outputs.json.empty())
    io::write_json(outputs.open(args.outputs.json), app::to_json(c, run));
  outputs.commit();
  for (const std::string* f :
       {&args.outputs.csv, &args.currents, &args.outputs.json, &args.outputs.plot})
    if (!f->empty()) out << "  wrote " << *f << "\n";
  return 0;
}

}  // namespace cutdyn::cli
