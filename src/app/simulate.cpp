#include "cutdyn/app/simulate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "cutdyn/app/case_models.hpp"
#include "cutdyn/app/detail/text.hpp"
#include "cutdyn/app/stability.hpp"
#include "cutdyn/core/detail/parallel.hpp"
#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn::app {
namespace {

using units::m_to_mm;
using units::m_to_um;

bool any_override(const SimulateRequest& r) { return r.rpm || r.depth_m || r.duration_s; }

// The turning options of the case and the request; every missing or bad value throws.
TurningSimulationOptions turning_options(const io::Case& c, const SimulateRequest& r) {
  Validator v;
  const auto rpm = r.rpm ? r.rpm : c.simulate.rpm;
  const auto depth_m = r.depth_m ? r.depth_m : c.simulate.depth_m;
  if (!rpm) v.add("simulate.rpm: missing (give it in the case or as " + r.names.rpm + ")");
  if (!depth_m)
    v.add("simulate.depth_mm: missing (give it in the case or as " + r.names.depth + ")");
  if (!c.cutting.uncut_chip_thickness_m)
    v.add(
        "cutting.uncut_chip_thickness_mm: missing (required by `cutdyn simulate`: the feed per "
        "revolution)");
  if (depth_m) require_depth(v, r.depth_m ? r.names.depth : "simulate.depth_mm", *depth_m);
  v.throw_if_any(c.source);
  TurningSimulationOptions o;
  o.rpm = *rpm;
  o.depth_m = *depth_m;
  o.feed_m = *c.cutting.uncut_chip_thickness_m;
  o.duration_s = r.duration_s.value_or(c.simulate.duration_s);
  o.initial_displacement_m = c.simulate.initial_displacement_m;
  o.progress = r.progress;
  if (const auto problems = o.validate(); !problems.empty()) {
    std::vector<std::string> named;
    for (const auto& p : problems) named.push_back("simulate: " + p);
    throw InvalidInput(named, r.where(c));
  }
  return o;
}

}  // namespace

std::string SimulateRequest::where(const io::Case& c) const {
  return any_override(*this) ? names.where : c.source;
}

TurningSimulationJobReport simulate_turning_case(const io::Case& c, const SimulateRequest& r) {
  const TurningProcess model = turning_process(c, "simulate");
  TurningSimulationJobReport report;
  report.options = turning_options(c, r);
  const TurningSimulationOptions& o = report.options;
  const std::string where = r.where(c);
  rethrow_as(where, "simulate", [&] { check_speed_domain(model, o.rpm); });
  report.description = describe_turning(c, model);
  if (std::string w = spindle_warning(c, o.rpm, r.rpm ? r.names.rpm : "simulate.rpm"); !w.empty())
    report.warnings.push_back(std::move(w));
  struct Run {
    std::string name;
    TurningProcess model;
  };
  std::vector<Run> runs{{model.vibration ? "vibration-assisted" : "conventional", model}};
  if (model.vibration) runs.push_back({"conventional", model.conventional()});
  TurningStabilityOptions so = turning_stability_options(c, TurningMethod::kFullDiscretization);
  so.depth_max_m = std::max(so.depth_max_m, std::min(4.0 * o.depth_m, kMaxDepthM));
  for (const Run& run : runs) {
    TurningSimulationRun out{run.name, {}, {}};
    rethrow_as(where, "simulate", [&] { out.result = simulate_turning(run.model, o); });
    so.method =
        run.model.vibration ? TurningMethod::kFullDiscretization : TurningMethod::kClosedForm;
    out.predicted = turning_critical_depth(run.model, o.rpm, so);
    if (!out.result.growth_settled)
      report.warnings.push_back(run.name + ": the free response's growth has not settled over " +
                                human(o.duration_s) +
                                " s: the verdict is uncertain; simulate longer ([simulate] "
                                "duration_s)");
    report.runs.push_back(std::move(out));
  }
  report.options.progress = nullptr;  // the report outlives the caller's progress
  return report;
}

MillingSetup milling_setup(const io::Case& c, const SimulateRequest& r) {
  const RequestNames& n = r.names;
  Validator v;
  const auto rpm = r.rpm ? r.rpm : c.simulate.rpm;
  const auto depth_m = r.depth_m ? r.depth_m : c.simulate.depth_m;
  if (!rpm) v.add("simulate.rpm: missing (give it in the case or as " + n.rpm + ")");
  if (!depth_m) v.add("simulate.depth_mm: missing (the axial depth of cut B; or " + n.depth + ")");
  if (!c.tool)
    v.add("tool: missing (required for milling: at least tool.teeth and tool.diameter_mm)");
  if (!c.operation || !c.operation->feed_per_tooth_m)
    v.add("operation.feed_per_tooth_mm: missing (required by `cutdyn simulate` for milling)");
  if (rpm && !(*rpm > 0.0))
    v.add((r.rpm ? n.rpm : "simulate.rpm") + " = " + human(*rpm) + ": must be positive");
  if (depth_m) require_depth(v, r.depth_m ? n.depth : "simulate.depth_mm", *depth_m);
  if (r.duration_s && !(*r.duration_s > 0.0))
    v.add(n.duration + " = " + human(*r.duration_s) + ": must be positive");
  if (!c.force_law && !c.cutting.kt_pa)
    v.add(
        "cutting.kt_n_per_mm2: missing (the mechanistic force law needs it; or give a "
        "[force_law] table for the S1 law)");
  v.throw_if_any(r.where(c));

  MillingSetup s;
  s.rpm = *rpm;
  s.where = r.where(c);
  MillingCut& cut = s.cut;
  cut.process = milling_process_as_given(c);
  cut.spindle_rad_s = units::rpm_to_rad_per_s(s.rpm);
  cut.feed_per_tooth_m = *c.operation->feed_per_tooth_m;
  cut.width_m = *depth_m;
  cut.regenerative = c.simulate.regenerative;
  MillingSimulationOptions& o = s.options;
  o.revolutions = r.duration_s ? *r.duration_s * s.rpm / 60.0 : c.simulate.revolutions;
  o.summary_revolutions = std::min(c.simulate.summary_revolutions, o.revolutions);
  o.steps_per_tooth = c.simulate.steps_per_tooth;
  o.slices = c.simulate.slices;
  o.closed_form_helix = c.simulate.closed_form_helix;
  o.progress = r.progress;
  Validator problems;
  for (const auto& p : cut.validate()) problems.add("simulate: " + p);
  for (const auto& p : o.validate()) problems.add("simulate: " + p);
  problems.throw_if_any(s.where);
  const ModalModel modes = cut.process.structure_modes();
  if (cut.regenerative && !modes.modes.empty())
    rethrow_as(s.where, r.rpm ? n.rpm : "simulate.rpm", [&] {
      check_milling_speed(cut.process.tool.teeth, units::rad_per_s_to_hz(modes.max_natural_rad_s()),
                          s.rpm);
    });
  return s;
}

MillingSimulationJobReport simulate_milling_case(const io::Case& c, const SimulateRequest& r) {
  MillingSimulationJobReport report;
  report.setup = milling_setup(c, r);
  const MillingSetup& s = report.setup;
  rethrow_as(s.where, "simulate", [&] { report.result = simulate_milling(s.cut, s.options); });
  report.setup.options.progress = nullptr;  // the report outlives the caller's progress
  report.s1_law = c.force_law.has_value();
  if (std::string w = spindle_warning(c, s.rpm, r.rpm ? r.names.rpm : "simulate.rpm"); !w.empty())
    report.warnings.push_back(std::move(w));
  // The stability prediction at this speed, for the mechanistic law with regeneration.
  if (!report.s1_law && s.cut.regenerative && !s.cut.process.structure_modes().modes.empty()) {
    // The simulated process itself (its [[frf]] tables read and fitted once, by the setup).
    const MillingProcess& m = s.cut.process;
    if (const auto problems = m.validate_for_stability(); !problems.empty())
      throw InvalidInput(problems, c.source);
    MillingStabilityOptions so;
    so.depth_max_m = c.lobes.depth_max_m;
    so.rel_tol = 1e-3;
    report.predicted = milling_critical_depth(m, s.rpm, so);
    // Beyond the case's limit, carried on to 1.25× the depth on the same depth grid (as
    // `check`), so the prediction is that of the lobes.
    const double reach = 1.25 * s.cut.width_m;
    if (!report.predicted->boundary.found && reach > so.depth_max_m &&
        reach <= kMaxSearchExtension * so.depth_max_m) {
      report.predicted = milling_critical_depth(m, s.rpm, extend_search(so, reach));
    }
  }
  if (!report.result.growth_settled && report.result.status == SimulationStatus::kCompleted)
    report.warnings.push_back(
        "the perturbation's growth has not settled over " + human(s.options.revolutions) +
        " revolutions (the decisive root is not yet told from its neighbours): the verdict is "
        "uncertain; run more revolutions ([simulate] revolutions)");
  return report;
}

const std::vector<std::string>& milling_metric_names() {
  static const std::vector<std::string> names{"force_pulsation",
                                              "mean_force_n",
                                              "peak_force_n",
                                              "min_force_n",
                                              "mean_teeth_in_cut",
                                              "vibration_pp_x_um",
                                              "vibration_pp_y_um",
                                              "chatter_indicator",
                                              "contact_loss",
                                              "surface_location_error_um",
                                              "cutting_force_pulsation",
                                              "mean_cutting_force_n"};
  return names;
}

std::vector<double> milling_metrics(const MillingSimulationResult& r) {
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
                                     : std::numeric_limits<double>::quiet_NaN(),
          r.cutting_force_pulsation,
          r.mean_cutting_force_n};
}

std::size_t metric_index(const std::vector<std::string>& names, const std::string& metric,
                         const std::string& fallback, const std::string& flag,
                         const std::string& where) {
  const std::string name = metric.empty() ? fallback : metric;
  const auto chosen = std::find(names.begin(), names.end(), name);
  if (chosen == names.end()) {
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
    throw InvalidInput({flag + " = \"" + name + "\": must be one of " + list}, where);
  }
  return static_cast<std::size_t>(chosen - names.begin());
}

Sweep parse_sweep(const std::string& spec, const std::string& flag, const std::string& where) {
  const auto fail = [&](const std::string& why) -> Sweep {
    throw InvalidInput({flag + " = \"" + spec + "\": " + why}, where);
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
  if (count > static_cast<double>(kMaxSweepValues))
    return fail(fmt::format("{:.0f} values; at most {}", count, kMaxSweepValues));
  for (int i = 0; i < static_cast<int>(count); ++i) {
    const double x = from + step * i;
    // Clean decimal values (0.1·3 = 0.30000000000000004 → 0.3).
    sweep.values.push_back(std::stod(fmt::format("{:.12g}", x)));
  }
  return sweep;
}

void require_values(const Sweep& sweep) {
  if (sweep.values.empty())
    throw InvalidInput({"values: none given (a sweep of " + sweep.key + " needs at least one)"},
                       "request");
  if (sweep.values.size() > kMaxSweepValues)
    throw InvalidInput({"values: " + std::to_string(sweep.values.size()) + " given, at most " +
                        std::to_string(kMaxSweepValues)},
                       "request");
}

MillingSweepJobReport sweep_milling_case(const io::Case& c, const Sweep& sweep,
                                         const SimulateRequest& r, int threads,
                                         const std::function<void(int, int)>& progress) {
  require_values(sweep);
  std::vector<MillingSetup> setups;
  for (double value : sweep.values) {
    const io::Case varied = io::with_value(c, sweep.key, value);
    if (varied.process != io::Process::kMilling)
      throw InvalidInput({sweep.key + ": the varied case is not a milling case"}, varied.source);
    setups.push_back(milling_setup(varied, r));
  }
  MillingSweepJobReport report{sweep, std::vector<MillingSimulationResult>(setups.size())};
  parallel_for(
      static_cast<int>(setups.size()), threads,
      [&](int i) {
        const auto k = static_cast<std::size_t>(i);
        rethrow_as(setups[k].where, "simulate",
                   [&] { report.results[k] = simulate_milling(setups[k].cut, setups[k].options); });
      },
      progress);
  return report;
}

}  // namespace cutdyn::app
