// `cutdyn drive`: the feed drives under the simulated milling load (models.md S1.7;
// docs/models/feed-drive.md).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/milling_setup.hpp"
#include "cutdyn/core/parallel.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/drive/feed_drive.hpp"
#include "cutdyn/drive/motor_currents.hpp"
#include "cutdyn/io/output.hpp"
#include "cutdyn/io/plot.hpp"

namespace cutdyn::cli {
namespace {

using nlohmann::json;
using units::m_to_mm;
using units::m_to_um;

constexpr const char* kDefaultDriveCase = "ermolaev2020";

struct AxisRun {
  FeedAxis axis;
  double feed_speed = 0.0;  // along the axis, m/s
  FeedDriveResult drive;
  std::vector<double> cutter_m;   // the cutter's deflection along the axis
  std::vector<double> epsilon_m;  // drive position error + cutter deflection
  double drive_pp = 0.0, cutter_pp = 0.0, epsilon_pp = 0.0;
};

struct DriveRun {
  SimulationSetup setup;
  std::vector<AxisRun> axes;
  double traces_from = 0.0;  // the written traces: the last summary revolutions
};

// Each axis' warnings on stderr, "cutdyn: warning: SOURCE: [PREFIX]axis x: …".
void warn(std::ostream& err, const std::string& source, const std::string& prefix,
          const DriveRun& run) {
  for (const AxisRun& a : run.axes)
    for (const std::string& w : a.drive.warnings)
      err << "cutdyn: warning: " << source << ": " << prefix << "axis " << a.axis.name << ": "
          << w << "\n";
}

// The milling cut of a drive case, every problem with the case or the flags thrown.
SimulationSetup drive_setup(const DriveArgs& args, const io::Case& c) {
  if (c.process != io::Process::kMilling)
    throw InvalidInput({"process: `cutdyn drive` takes milling cases"}, c.source);
  if (c.drives.empty())
    throw InvalidInput({"drives: missing (at least one [[drives]] table: axis, transmission, "
                        "drive model)"},
                       c.source);
  SimulateArgs sim;
  sim.case_path = args.case_path;
  sim.rpm = args.rpm;
  sim.depth_mm = args.depth_mm;
  return milling_setup(sim, c);
}

DriveRun run_case(const io::Case& c, SimulationSetup setup, std::optional<int> seed) {
  DriveRun run{std::move(setup), {}, 0.0};
  SimulationSetup& s = run.setup;
  s.options.max_recorded_samples = 4'000'000;  // the whole run at full resolution
  MillingSimulationResult r;
  rethrow_as(s.where, "simulate", [&] { r = simulate_milling(s.cut, s.options); });
  // The drives run over the whole cut and are summarised over their periodic steady state at
  // the spindle revolution (the force's period); the traces written are of the last summary
  // revolutions.
  const double revolution = 60.0 / s.rpm;
  run.traces_from = r.time_s.back() - s.options.summary_revolutions * revolution;
  std::vector<double> t, fx, fy, fz, x, y;
  for (std::size_t i = 0; i < r.time_s.size(); ++i) {
    if (!t.empty() && !(r.time_s[i] > t.back())) continue;
    t.push_back(r.time_s[i]);
    fx.push_back(r.fx_n[i]);
    fy.push_back(r.fy_n[i]);
    fz.push_back(0.0);
    x.push_back(r.x_m[i]);
    y.push_back(r.y_m[i]);
  }
  const double feed = s.cut.feed_per_tooth_m * s.cut.teeth * s.rpm / 60.0;  // along +x
  SteadyStateOptions steady;
  steady.period_s = revolution;
  unsigned stream = 0;
  for (FeedAxis axis : c.drives) {
    AxisRun a;
    // The axis moves the cutter along its direction: its share of the feed velocity. An
    // axis pointing against the feed is turned round.
    if (axis.direction[0] < 0.0)
      for (double& d : axis.direction) d = -d;
    // The noise of each axis' currents: its own stream of the seed (case or --seed).
    if (axis.motor) {
      if (seed) axis.motor->seed = static_cast<unsigned>(*seed);
      axis.motor->stream = stream;
    }
    ++stream;
    a.feed_speed = feed * axis.direction[0];
    rethrow_as(c.source, "drives", [&] {
      a.drive = simulate_feed_drive(axis, t, fx, fy, fz, a.feed_speed, true, steady);
    });
    for (std::size_t i = 0; i < t.size(); ++i) {
      a.cutter_m.push_back(x[i] * axis.direction[0] + y[i] * axis.direction[1]);
      a.epsilon_m.push_back(a.drive.position_error_m[i] + a.cutter_m.back());
    }
    // Peak-to-peak over the last summary revolutions (the simulation's summary window: the
    // cutter's own vibration need not be periodic), within the drive's steady window.
    const double from = std::max(run.traces_from, a.drive.steady_from_s) - 1e-12;
    const auto window = [&](const std::vector<double>& v) {
      double lo = 1e300, hi = -1e300;
      for (std::size_t i = 0; i < t.size(); ++i) {
        if (t[i] < from) continue;
        lo = std::min(lo, v[i]);
        hi = std::max(hi, v[i]);
      }
      return hi - lo;
    };
    a.drive_pp = window(a.drive.position_error_m);
    a.cutter_pp = window(a.cutter_m);
    a.epsilon_pp = window(a.epsilon_m);
    a.axis = axis;
    run.axes.push_back(std::move(a));
  }
  return run;
}

const std::vector<std::string>& metric_names() {
  static const std::vector<std::string> names{
      "epsilon_um",   "drive_error_um",   "cutter_error_um",   "k_delta",
      "static_error", "torque_ripple_nm", "speed_ripple_rad_s"};
  return names;
}

std::vector<double> metrics(const AxisRun& a) {
  return {m_to_um(a.epsilon_pp),     m_to_um(a.drive_pp),  m_to_um(a.cutter_pp),
          a.drive.k_delta,           a.drive.static_error, a.drive.torque_ripple_nm,
          a.drive.speed_ripple_rad_s};
}

int run_sweep(const DriveArgs& args, const io::Case& c, std::ostream& out, std::ostream& err) {
  const Sweep sweep = parse_sweep(args.sweep);
  const auto& names = metric_names();
  const std::size_t column = metric_column(args.metric, "epsilon_um", names);
  const std::string& metric = names[column];
  std::vector<io::Case> cases;
  for (double value : sweep.values) cases.push_back(io::with_value(c, sweep.key, value));
  // Every case is checked before any runs (the milling part; the drives as they run).
  std::vector<SimulationSetup> setups;
  for (const io::Case& v : cases) setups.push_back(drive_setup(args, v));
  std::vector<DriveRun> runs(cases.size());
  parallel_for(
      static_cast<int>(cases.size()), args.threads,
      [&](int i) {
        const auto k = static_cast<std::size_t>(i);
        runs[k] = run_case(cases[k], setups[k], args.seed);
      },
      progress_reporter(err, "sweep"));

  for (std::size_t i = 0; i < runs.size(); ++i)
    warn(err, c.source, sweep.key + " = " + human(sweep.values[i]) + ", ", runs[i]);
  out << "cutdyn drive: " << c.source << ", sweep of " << sweep.key << " over "
      << sweep.values.size() << " values\n";
  out << fmt::format("  {:>14}", sweep.key);
  for (const AxisRun& a : runs.front().axes)
    out << fmt::format("  {:>16}", a.axis.name + ": " + metric);
  out << "\n";
  for (std::size_t i = 0; i < runs.size(); ++i) {
    out << fmt::format("  {:>14}", human(sweep.values[i]));
    for (const AxisRun& a : runs[i].axes)
      out << fmt::format("  {:>16}", human(metrics(a)[column], 4));
    out << "\n";
  }
  io::OutputTransaction outputs;
  if (!args.outputs.csv.empty()) {
    std::vector<std::string> header{sweep.key, "axis"};
    header.insert(header.end(), names.begin(), names.end());
    io::CsvWriter csv(outputs.open(args.outputs.csv), header);
    for (std::size_t i = 0; i < runs.size(); ++i) {
      for (const AxisRun& a : runs[i].axes) {
        std::vector<io::CsvCell> row{sweep.values[i], a.axis.name};
        for (double m : metrics(a)) row.emplace_back(m);
        csv.row(row);
      }
    }
  }
  if (!args.outputs.json.empty()) {
    json points = json::array();
    for (std::size_t i = 0; i < runs.size(); ++i) {
      json axes = json::array();
      for (const AxisRun& a : runs[i].axes) {
        json p{{"axis", a.axis.name},
               {"steady_state", a.drive.steady},
               {"warnings", a.drive.warnings}};
        const auto m = metrics(a);
        for (std::size_t k = 0; k < names.size(); ++k) p[names[k]] = m[k];
        axes.push_back(std::move(p));
      }
      points.push_back({{"value", sweep.values[i]}, {"axes", std::move(axes)}});
    }
    io::write_json(outputs.open(args.outputs.json), json{{"command", "drive"},
                                                         {"case", io::to_json(c)},
                                                         {"source", c.source},
                                                         {"sweep", sweep.key},
                                                         {"metric", metric},
                                                         {"points", std::move(points)}});
  }
  if (!args.outputs.plot.empty()) {
    io::PlotSpec spec;
    spec.title = fmt::format("{} against {}", metric, sweep.key);
    spec.x_label = sweep.key;
    spec.y_label = metric;
    for (std::size_t k = 0; k < runs.front().axes.size(); ++k) {
      io::PlotSeries series{"axis " + runs.front().axes[k].axis.name, {}, {}, "linespoints"};
      for (std::size_t i = 0; i < runs.size(); ++i) {
        series.x.push_back(sweep.values[i]);
        series.y.push_back(metrics(runs[i].axes[k])[column]);
      }
      spec.series.push_back(std::move(series));
    }
    io::write_plot(spec, args.outputs.plot, outputs);
  }
  commit_outputs(outputs, args.outputs, out);
  return 0;
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
  const DriveRun run = run_case(c, drive_setup(args, c), args.seed);
  const SimulationSetup& s = run.setup;
  if (!args.currents.empty()) {
    for (const AxisRun& a : run.axes)
      if (!a.axis.motor)
        throw InvalidInput({"drives (axis " + a.axis.name +
                            "): --currents needs the motor: pole_pairs, torque_constant_nm_per_a"},
                           c.source);
  }

  out << "cutdyn drive: " << c.source << " at " << human(s.rpm) << " rpm, depth "
      << human(m_to_mm(s.cut.width_m)) << " mm, feed " << human(m_to_mm(s.cut.feed_per_tooth_m))
      << " mm/tooth; summaries over each axis' periodic steady state, traces of the last "
      << human(s.options.summary_revolutions) << " revolutions\n";
  for (const AxisRun& a : run.axes) {
    const FeedDriveResult& d = a.drive;
    out << fmt::format("  axis {} ({} drive, {:.4g} mm/s):\n", a.axis.name,
                       a.axis.drive.model == FeedDrive::Model::kDynamic ? "dynamic" : "static",
                       1e3 * a.feed_speed);
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
                       human(m_to_um(a.drive_pp), 3), human(m_to_um(a.cutter_pp), 3),
                       human(m_to_um(a.epsilon_pp), 3));
  }

  warn(err, c.source, "", run);

  // The written traces: the last summary revolutions.
  const auto in_traces = [&](double t) { return t >= run.traces_from - 1e-12; };
  io::OutputTransaction outputs;
  if (!args.outputs.csv.empty()) {
    io::CsvWriter csv(outputs.open(args.outputs.csv),
                      {"axis", "time_s", "axis_force_n", "load_torque_nm", "speed_rad_s",
                       "position_error_um", "epsilon_um"});
    for (const AxisRun& a : run.axes)
      for (std::size_t i = 0; i < a.drive.time_s.size(); ++i)
        if (in_traces(a.drive.time_s[i]))
          csv.row({a.axis.name, a.drive.time_s[i], a.drive.axis_force_n[i], a.drive.load_torque_nm[i],
                 a.drive.speed_rad_s[i], m_to_um(a.drive.position_error_m[i]),
                 m_to_um(a.epsilon_m[i])});
  }
  if (!args.currents.empty()) {
    std::ostream& file = outputs.open(args.currents);
    // Before the header, each axis' motor as used to make its currents: the monitor checks the
    // measure against its calibration's.
    for (const AxisRun& a : run.axes)
      file << "# axis = " << a.axis.name << ", measure = " << to_string(a.axis.motor->measure)
           << ", torque_constant_nm_per_a = "
           << io::format_number(a.axis.motor->torque_constant_nm_per_a)
           << ", pole_pairs = " << a.axis.motor->pole_pairs << "\n";
    io::CsvWriter csv(file,
                      {"time_s", "axis", "iu_a", "iv_a", "iw_a", "speed_rad_s", "rotor_angle_rad"});
    for (const AxisRun& a : run.axes) {
      std::vector<double> t, torque, speed;
      for (std::size_t i = 0; i < a.drive.time_s.size(); ++i) {
        if (!in_traces(a.drive.time_s[i])) continue;
        t.push_back(a.drive.time_s[i]);
        torque.push_back(a.drive.motor_torque_nm[i]);
        speed.push_back(a.drive.speed_rad_s[i]);
      }
      const PhaseCurrents p = motor_currents(*a.axis.motor, t, torque, speed);
      for (std::size_t i = 0; i < p.time_s.size(); ++i)
        csv.row({p.time_s[i], a.axis.name, p.iu_a[i], p.iv_a[i], p.iw_a[i], p.speed_rad_s[i],
                 p.rotor_angle_rad[i]});
    }
  }
  if (!args.outputs.json.empty()) {
    json axes = json::array();
    for (const AxisRun& a : run.axes) {
      const FeedDriveResult& d = a.drive;
      axes.push_back({{"axis", a.axis.name},
                      {"feed_speed_mm_per_s", 1e3 * a.feed_speed},
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
                      {"drive_error_um", m_to_um(a.drive_pp)},
                      {"cutter_error_um", m_to_um(a.cutter_pp)},
                      {"epsilon_um", m_to_um(a.epsilon_pp)}});
    }
    io::write_json(outputs.open(args.outputs.json), json{{"command", "drive"},
                                                         {"case", io::to_json(c)},
                                                         {"source", c.source},
                                                         {"spindle_rpm", s.rpm},
                                                         {"axes", std::move(axes)}});
  }
  if (!args.outputs.plot.empty()) {
    io::PlotSpec spec;
    spec.title = fmt::format("Relative motion error at {} rpm", human(s.rpm));
    spec.x_label = "time (s)";
    spec.y_label = "error along the axis (µm)";
    spec.y2_label = "motor speed (rad/s)";
    for (const AxisRun& a : run.axes) {
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
  outputs.commit();
  for (const std::string* f :
       {&args.outputs.csv, &args.currents, &args.outputs.json, &args.outputs.plot})
    if (!f->empty()) out << "  wrote " << *f << "\n";
  return 0;
}

}  // namespace cutdyn::cli
