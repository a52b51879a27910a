#include "cutdyn/app/drive.hpp"

#include <algorithm>
#include <limits>
#include <utility>

#include "cutdyn/app/detail/text.hpp"
#include "cutdyn/core/detail/parallel.hpp"
#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/io/output.hpp"

namespace cutdyn::app {
namespace {

using units::m_to_mm;
using units::m_to_um;

// The cutter's force and deflection over the whole cut, one sample per distinct instant.
struct CutTraces {
  std::vector<double> t, fx, fy, fz, x, y;
};

CutTraces cut_traces(const MillingSimulationResult& r) {
  CutTraces c;
  for (std::size_t i = 0; i < r.time_s.size(); ++i) {
    if (!c.t.empty() && !(r.time_s[i] > c.t.back())) continue;
    c.t.push_back(r.time_s[i]);
    c.fx.push_back(r.fx_n[i]);
    c.fy.push_back(r.fy_n[i]);
    c.fz.push_back(0.0);
    c.x.push_back(r.x_m[i]);
    c.y.push_back(r.y_m[i]);
  }
  return c;
}

// Peak-to-peak of `v` over the samples from `from` on.
double peak_to_peak(const std::vector<double>& t, const std::vector<double>& v, double from) {
  double lo = 1e300, hi = -1e300;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (t[i] < from) continue;
    lo = std::min(lo, v[i]);
    hi = std::max(hi, v[i]);
  }
  return hi - lo;
}

// One axis under the cut: its share of the feed `feed` (along +x), the projection of the
// cutter's force, and its errors.
DriveAxisReport run_axis(const io::Case& c, FeedAxis axis, const CutTraces& cut, double feed,
                         const SteadyStateOptions& steady, double traces_from) {
  DriveAxisReport a;
  a.feed_speed_m_per_s = feed * axis.direction[0];
  rethrow_as(c.source, "drives", [&] {
    a.drive = simulate_feed_drive(axis, cut.t, cut.fx, cut.fy, cut.fz, a.feed_speed_m_per_s, true,
                                  steady);
  });
  for (std::size_t i = 0; i < cut.t.size(); ++i) {
    a.cutter_m.push_back(cut.x[i] * axis.direction[0] + cut.y[i] * axis.direction[1]);
    a.epsilon_m.push_back(a.drive.position_error_m[i] + a.cutter_m.back());
  }
  // Peak-to-peak over the last summary revolutions (the simulation's summary window: the
  // cutter's own vibration need not be periodic), within the drive's steady window.
  const double from = std::max(traces_from, a.drive.steady_from_s) - 1e-12;
  a.drive_pp_m = peak_to_peak(cut.t, a.drive.position_error_m, from);
  a.cutter_pp_m = peak_to_peak(cut.t, a.cutter_m, from);
  a.epsilon_pp_m = peak_to_peak(cut.t, a.epsilon_m, from);
  // Against the programme (a speed loop with an integrator): the table ahead of its programmed
  // position by −lag, plus the cutter's deflection; the value of largest magnitude.
  if (!a.drive.load_lag_m.empty()) {
    double worst = 0.0;
    for (std::size_t i = 0; i < cut.t.size(); ++i) {
      if (cut.t[i] < from) continue;
      const double e = a.cutter_m[i] - a.drive.load_lag_m[i];
      if (std::abs(e) > std::abs(worst)) worst = e;
    }
    a.program_error_m = worst;
  }
  a.axis = std::move(axis);
  return a;
}

}  // namespace

void require_drive_case(const io::Case& c) {
  if (c.process != io::Process::kMilling)
    throw InvalidInput({"process: `cutdyn drive` takes milling cases"}, c.source);
  if (c.drives.empty())
    throw InvalidInput({"drives: missing (at least one [[drives]] table: axis, transmission, "
                        "drive model)"},
                       c.source);
}

DriveReport run_drive(const io::Case& c, const DriveCut& cut, const DriveOptions& options) {
  require_drive_case(c);
  DriveReport run{cut, options, {}, 0.0, false, {}};
  DriveCut& s = run.cut;
  s.options.max_recorded_samples = 4'000'000;  // the whole run at full resolution
  MillingSimulationResult r;
  rethrow_as(s.where, "simulate", [&] { r = simulate_milling(s.cut, s.options); });
  s.options.progress = nullptr;  // the report outlives the caller's progress
  run.chatter = r.chatter;
  run.verdict = r.verdict();
  // The drives run over the whole cut and are summarised over their periodic steady state at
  // the spindle revolution (the force's period); the traces shown are of the last summary
  // revolutions.
  const double revolution = 60.0 / s.rpm;
  run.traces_from_s = r.time_s.back() - s.options.summary_revolutions * revolution;
  const CutTraces traces = cut_traces(r);
  const double feed = s.cut.feed_per_tooth_m * s.cut.process.tool.teeth * s.rpm / 60.0;  // along +x
  SteadyStateOptions steady;
  steady.period_s = revolution;
  unsigned stream = 0;
  for (FeedAxis axis : c.drives) {
    // The axis moves the cutter along its direction: its share of the feed velocity. An
    // axis pointing against the feed is turned round.
    if (axis.direction[0] < 0.0)
      for (double& d : axis.direction) d = -d;
    // The noise of each axis' currents: its own stream of the seed (case or options).
    if (axis.motor) {
      if (options.seed) axis.motor->seed = static_cast<unsigned>(*options.seed);
      axis.motor->stream = stream;
    }
    ++stream;
    run.axes.push_back(run_axis(c, std::move(axis), traces, feed, steady, run.traces_from_s));
  }
  return run;
}

std::string chatter_warning(const DriveReport& run) {
  if (!run.chatter) return {};
  return "the cut chatters at " + human(run.cut.rpm) + " rpm, depth " +
         human(m_to_mm(run.cut.cut.width_m)) + " mm (the simulation's verdict: " + run.verdict +
         "): the ripples, kδ and ε are those of a chattering cut, not of the steady process";
}

const std::vector<std::string>& drive_metric_names() {
  static const std::vector<std::string> names{
      "epsilon_um",      "drive_error_um",   "cutter_error_um",    "k_delta",
      "static_error",    "torque_ripple_nm", "speed_ripple_rad_s", "load_lag_um",
      "program_error_um"};
  return names;
}

std::vector<double> drive_metrics(const DriveAxisReport& a) {
  return {
      m_to_um(a.epsilon_pp_m),
      m_to_um(a.drive_pp_m),
      m_to_um(a.cutter_pp_m),
      a.drive.k_delta,
      a.drive.static_error,
      a.drive.torque_ripple_nm,
      a.drive.speed_ripple_rad_s,
      a.drive.load_lag_max_m ? m_to_um(*a.drive.load_lag_max_m)
                             : std::numeric_limits<double>::quiet_NaN(),
      a.program_error_m ? m_to_um(*a.program_error_m) : std::numeric_limits<double>::quiet_NaN()};
}

PhaseCurrents axis_currents(const DriveAxisReport& a, double from_s) {
  std::vector<double> t, torque, speed;
  for (std::size_t i = 0; i < a.drive.time_s.size(); ++i) {
    if (a.drive.time_s[i] < from_s - 1e-12) continue;
    t.push_back(a.drive.time_s[i]);
    torque.push_back(a.drive.motor_torque_nm[i]);
    speed.push_back(a.drive.speed_rad_s[i]);
  }
  return motor_currents(*a.axis.motor, t, torque, speed);
}

void require_motors(const DriveReport& report, const std::string& source) {
  for (const DriveAxisReport& a : report.axes)
    if (!a.axis.motor)
      throw InvalidInput(
          {"drives (axis " + a.axis.name +
           "): the motor phase currents need the motor: pole_pairs, torque_constant_nm_per_a"},
          source);
}

void write_current_log(std::ostream& file, const DriveReport& report, const std::string& source) {
  require_motors(report, source);
  // Before the header, each axis' motor as used to make its currents: the monitor checks the
  // measure against its calibration's.
  for (const DriveAxisReport& a : report.axes)
    file << "# axis = " << a.axis.name << ", measure = " << to_string(a.axis.motor->measure)
         << ", torque_constant_nm_per_a = "
         << io::format_number(a.axis.motor->torque_constant_nm_per_a)
         << ", pole_pairs = " << a.axis.motor->pole_pairs << "\n";
  io::CsvWriter csv(file,
                    {"time_s", "axis", "iu_a", "iv_a", "iw_a", "speed_rad_s", "rotor_angle_rad"});
  for (const DriveAxisReport& a : report.axes) {
    const PhaseCurrents p = axis_currents(a, report.traces_from_s);
    for (std::size_t i = 0; i < p.time_s.size(); ++i)
      csv.row({p.time_s[i], a.axis.name, p.iu_a[i], p.iv_a[i], p.iw_a[i], p.speed_rad_s[i],
               p.rotor_angle_rad[i]});
  }
}

DriveSweepReport run_drive_sweep(const io::Case& c, const std::string& key,
                                 const std::vector<double>& values,
                                 const std::function<DriveCut(const io::Case&)>& cut_of,
                                 const DriveOptions& options, int threads,
                                 const std::function<void(int, int)>& progress) {
  DriveSweepReport sweep{key, values, std::vector<DriveReport>(values.size())};
  std::vector<io::Case> cases;
  for (double value : values) cases.push_back(io::with_value(c, key, value));
  // Every case is checked before any runs (the milling part; the drives as they run).
  std::vector<DriveCut> cuts;
  for (const io::Case& v : cases) {
    require_drive_case(v);
    cuts.push_back(cut_of(v));
  }
  parallel_for(
      static_cast<int>(cases.size()), threads,
      [&](int i) {
        const auto k = static_cast<std::size_t>(i);
        sweep.runs[k] = run_drive(cases[k], cuts[k], options);
      },
      progress);
  return sweep;
}

}  // namespace cutdyn::app

namespace cutdyn::app {

DriveReport run_drive(const io::Case& c, const SimulateRequest& request,
                      const DriveOptions& options) {
  require_drive_case(c);
  return run_drive(c, milling_setup(c, request), options);
}

DriveSweepReport run_drive_sweep(const io::Case& c, const Sweep& sweep,
                                 const SimulateRequest& request, const DriveOptions& options,
                                 int threads, const std::function<void(int, int)>& progress) {
  require_values(sweep);
  return run_drive_sweep(
      c, sweep.key, sweep.values, [&](const io::Case& v) { return milling_setup(v, request); },
      options, threads, progress);
}

}  // namespace cutdyn::app
