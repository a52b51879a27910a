// The milling simulation's reports rendered: the text of `cutdyn simulate` and its figures
// (force laws after [Ermolaev2020]; docs/models/milling-simulation.md).
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>

#include "cutdyn/app/detail/render_text.hpp"
#include "cutdyn/app/detail/text.hpp"
#include "cutdyn/app/render.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/simulate/milling_simulation.hpp"

namespace cutdyn::app {
namespace {

using units::m_to_mm;
using units::m_to_um;

std::string um(double m) { return human(m_to_um(m), 4); }

// "chatter…" → "CHATTER…": the verdict stands out in the text report.
std::string shout(std::string verdict) {
  if (verdict.rfind("chatter", 0) == 0) verdict.replace(0, 7, "CHATTER");
  return verdict;
}

MetricAxis milling_metric_axis(const std::string& metric) {
  if (metric == "force_pulsation") return {"force pulsation ΔP", "%", 100.0};
  if (metric == "cutting_force_pulsation")
    return {"cutting force pulsation ΔP (P alone)", "%", 100.0};
  if (metric == "mean_cutting_force_n") return {"mean cutting force ΣP", "N"};
  if (metric == "mean_force_n") return {"mean force |F|", "N"};
  if (metric == "peak_force_n") return {"peak force |F|", "N"};
  if (metric == "min_force_n") return {"smallest force |F|", "N"};
  if (metric == "mean_teeth_in_cut") return {"mean teeth in cut", ""};
  if (metric == "vibration_pp_x_um") return {"vibration in x, peak to peak", "µm"};
  if (metric == "vibration_pp_y_um") return {"vibration in y, peak to peak", "µm"};
  if (metric == "chatter_indicator") return {"chatter indicator", ""};
  if (metric == "contact_loss") return {"out of the cut inside the window", "%", 100.0};
  if (metric == "surface_location_error_um") return {"surface location error", "µm"};
  return {metric, ""};
}

// Points per series of the whole run: enough for the envelope of every tooth pass in a
// figure a few thousand pixels wide.
constexpr std::size_t kEnvelopeBuckets = 2000;
// One colour per direction on both panels (x and Fx, y and Fy); |F| in black.
constexpr const char* kXColour = "#0072B2";
constexpr const char* kYColour = "#D55E00";
constexpr const char* kForceColour = "#000000";
constexpr const char* kCuttingColour = "#009E73";

}  // namespace

void write_text(std::ostream& out, const io::Case& c, const MillingSimulationJobReport& job) {
  const MillingSetup& s = job.setup;
  const MillingSimulationResult& r = job.result;
  const bool s1 = job.s1_law;
  const bool unwindowed = s.cut.process.s1_law && s.cut.process.s1_law->lag_input ==
                                                      ErmolaevForceLaw::LagInput::kUnwindowed;
  const std::optional<MillingBoundary>& predicted = job.predicted;
  out << "cutdyn simulate: " << c.source << " at " << human(s.rpm) << " rpm, depth "
      << human(m_to_mm(s.cut.width_m)) << " mm, feed " << human(m_to_mm(s.cut.feed_per_tooth_m))
      << " mm/tooth, " << human(s.options.revolutions) << " revolutions\n";
  out << fmt::format("  milling, {} teeth, window {}–{}°, {} law{}, {}\n", s.cut.process.tool.teeth,
                     human(units::rad_to_deg(s.cut.process.engagement.entry_angle())),
                     human(units::rad_to_deg(s.cut.process.engagement.exit_angle())),
                     !s1          ? "mechanistic"
                     : unwindowed ? "S1 (Ermolaev, unwindowed lag)"
                                  : "S1 (Ermolaev)",
                     s.cut.process.tool.helix_rad > 0.0
                         ? fmt::format(", helix {}° ({}{})",
                                       human(units::rad_to_deg(s.cut.process.tool.helix_rad)),
                                       s.options.closed_form_helix ? "closed form" : "slices: ",
                                       s.options.closed_form_helix ? "" : std::to_string(r.slices))
                         : "",
                     s.cut.regenerative ? "regenerative chip" : "chip from the feed alone");
  if (r.status == SimulationStatus::kRunaway)
    out << fmt::format(
        "  runaway growth: stopped at t = {} s (of {} s); over the revolutions before:\n",
        human(r.stop_time_s, 4), human(s.options.revolutions * 60.0 / s.rpm, 4));
  else
    out << fmt::format("  over the last {} revolutions:\n", human(s.options.summary_revolutions));
  out << fmt::format("    force pulsation ΔP      {} % (|F|), {} % (cutting force ΣP alone)\n",
                     human(100.0 * r.force_pulsation, 3),
                     human(100.0 * r.cutting_force_pulsation, 3));
  out << fmt::format("    cutting force ΣP        mean {} N\n", human(r.mean_cutting_force_n));
  out << fmt::format("    force |F|               mean {} N, min {} N, peak {} N\n",
                     human(r.mean_force_n), human(r.min_force_n), human(r.peak_force_n));
  out << fmt::format("    mean force Fx, Fy       {} N, {} N\n", human(r.mean_fx_n),
                     human(r.mean_fy_n));
  out << fmt::format("    mean teeth in cut       {} (out of the cut inside the window: {} %)\n",
                     human(r.mean_teeth_in_cut), human(100.0 * r.contact_loss, 3));
  out << fmt::format("    vibration (peak-peak)   x {} µm, y {} µm\n", um(r.vibration_pp_x_m),
                     um(r.vibration_pp_y_m));
  if (r.surface_location_error_m)
    out << fmt::format("    surface location error  {} µm\n", um(*r.surface_location_error_m));
  out << fmt::format("    chatter indicator       {}\n", human(r.chatter_indicator, 3));
  out << fmt::format("    perturbation growth     {:+.3g} per period ({:+.3g} 1/s) → {}\n",
                     r.growth_per_period, r.growth_rate_per_s, shout(r.verdict()));
  if (predicted) {
    out << "    predicted critical depth " << depth_text(predicted->boundary) << " → depth is "
        << human(100.0 * s.cut.width_m / predicted->boundary.depth_m, 3) << " % of it\n";
  }
}

// Two panels: the cutter's displacement over the whole run in each direction that has modes
// (so that growth or decay shows), and the forces over the last summary revolutions, whose
// window the first panel marks.
io::PlotFigure figure(const MillingSimulationJobReport& job) {
  const MillingSetup& s = job.setup;
  const MillingSimulationResult& r = job.result;
  const double summary_s = s.options.summary_revolutions * 60.0 / s.rpm;
  const double from =
      r.time_s.empty() ? 0.0 : std::max(r.time_s.front(), r.time_s.back() - summary_s);
  const std::string revolutions = human(s.options.summary_revolutions);
  const bool runaway = r.status == SimulationStatus::kRunaway;
  const ModalModel modes = s.cut.process.structure_modes();
  const auto has_modes = [&](Direction d) { return modes.count(d) > 0; };

  io::PlotFigure figure;
  figure.title =
      fmt::format("Milling at {} rpm, depth {} mm: ΔP = {} %, {}", human(s.rpm),
                  human(m_to_mm(s.cut.width_m)), human(100.0 * r.force_pulsation, 3), r.verdict());

  io::PlotSpec whole;
  whole.x_label = "time (s)";
  whole.title = runaway ? "Cutter displacement until the runaway stopped the run"
                        : "Cutter displacement over the whole run";
  whole.y_label = "cutter displacement (µm)";
  io::PlotSeries x{"x (feed)", r.time_s, {}, "lines", false, kXColour},
      y{"y", r.time_s, {}, "lines", false, kYColour};
  for (std::size_t i = 0; i < r.time_s.size(); ++i) {
    x.y.push_back(m_to_um(r.x_m[i]));
    y.y.push_back(m_to_um(r.y_m[i]));
  }
  // A case has modes (the loader requires them), but not always in both directions.
  if (has_modes(Direction::kX)) whole.series.push_back(io::envelope(x, kEnvelopeBuckets));
  if (has_modes(Direction::kY)) whole.series.push_back(io::envelope(y, kEnvelopeBuckets));
  whole.x_marks.push_back({from, "last " + revolutions + " rev (below)"});

  io::PlotSpec last;
  last.title = fmt::format(
      "Force on the cutter over the last {}{}",
      s.options.summary_revolutions == 1.0 ? "revolution" : revolutions + " revolutions",
      runaway ? " before the stop" : "");
  last.x_label = "time (s)";
  last.y_label = "force on the cutter (N)";
  io::PlotSeries lf{"|F|", {}, {}, "lines", false, kForceColour},
      lfx{"Fx (feed)", {}, {}, "lines", false, kXColour},
      lfy{"Fy", {}, {}, "lines", false, kYColour},
      lp{"ΣP (cutting forces alone)", {}, {}, "lines", false, kCuttingColour};
  for (std::size_t i = 0; i < r.time_s.size(); ++i) {
    if (r.time_s[i] < from) continue;
    for (io::PlotSeries* p : {&lf, &lfx, &lfy, &lp}) p->x.push_back(r.time_s[i]);
    lf.y.push_back(r.force_n[i]);
    lfx.y.push_back(r.fx_n[i]);
    lfy.y.push_back(r.fy_n[i]);
    lp.y.push_back(r.cutting_force_n[i]);
  }
  for (io::PlotSeries* p : {&lf, &lfx, &lfy, &lp})
    last.series.push_back(io::envelope(*p, kEnvelopeBuckets));
  figure.panels = {std::move(whole), std::move(last)};
  return figure;
}

void write_text(std::ostream& out, const io::Case& c, const MillingSweepJobReport& job,
                std::size_t column) {
  const std::string& metric = milling_metric_names()[column];
  const Sweep& sweep = job.sweep;
  const auto& results = job.results;
  const auto metrics = milling_metrics;

  out << "cutdyn simulate: " << c.source << ", sweep of " << sweep.key << " over "
      << sweep.values.size() << " values (" << human(sweep.values.front()) << " to "
      << human(sweep.values.back()) << ")\n";
  out << fmt::format("  {:>14}  {:>16}  {:>12}  {:>10}  {}\n", sweep.key, metric, "mean |F| N",
                     "teeth", "chatter");
  for (std::size_t i = 0; i < results.size(); ++i) {
    const auto m = metrics(results[i]);
    out << fmt::format("  {:>14}  {:>16}  {:>12}  {:>10}  {}\n", human(sweep.values[i]),
                       std::isnan(m[column]) ? "–" : human(m[column], 4),
                       human(results[i].mean_force_n, 4), human(results[i].mean_teeth_in_cut, 4),
                       results[i].status == SimulationStatus::kRunaway
                           ? "yes (runaway)"
                           : (results[i].chatter ? "yes" : "no"));
  }
}

// The metric against the swept key, the runs that chatter marked.
io::PlotSpec figure(const io::Case& c, const MillingSweepJobReport& job, std::size_t column) {
  const std::string& metric = milling_metric_names()[column];
  const MetricAxis axis = milling_metric_axis(metric);
  io::PlotSpec spec;
  std::string what = axis.name;
  what[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(what[0])));
  spec.title = fmt::format("{} over a sweep of {}", what, job.sweep.key);
  spec.x_label = io::case_key_label(c, job.sweep.key);
  spec.y_label = axis.label();
  io::PlotSeries line{axis.name, {}, {}, "linespoints"};
  io::PlotSeries chatter{"chatter (vibration grows)", {}, {}, "marker"};
  for (std::size_t i = 0; i < job.results.size(); ++i) {
    const double m = milling_metrics(job.results[i])[column];
    if (std::isnan(m)) continue;
    line.x.push_back(job.sweep.values[i]);
    line.y.push_back(axis.scale * m);
    if (job.results[i].chatter) {
      chatter.x.push_back(job.sweep.values[i]);
      chatter.y.push_back(axis.scale * m);
    }
  }
  spec.series.push_back(std::move(line));
  if (!chatter.x.empty()) spec.series.push_back(std::move(chatter));
  return spec;
}

}  // namespace cutdyn::app
