// The feed drives' reports rendered: the text and figures of `cutdyn drive`, one run or a
// sweep ([Ermolaev2020]; docs/models/feed-drive.md).
#include <fmt/format.h>

#include <cctype>
#include <cmath>

#include "cutdyn/app/detail/render_text.hpp"
#include "cutdyn/app/detail/text.hpp"
#include "cutdyn/app/render.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn::app {
namespace {

using units::m_to_mm;
using units::m_to_um;

MetricAxis drive_metric_axis(const std::string& metric) {
  if (metric == "epsilon_um") return {"relative motion error ε, peak to peak", "µm"};
  if (metric == "drive_error_um") return {"table position error, peak to peak", "µm"};
  if (metric == "cutter_error_um") return {"cutter deflection along the axis, peak to peak", "µm"};
  if (metric == "k_delta") return {"speed non-uniformity kδ", ""};
  if (metric == "static_error") return {"static speed error δ", "%", 100.0};
  if (metric == "torque_ripple_nm") return {"load torque ripple ±ΔMc", "N·m"};
  if (metric == "speed_ripple_rad_s") return {"motor speed ripple ±ΔΩ", "rad/s"};
  if (metric == "load_lag_um")
    return {"table lag behind its program from the load (PI loop)", "µm"};
  if (metric == "program_error_um")
    return {"error against the program, lag and cutter deflection (PI loop)", "µm"};
  return {metric, ""};
}

}  // namespace

void write_text(std::ostream& out, const io::Case& c, const DriveSweepReport& sweep,
                std::size_t column) {
  const std::string& metric = drive_metric_names()[column];
  out << "cutdyn drive: " << c.source << ", sweep of " << sweep.key << " over "
      << sweep.values.size() << " values\n";
  out << fmt::format("  {:>14}", sweep.key);
  for (const DriveAxisReport& a : sweep.runs.front().axes)
    out << fmt::format("  {:>16}", a.axis.name + ": " + metric);
  out << "\n";
  bool any_chatter = false;
  for (std::size_t i = 0; i < sweep.runs.size(); ++i) {
    out << fmt::format("  {:>14}", human(sweep.values[i]));
    for (const DriveAxisReport& a : sweep.runs[i].axes) {
      const double m = drive_metrics(a)[column];
      out << fmt::format("  {:>16}", std::isnan(m) ? "–" : human(m, 4));
    }
    out << (sweep.runs[i].chatter ? "  chatter" : "") << "\n";
    any_chatter = any_chatter || sweep.runs[i].chatter;
  }
  if (any_chatter)
    out << "  chatter: the cut chatters there (the simulation's verdict): the values are those "
           "of a chattering cut\n";
}

// The metric of each axis against the swept key.
io::PlotSpec figure(const io::Case& c, const DriveSweepReport& sweep, std::size_t column) {
  const MetricAxis axis = drive_metric_axis(drive_metric_names()[column]);
  io::PlotSpec spec;
  std::string what = axis.name;
  what[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(what[0])));
  spec.title = fmt::format("{} over a sweep of {}", what, sweep.key);
  spec.x_label = io::case_key_label(c, sweep.key);
  spec.y_label = axis.label();
  for (std::size_t k = 0; k < sweep.runs.front().axes.size(); ++k) {
    io::PlotSeries series{"axis " + sweep.runs.front().axes[k].axis.name, {}, {}, "linespoints"};
    for (std::size_t i = 0; i < sweep.runs.size(); ++i) {
      const double m = drive_metrics(sweep.runs[i].axes[k])[column];
      if (std::isnan(m)) continue;  // no such quantity for this run (e.g. no integrator)
      series.x.push_back(sweep.values[i]);
      series.y.push_back(axis.scale * m);
    }
    spec.series.push_back(std::move(series));
  }
  return spec;
}

void write_text(std::ostream& out, const io::Case& c, const DriveReport& run) {
  const DriveCut& s = run.cut;
  out << "cutdyn drive: " << c.source << " at " << human(s.rpm) << " rpm, depth "
      << human(m_to_mm(s.cut.width_m)) << " mm, feed " << human(m_to_mm(s.cut.feed_per_tooth_m))
      << " mm/tooth; summaries over each axis' periodic steady state, traces of the last "
      << human(s.options.summary_revolutions) << " revolutions\n";
  if (run.chatter) out << "  warning: " << chatter_warning(run) << "\n";
  for (const DriveAxisReport& a : run.axes) {
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
    if (d.load_lag_max_m)
      out << fmt::format(
          "    load lag        {} µm behind the programmed position (the cut's "
          "load on the speed loop's integrator)\n",
          human(m_to_um(*d.load_lag_max_m), 3));
    if (a.program_error_m)
      out << fmt::format("    against program {} µm (the cutter's deflection less the load lag)\n",
                         human(m_to_um(*a.program_error_m), 3));
  }
}

// Over the last summary revolutions, two panels: ε of each axis, and its motor speed about
// the mean (the speed ripple), on its own axis.
io::PlotFigure figure(const DriveReport& run) {
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
  for (const DriveAxisReport& a : run.axes) {
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

}  // namespace cutdyn::app
