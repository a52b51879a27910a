// `cutdyn simulate` for milling: the time-domain simulation, force laws after
// [Ermolaev2020] (docs/models/milling-simulation.md).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/milling_setup.hpp"
#include "cutdyn/core/parallel.hpp"
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

int run_sweep(const SimulateArgs& args, const io::Case& c, std::ostream& out, std::ostream& err) {
  const auto& names = app::milling_metric_names();
  const std::size_t column = metric_column(args.metric, "force_pulsation", names);
  const std::string& metric = names[column];
  const app::MillingSweepJobReport job = app::sweep_milling_case(
      c, parse_sweep(args.sweep), simulate_request(args), args.threads,
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
    json doc{{"command", "simulate"}, {"schema_version", kJsonSchemaVersion}, {"case", io::to_json(c)}, {"source", c.source},
             {"sweep", sweep.key},    {"metric", metric},       {"points", std::move(points)}};
    io::write_json(outputs.open(args.outputs.json), doc);
  }
  if (!args.outputs.plot.empty()) {
    io::PlotSpec spec;
    spec.title = fmt::format("{} against {}", metric, sweep.key);
    spec.x_label = sweep.key;
    spec.y_label = metric;
    io::PlotSeries series{metric, {}, {}, "linespoints"};
    for (std::size_t i = 0; i < results.size(); ++i) {
      const double m = metrics(results[i])[column];
      if (std::isnan(m)) continue;
      series.x.push_back(sweep.values[i]);
      series.y.push_back(m);
    }
    spec.series.push_back(std::move(series));
    io::write_plot(spec, args.outputs.plot, outputs);
  }
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
  out << fmt::format(
      "  milling, {} teeth, window {}–{}°, {} law{}, {}\n", s.cut.teeth,
      human(units::rad_to_deg(s.cut.entry_rad)), human(units::rad_to_deg(s.cut.exit_rad)),
      s1 ? "S1 (Ermolaev)" : "mechanistic",
      s.cut.helix_rad > 0.0
          ? fmt::format(", helix {}° ({}{})", human(units::rad_to_deg(s.cut.helix_rad)),
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
  for (const std::string& w : job.warnings) err << "cutdyn: warning: " << c.source << ": " << w << "\n";
  if (predicted) {
    out << "    predicted critical depth " << depth_text(predicted->boundary) << " → depth is "
        << human(100.0 * s.cut.width_m / predicted->boundary.depth_m, 3) << " % of it\n";
  }

}

json milling_json(const io::Case& c, const app::MillingSimulationJobReport& job) {
  const SimulationSetup& s = job.setup;
  const MillingSimulationResult& r = job.result;
  const bool s1 = job.s1_law;
  const std::optional<MillingBoundary>& predicted = job.predicted;
  json summary{{"force_pulsation", r.force_pulsation},
               {"mean_force_n", r.mean_force_n},
               {"min_force_n", r.min_force_n},
               {"peak_force_n", r.peak_force_n},
               {"mean_fx_n", r.mean_fx_n},
               {"mean_fy_n", r.mean_fy_n},
               {"mean_teeth_in_cut", r.mean_teeth_in_cut},
               {"vibration_pp_x_um", m_to_um(r.vibration_pp_x_m)},
               {"vibration_pp_y_um", m_to_um(r.vibration_pp_y_m)},
               {"chatter_indicator", r.chatter_indicator},
               {"growth_per_period", r.growth_per_period},
               {"growth_rate_per_s", r.growth_rate_per_s},
               {"growth_settled", r.growth_settled},
               {"growth_components", r.growth_components},
               {"status", to_string(r.status)},
               {"stop_time_s", r.stop_time_s},
               {"verdict", r.verdict()},
               {"contact_loss", r.contact_loss},
               {"chatter", r.chatter},
               {"surface_location_error_um",
                r.surface_location_error_m ? json(m_to_um(*r.surface_location_error_m)) : json()},
               {"slices", r.slices},
               {"step_s", r.step_s},
               {"steps", r.steps}};
  if (predicted) summary["predicted_critical_depth_mm"] = m_to_mm(predicted->boundary.depth_m);
  json doc{{"command", "simulate"}, {"schema_version", kJsonSchemaVersion},
           {"case", io::to_json(c)},
           {"source", c.source},
           {"spindle_rpm", s.rpm},
           {"depth_mm", m_to_mm(s.cut.width_m)},
           {"revolutions", s.options.revolutions},
           {"force_law", s1 ? "s1" : "mechanistic"},
           {"summary", std::move(summary)}};
  return doc;
}

io::PlotSpec milling_plot(const app::MillingSimulationJobReport& job) {
  const SimulationSetup& s = job.setup;
  const MillingSimulationResult& r = job.result;
  // The steady part: the last summary revolutions.
  const double from =
      r.time_s.empty() ? 0.0 : r.time_s.back() - s.options.summary_revolutions * 60.0 / s.rpm;
  io::PlotSpec spec;
  spec.title = fmt::format("Force and vibration at {} rpm, depth {} mm (ΔP = {} %)", human(s.rpm),
                           human(m_to_mm(s.cut.width_m)), human(100.0 * r.force_pulsation, 3));
  spec.x_label = "time (s)";
  spec.y_label = "force on the cutter (N)";
  spec.y2_label = "cutter displacement (µm)";
  io::PlotSeries fx{"Fx (feed)", {}, {}, "lines"}, fy{"Fy", {}, {}, "lines"},
      f{"|F|", {}, {}, "lines"}, x{"x (right axis)", {}, {}, "lines", true},
      y{"y (right axis)", {}, {}, "lines", true};
  for (std::size_t i = 0; i < r.time_s.size(); ++i) {
    if (r.time_s[i] < from) continue;
    for (io::PlotSeries* p : {&fx, &fy, &f, &x, &y}) p->x.push_back(r.time_s[i]);
    fx.y.push_back(r.fx_n[i]);
    fy.y.push_back(r.fy_n[i]);
    f.y.push_back(r.force_n[i]);
    x.y.push_back(m_to_um(r.x_m[i]));
    y.y.push_back(m_to_um(r.y_m[i]));
  }
  spec.series = {std::move(f), std::move(fx), std::move(fy)};
  if (!s.cut.modal.modes.empty()) {
    spec.series.push_back(std::move(x));
    spec.series.push_back(std::move(y));
  }
  return spec;
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
  if (!args.outputs.json.empty()) io::write_json(outputs.open(args.outputs.json), milling_json(c, job));
  if (!args.outputs.plot.empty()) io::write_plot(milling_plot(job), args.outputs.plot, outputs);
  commit_outputs(outputs, args.outputs, out);
  return 0;
}

}  // namespace cutdyn::cli
