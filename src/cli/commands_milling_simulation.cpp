// `cutdyn simulate` for milling: the time-domain simulation, force laws after
// [Ermolaev2020] (docs/models/milling-simulation.md).
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/milling_setup.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/io/output.hpp"
#include "cutdyn/io/plot.hpp"
#include "cutdyn/simulate/milling_simulation.hpp"
#include "cutdyn/stability/milling.hpp"

namespace cutdyn::cli {
namespace {

using nlohmann::json;
using units::m_to_mm;
using units::m_to_um;
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

std::string um(double m) { return human(m_to_um(m), 4); }

// "chatter…" → "CHATTER…": the verdict stands out in the text report.
std::string shout(std::string verdict) {
  if (verdict.rfind("chatter", 0) == 0) verdict.replace(0, 7, "CHATTER");
  return verdict;
}

// ---- sweeps ------------------------------------------------------------------------------

// A metric's axis in a figure: its name in words, the unit it is drawn in ("" for a
// number without one) and the factor from the metric's value to that unit.
struct MetricAxis {
  std::string name, unit;
  double scale = 1.0;
  std::string label() const { return unit.empty() ? name : name + " (" + unit + ")"; }
};

MetricAxis milling_metric_axis(const std::string& metric) {
  if (metric == "force_pulsation") return {"force pulsation ΔP", "%", 100.0};
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

// The metric against the swept key, the runs that chatter marked.
io::PlotSpec sweep_plot(const io::Case& c, const app::MillingSweepJobReport& job,
                        std::size_t column) {
  const std::string& metric = app::milling_metric_names()[column];
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
    const double m = app::milling_metrics(job.results[i])[column];
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
    io::write_plot(sweep_plot(c, job, column), args.outputs.plot, outputs);
  commit_outputs(outputs, args.outputs, out);
  return 0;
}

}  // namespace

namespace {

void print_milling(const io::Case& c, const app::MillingSimulationJobReport& job, std::ostream& out,
                   std::ostream& err) {
  const SimulationSetup& s = job.setup;
  const MillingSimulationResult& r = job.result;
  const bool s1 = job.s1_law;
  const std::optional<MillingBoundary>& predicted = job.predicted;
  out << "cutdyn simulate: " << c.source << " at " << human(s.rpm) << " rpm, depth "
      << human(m_to_mm(s.cut.width_m)) << " mm, feed " << human(m_to_mm(s.cut.feed_per_tooth_m))
      << " mm/tooth, " << human(s.options.revolutions) << " revolutions\n";
  out << fmt::format("  milling, {} teeth, window {}–{}°, {} law{}, {}\n", s.cut.process.tool.teeth,
                     human(units::rad_to_deg(s.cut.process.engagement.entry_angle())),
                     human(units::rad_to_deg(s.cut.process.engagement.exit_angle())),
                     s1 ? "S1 (Ermolaev)" : "mechanistic",
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
  out << fmt::format("    force pulsation ΔP      {} %\n", human(100.0 * r.force_pulsation, 3));
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
  for (const std::string& w : job.warnings)
    err << "cutdyn: warning: " << c.source << ": " << w << "\n";
  if (predicted) {
    out << "    predicted critical depth " << depth_text(predicted->boundary) << " → depth is "
        << human(100.0 * s.cut.width_m / predicted->boundary.depth_m, 3) << " % of it\n";
  }
}

// Points per series of the whole run: enough for the envelope of every tooth pass in a
// figure a few thousand pixels wide.
constexpr std::size_t kEnvelopeBuckets = 2000;
// One colour per direction on both panels (x and Fx, y and Fy); |F| in black.
constexpr const char* kXColour = "#0072B2";
constexpr const char* kYColour = "#D55E00";
constexpr const char* kForceColour = "#000000";

// Two panels: the cutter's displacement over the whole run in each direction that has modes
// (so that growth or decay shows), and the forces over the last summary revolutions, whose
// window the first panel marks.
io::PlotFigure milling_plot(const app::MillingSimulationJobReport& job) {
  const SimulationSetup& s = job.setup;
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
      lfy{"Fy", {}, {}, "lines", false, kYColour};
  for (std::size_t i = 0; i < r.time_s.size(); ++i) {
    if (r.time_s[i] < from) continue;
    for (io::PlotSeries* p : {&lf, &lfx, &lfy}) p->x.push_back(r.time_s[i]);
    lf.y.push_back(r.force_n[i]);
    lfx.y.push_back(r.fx_n[i]);
    lfy.y.push_back(r.fy_n[i]);
  }
  for (io::PlotSeries* p : {&lf, &lfx, &lfy})
    last.series.push_back(io::envelope(*p, kEnvelopeBuckets));
  figure.panels = {std::move(whole), std::move(last)};
  return figure;
}

}  // namespace

int run_simulate_milling(const SimulateArgs& args, const io::Case& c, std::ostream& out,
                         std::ostream& err) {
  if (!args.sweep.empty()) return run_sweep(args, c, out, err);
  if (!args.metric.empty()) throw InvalidInput({"--metric: only with --sweep"}, "command line");
  const app::MillingSimulationJobReport job = app::simulate_milling_case(c, simulate_request(args));
  print_milling(c, job, out, err);
  const MillingSimulationResult& r = job.result;
  io::OutputTransaction outputs;
  if (!args.outputs.csv.empty()) {
    io::CsvWriter csv(outputs.open(args.outputs.csv),
                      {"time_s", "fx_n", "fy_n", "force_n", "x_um", "y_um", "teeth_in_cut"});
    for (std::size_t i = 0; i < r.time_s.size(); ++i)
      csv.row({r.time_s[i], r.fx_n[i], r.fy_n[i], r.force_n[i], m_to_um(r.x_m[i]),
               m_to_um(r.y_m[i]), r.teeth_in_cut[i]});
  }
  if (!args.outputs.json.empty())
    io::write_json(outputs.open(args.outputs.json), app::to_json(c, job));
  if (!args.outputs.plot.empty()) io::write_plot(milling_plot(job), args.outputs.plot, outputs);
  commit_outputs(outputs, args.outputs, out);
  return 0;
}

}  // namespace cutdyn::cli
