// `cutdyn simulate` for milling: the time-domain simulation of models.md S1
// (docs/models/milling-simulation.md).
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

SimulationSetup milling_setup(const SimulateArgs& args, const io::Case& c) {
  Validator v;
  const auto rpm = args.rpm ? args.rpm : c.simulate.rpm;
  const auto depth_m = args.depth_mm ? std::optional(mm_to_m(*args.depth_mm)) : c.simulate.depth_m;
  if (!rpm) v.add("simulate.rpm: missing (give it in the case or as --rpm)");
  if (!depth_m) v.add("simulate.depth_mm: missing (the axial depth of cut B; or --depth-mm)");
  if (!c.tool)
    v.add("tool: missing (required for milling: at least tool.teeth and tool.diameter_mm)");
  if (!c.operation || !c.operation->feed_per_tooth_m)
    v.add("operation.feed_per_tooth_mm: missing (required by `cutdyn simulate` for milling)");
  const std::string from_flag = args.rpm ? "--rpm" : "simulate.rpm";
  if (rpm && !(*rpm > 0.0)) v.add(from_flag + " = " + human(*rpm) + ": must be positive");
  if (depth_m && !(*depth_m > 0.0))
    v.add(std::string(args.depth_mm ? "--depth-mm" : "simulate.depth_mm") + " = " +
          human(m_to_mm(*depth_m)) + ": must be positive");
  if (args.duration_s && !(*args.duration_s > 0.0))
    v.add("--duration-s = " + human(*args.duration_s) + ": must be positive");
  if (!c.force_law && !c.cutting.kt_pa)
    v.add(
        "cutting.kt_n_per_mm2: missing (the mechanistic force law needs it; or give a "
        "[force_law] table for the S1 law)");
  v.throw_if_any(args.rpm || args.depth_mm || args.duration_s ? "command line" : c.source);

  SimulationSetup s;
  s.rpm = *rpm;
  s.where = args.rpm || args.depth_mm || args.duration_s ? "command line" : c.source;
  MillingCut& cut = s.cut;
  cut.modal = c.modal;
  cut.teeth = c.tool->teeth;
  cut.diameter_m = c.tool->diameter_m;
  cut.helix_rad = c.tool->helix_rad;
  cut.pitch_rad = c.tool->pitch_rad;
  const io::OperationSection& op = *c.operation;
  if (op.entry_rad) {
    cut.entry_rad = *op.entry_rad;
    cut.exit_rad = *op.exit_rad;
  } else {
    MillingModel geometry;
    geometry.radial_immersion = op.radial_immersion;
    geometry.down_milling = op.down_milling;
    cut.entry_rad = geometry.entry_angle();
    cut.exit_rad = geometry.exit_angle();
  }
  cut.spindle_rad_s = units::rpm_to_rad_per_s(s.rpm);
  cut.feed_per_tooth_m = *op.feed_per_tooth_m;
  cut.width_m = *depth_m;
  if (c.force_law) {
    const io::ForceLawSection& f = *c.force_law;
    cut.law = ErmolaevForceLaw{f.c_n_per_m, f.t2_s, f.p0_n, f.t1_m, f.phi_rez_rad, f.phi_skv_rad};
  } else {
    cut.law = MechanisticForceLaw{*c.cutting.kt_pa, c.cutting.kr_pa.value_or(0.0),
                                  c.cutting.kte_n_per_m.value_or(0.0),
                                  c.cutting.kre_n_per_m.value_or(0.0)};
  }
  cut.regenerative = c.simulate.regenerative;
  MillingSimulationOptions& o = s.options;
  o.revolutions = args.duration_s ? *args.duration_s * s.rpm / 60.0 : c.simulate.revolutions;
  o.summary_revolutions = std::min(c.simulate.summary_revolutions, o.revolutions);
  o.steps_per_tooth = c.simulate.steps_per_tooth;
  o.slices = c.simulate.slices;
  o.closed_form_helix = c.simulate.closed_form_helix;
  Validator problems;
  for (const auto& p : cut.validate()) problems.add("simulate: " + p);
  for (const auto& p : o.validate()) problems.add("simulate: " + p);
  problems.throw_if_any(s.where);
  return s;
}

// "KEY=FROM:STEP:TO" (MATLAB's colon notation), at most 10 000 values.
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
  const auto fail = [&](const std::string& why) -> Sweep {
    throw InvalidInput({"--sweep = \"" + spec + "\": " + why}, "command line");
  };
  const auto eq = spec.find('=');
  if (eq == std::string::npos || eq == 0) return fail("expected KEY=FROM:STEP:TO");
  Sweep sweep{spec.substr(0, eq), {}};
  const std::string range = spec.substr(eq + 1);
  const auto c1 = range.find(':');
  const auto c2 = c1 == std::string::npos ? std::string::npos : range.find(':', c1 + 1);
  if (c2 == std::string::npos || range.find(':', c2 + 1) != std::string::npos)
    return fail("expected KEY=FROM:STEP:TO");
  double from = 0, step = 0, to = 0;
  try {
    std::size_t used = 0;
    const auto number = [&](const std::string& text) {
      const double x = std::stod(text, &used);
      if (used != text.size() || !std::isfinite(x)) throw std::invalid_argument(text);
      return x;
    };
    from = number(range.substr(0, c1));
    step = number(range.substr(c1 + 1, c2 - c1 - 1));
    to = number(range.substr(c2 + 1));
  } catch (const std::exception&) {
    return fail("FROM, STEP and TO must be numbers");
  }
  if (!(step > 0.0)) return fail("STEP must be positive");
  if (to < from) return fail("TO must not be less than FROM");
  const double count = std::floor((to - from) / step + 1e-9) + 1.0;
  if (count > 10000.0) return fail(fmt::format("{:.0f} values; at most 10000", count));
  for (int i = 0; i < static_cast<int>(count); ++i) {
    const double x = from + step * i;
    // Clean decimal values (0.1·3 = 0.30000000000000004 → 0.3).
    sweep.values.push_back(std::stod(fmt::format("{:.12g}", x)));
  }
  return sweep;
}

namespace {

std::string um(double m) { return human(m_to_um(m), 4); }

// "chatter…" → "CHATTER…": the verdict stands out in the text report.
std::string shout(std::string verdict) {
  if (verdict.rfind("chatter", 0) == 0) verdict.replace(0, 7, "CHATTER");
  return verdict;
}

// ---- sweeps ------------------------------------------------------------------------------

const std::vector<std::string>& metric_names() {
  static const std::vector<std::string> names{"force_pulsation",   "mean_force_n",
                                              "peak_force_n",      "min_force_n",
                                              "mean_teeth_in_cut", "vibration_pp_x_um",
                                              "vibration_pp_y_um", "chatter_indicator",
                                              "contact_loss",      "surface_location_error_um"};
  return names;
}

std::vector<double> metrics(const MillingSimulationResult& r) {
  return {r.force_pulsation,
          r.mean_force_n,
          r.peak_force_n,
          r.min_force_n,
          r.mean_teeth_in_cut,
          m_to_um(r.vibration_pp_x_m),
          m_to_um(r.vibration_pp_y_m),
          r.chatter_indicator,
          r.contact_loss,
          r.surface_location_error_m ? m_to_um(*r.surface_location_error_m)
                                     : std::numeric_limits<double>::quiet_NaN()};
}

int run_sweep(const SimulateArgs& args, const io::Case& c, std::ostream& out, std::ostream& err) {
  const Sweep sweep = parse_sweep(args.sweep);
  const auto& names = metric_names();
  const std::size_t column = metric_column(args.metric, "force_pulsation", names);
  const std::string& metric = names[column];
  // Every case of the sweep is read and checked before any simulation runs.
  std::vector<SimulationSetup> setups;
  for (double value : sweep.values) {
    const io::Case varied = io::with_value(c, sweep.key, value);
    if (varied.process != io::Process::kMilling)
      throw InvalidInput({"--sweep: the varied case is not a milling case"}, varied.source);
    setups.push_back(milling_setup(args, varied));
  }
  std::vector<MillingSimulationResult> results(setups.size());
  parallel_for(
      static_cast<int>(setups.size()), args.threads,
      [&](int i) {
        const auto k = static_cast<std::size_t>(i);
        rethrow_as(setups[k].where, "simulate",
                   [&] { results[k] = simulate_milling(setups[k].cut, setups[k].options); });
      },
      progress_reporter(err, "sweep"));

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
    json doc{{"command", "simulate"}, {"case", io::to_json(c)}, {"source", c.source},
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

int run_simulate_milling(const SimulateArgs& args, const io::Case& c, std::ostream& out,
                         std::ostream& err) {
  if (!args.sweep.empty()) return run_sweep(args, c, out, err);
  if (!args.metric.empty()) throw InvalidInput({"--metric: only with --sweep"}, "command line");
  const SimulationSetup s = milling_setup(args, c);
  MillingSimulationResult r;
  rethrow_as(s.where, "simulate", [&] { r = simulate_milling(s.cut, s.options); });
  const bool s1 = c.force_law.has_value();

  // The stability prediction at this speed, for the mechanistic law with regeneration.
  std::optional<MillingBoundary> predicted;
  if (!s1 && s.cut.regenerative && !s.cut.modal.modes.empty()) {
    MillingModel m = milling_model(c, "simulate");
    MillingStabilityOptions so;
    so.depth_max_m = c.lobes.depth_max_m;
    so.rel_tol = 1e-3;
    predicted = milling_critical_depth(m, s.rpm, so);
    // Beyond the case's limit, carried on to 1.25× the depth on the same depth grid (as
    // `cutdyn check`), so the prediction is that of the lobes.
    const double reach = 1.25 * s.cut.width_m;
    if (!predicted->boundary.found && reach > so.depth_max_m &&
        reach <= kMaxSearchExtension * so.depth_max_m) {
      predicted = milling_critical_depth(m, s.rpm, extend_search(so, reach));
    }
  }

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
  if (!r.growth_settled && r.status == SimulationStatus::kCompleted)
    err << "cutdyn: warning: " << c.source << ": the perturbation's growth has not settled over "
        << human(s.options.revolutions)
        << " revolutions (the decisive root is not yet told from its neighbours): the verdict is "
           "uncertain; run more revolutions ([simulate] revolutions)\n";
  if (predicted) {
    out << "    predicted critical depth " << depth_text(predicted->boundary) << " → depth is "
        << human(100.0 * s.cut.width_m / predicted->boundary.depth_m, 3) << " % of it\n";
  }

  io::OutputTransaction outputs;
  if (!args.outputs.csv.empty()) {
    io::CsvWriter csv(outputs.open(args.outputs.csv),
                      {"time_s", "fx_n", "fy_n", "force_n", "x_um", "y_um", "teeth_in_cut"});
    for (std::size_t i = 0; i < r.time_s.size(); ++i)
      csv.row({r.time_s[i], r.fx_n[i], r.fy_n[i], r.force_n[i], m_to_um(r.x_m[i]),
               m_to_um(r.y_m[i]), r.teeth_in_cut[i]});
  }
  if (!args.outputs.json.empty()) {
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
    json doc{{"command", "simulate"},
             {"case", io::to_json(c)},
             {"source", c.source},
             {"spindle_rpm", s.rpm},
             {"depth_mm", m_to_mm(s.cut.width_m)},
             {"revolutions", s.options.revolutions},
             {"force_law", s1 ? "s1" : "mechanistic"},
             {"summary", std::move(summary)}};
    io::write_json(outputs.open(args.outputs.json), doc);
  }
  if (!args.outputs.plot.empty()) {
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
    io::write_plot(spec, args.outputs.plot, outputs);
  }
  commit_outputs(outputs, args.outputs, out);
  return 0;
}

}  // namespace cutdyn::cli
