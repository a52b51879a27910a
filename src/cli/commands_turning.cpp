// `cutdyn lobes`, `check`, `simulate` and `force` for turning, conventional and
// vibration-assisted.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/forces/duty_cycle.hpp"
#include "cutdyn/io/output.hpp"
#include "cutdyn/io/plot.hpp"
#include "cutdyn/simulate/turning_simulation.hpp"
#include "cutdyn/stability/lobes.hpp"

namespace cutdyn::cli {
namespace {

using nlohmann::json;
using units::m_to_mm;
using units::mm_to_m;

constexpr std::string_view kDefaultTurningCase = "turning-ultrasonic";
constexpr std::string_view kDefaultForceCase = "ultrasonic-force";

// The method: --method, else the case's [lobes].method (library rule: turning_method).
TurningMethod resolve_method(const io::Case& c, const TurningModel& m, const std::string& flag) {
  return turning_method(asked_method(c, flag), m.vibration.has_value());
}

TurningStabilityOptions stability_options(const io::Case& c, TurningMethod method) {
  TurningStabilityOptions o;
  o.method = method;
  o.depth_max_m = c.lobes.depth_max_m;
  o.harmonics = c.lobes.harmonics;
  o.fd.steps_per_period = c.lobes.steps_per_period;
  return o;
}

std::string describe_model(const io::Case& c, const TurningModel& m) {
  std::string s =
      fmt::format("turning, {} mode{} in x, Kt = {} N/mm²", m.modal.modes.size(),
                  m.modal.modes.size() == 1 ? "" : "s", human(units::pa_to_n_per_mm2(m.kt_pa)));
  if (c.material && !c.cutting.kt_pa)
    s += fmt::format(" (predicted for {} by Oxley's theory at {} m/min)", c.material->name,
                     human(units::m_per_s_to_m_per_min(*c.cutting.speed_m_per_s)));
  if (m.vibration) {
    s += fmt::format("; vibration {} Hz", human(m.vibration->frequency_hz));
    if (m.vibration->duty_cycle) {
      s += fmt::format(", duty cycle {} (fixed)", human(*m.vibration->duty_cycle));
    } else {
      s += fmt::format(", {} µm on a {} mm workpiece (duty cycle from the speed)",
                       human(units::m_to_um(m.vibration->amplitude_m)),
                       human(m_to_mm(*m.vibration->workpiece_diameter_m)));
    }
  }
  return s;
}

}  // namespace

int run_lobes(const LobesArgs& args, std::ostream& out, std::ostream& err) {
  check_outputs(args.outputs);
  if (args.target_depth_mm) {
    Validator v;
    v.require_positive("--target-depth-mm", *args.target_depth_mm, "mm");
    v.throw_if_any("command line");
  }
  const io::Case c = load_case(args.case_path, kDefaultTurningCase, err);
  if (c.process == io::Process::kMilling) return run_lobes_milling(args, c, out, err);
  const TurningModel model = turning_model(c, "lobes");
  const TurningMethod method = resolve_method(c, model, args.method);
  const TurningStabilityOptions options = stability_options(c, method);
  if (const auto problems = options.validate(); !problems.empty())
    throw InvalidInput(problems, c.source);
  const LobesOptions grid = lobes_grid(c, args.threads);

  rethrow_as(c.source, "lobes.rpm_min", [&] { check_speed_domain(model, grid.rpm_min); });
  const bool assisted = model.vibration.has_value();
  const auto at_speed = [&](double rpm) {
    const TurningBoundary b = turning_critical_depth(model, rpm, options);
    return LobePoint{rpm, b.boundary, b.duty_cycle, b.lobe};
  };
  LobesReport report = trace_lobes(at_speed, grid, progress_reporter(err, "lobes"));
  // With vibration, the conventional lobes beside them (exact closed form, cheap), traced
  // with their own refinement; each curve is then completed at the other's speeds, so both
  // hold their cusps and share one row per speed.
  std::vector<CriticalDepth> reference;
  if (assisted) {
    TurningStabilityOptions exact = options;
    exact.method = TurningMethod::kClosedForm;
    const TurningModel conventional = model.conventional();
    const auto conventional_at = [&](double rpm) {
      return LobePoint{rpm, turning_critical_depth(conventional, rpm, exact).boundary, 1.0, 0};
    };
    LobesReport conv = trace_lobes(conventional_at, grid);
    complete_lobes(at_speed, conv.points, report.points, grid.threads);
    complete_lobes(conventional_at, report.points, conv.points, grid.threads);
    for (const LobePoint& p : conv.points) reference.push_back(p.boundary);
  }

  LobesView view;
  view.description = describe_model(c, model);
  view.method = to_string(method);
  view.depth_max_m = options.depth_max_m;
  view.title = assisted ? "Stability lobes: vibration-assisted and conventional turning"
                        : "Stability lobes: turning";
  view.label = assisted ? fmt::format("vibration-assisted ({})", to_string(method))
                        : fmt::format("conventional ({})", to_string(method));
  if (assisted) {
    view.reference = &reference;
    view.reference_label = "conventional (closed form)";
    view.duty_cycle = true;
  }
  if (args.target_depth_mm) view.target_depth_m = mm_to_m(*args.target_depth_mm);
  report_lobes(c, report, view, args.outputs, out, err);
  return 0;
}

int run_check(const CheckArgs& args, std::ostream& out, std::ostream& err) {
  Validator v;
  check_output_folder(v, "--json", args.json);
  v.require_positive("--rpm", args.rpm, "rpm");
  v.require_positive("--depth-mm", args.depth_mm, "mm");
  v.throw_if_any("command line");
  const io::Case c = load_case(args.case_path, kDefaultTurningCase, err);
  if (c.process == io::Process::kMilling) return run_check_milling(args, c, out);
  const TurningModel model = turning_model(c, "check");
  rethrow_as("command line", "--rpm", [&] { check_speed_domain(model, args.rpm); });
  const TurningMethod method = resolve_method(c, model, args.method);
  TurningStabilityOptions options = stability_options(c, method);
  // Search far enough above the requested depth to say how much margin there is.
  options.depth_max_m = std::max(options.depth_max_m, 4.0 * mm_to_m(args.depth_mm));
  if (const auto problems = options.validate(); !problems.empty())
    throw InvalidInput(problems, c.source);
  const TurningBoundary b = turning_critical_depth(model, args.rpm, options);
  CheckView view;
  view.description = describe_model(c, model);
  view.method = to_string(method);
  view.lobe = b.lobe;
  if (model.vibration) {
    TurningStabilityOptions exact = options;
    exact.method = TurningMethod::kClosedForm;
    const TurningBoundary cb = turning_critical_depth(model.conventional(), args.rpm, exact);
    const bool conv_stable = !cb.boundary.found || mm_to_m(args.depth_mm) < cb.boundary.depth_m;
    view.notes.push_back("duty cycle " + human(b.duty_cycle));
    view.notes.push_back("conventional turning: critical depth " + depth_text(cb.boundary) + ", " +
                         (conv_stable ? "stable" : "unstable") + " at this depth");
    view.extra["conventional"] = {{"critical_depth_mm", m_to_mm(cb.boundary.depth_m)},
                                  {"chatter_hz", cb.boundary.chatter_hz},
                                  {"stable", conv_stable}};
  }
  view.extra["duty_cycle"] = b.duty_cycle;
  report_check(c, args, b.boundary, view, out);
  return 0;
}

int run_simulate(const SimulateArgs& args, std::ostream& out, std::ostream& err) {
  check_outputs(args.outputs);
  const io::Case c = load_case(args.case_path, kDefaultTurningCase, err);
  if (c.process == io::Process::kMilling) return run_simulate_milling(args, c, out, err);
  if (!args.sweep.empty() || !args.metric.empty())
    throw InvalidInput({"--sweep, --metric: sweeps take milling cases in this version"},
                       "command line");
  const TurningModel model = turning_model(c, "simulate");
  Validator v;
  TurningSimulationOptions o;
  const auto rpm = args.rpm ? args.rpm : c.simulate.rpm;
  const auto depth_m = args.depth_mm ? std::optional(mm_to_m(*args.depth_mm)) : c.simulate.depth_m;
  if (!rpm) v.add("simulate.rpm: missing (give it in the case or as --rpm)");
  if (!depth_m) v.add("simulate.depth_mm: missing (give it in the case or as --depth-mm)");
  if (!c.cutting.uncut_chip_thickness_m)
    v.add(
        "cutting.uncut_chip_thickness_mm: missing (required by `cutdyn simulate`: the feed per "
        "revolution)");
  v.throw_if_any(c.source);
  o.rpm = *rpm;
  o.depth_m = *depth_m;
  o.feed_m = *c.cutting.uncut_chip_thickness_m;
  o.duration_s = args.duration_s.value_or(c.simulate.duration_s);
  o.initial_displacement_m = c.simulate.initial_displacement_m;
  if (const auto problems = o.validate(); !problems.empty()) {
    std::vector<std::string> named;
    for (const auto& p : problems) named.push_back("simulate: " + p);
    throw InvalidInput(named,
                       args.rpm || args.depth_mm || args.duration_s ? "command line" : c.source);
  }

  const bool from_flags = args.rpm || args.depth_mm || args.duration_s;
  const std::string where = from_flags ? "command line" : c.source;
  rethrow_as(where, "simulate", [&] { check_speed_domain(model, o.rpm); });
  struct Run {
    std::string name;
    TurningModel model;
    TurningSimulationResult result;
    TurningBoundary predicted;
  };
  std::vector<Run> runs;
  runs.push_back({model.vibration ? "vibration-assisted" : "conventional", model, {}, {}});
  if (model.vibration) runs.push_back({"conventional", model.conventional(), {}, {}});
  TurningStabilityOptions so = stability_options(c, TurningMethod::kFullDiscretization);
  so.depth_max_m = std::max(so.depth_max_m, 4.0 * o.depth_m);
  for (Run& r : runs) {
    rethrow_as(where, "simulate", [&] { r.result = simulate_turning(r.model, o); });
    so.method = r.model.vibration ? TurningMethod::kFullDiscretization : TurningMethod::kClosedForm;
    r.predicted = turning_critical_depth(r.model, o.rpm, so);
  }

  out << "cutdyn simulate: " << c.source << " at " << human(o.rpm) << " rpm, depth "
      << human(m_to_mm(o.depth_m)) << " mm, feed " << human(m_to_mm(o.feed_m)) << " mm/rev, "
      << human(o.duration_s) << " s\n";
  out << "  " << describe_model(c, model) << "\n";
  for (const Run& r : runs) {
    const auto& s = r.result;
    out << fmt::format(
        "  {:<19} {:<9} growth rate {} 1/s; amplitude {} → {} µm over {} revolutions{}\n",
        r.name + ":", s.chatter ? "GROWS" : "decays",
        // (not fitted: fewer than two whole revolutions before a runaway or loss of contact)
        s.revolution_amplitude_m.size() < 2 ? std::string("–")
                                            : fmt::format("{:+.3g}", s.growth_rate_per_s),
        human(units::m_to_um(s.revolution_amplitude_m.empty() ? 0.0
                                                              : s.revolution_amplitude_m.front()),
              3),
        human(units::m_to_um(s.revolution_amplitude_m.empty() ? 0.0
                                                              : s.revolution_amplitude_m.back()),
              3),
        s.revolution_amplitude_m.size(),
        s.lost_contact ? fmt::format("; tool left the cut at {:.3f} s", s.contact_loss_time_s)
                       : "");
    if (s.status == SimulationStatus::kRunaway)
      out << "  " << std::string(20, ' ') << "CHATTER" << s.verdict().substr(7) << "\n";
    if (!s.growth_settled)
      err << "cutdyn: warning: " << c.source << ": " << r.name
          << ": the free response's growth has not settled over " << human(o.duration_s)
          << " s: the verdict is uncertain; simulate longer ([simulate] duration_s)\n";
    out << "  " << std::string(20, ' ') << "predicted critical depth "
        << depth_text(r.predicted.boundary) << " → depth is "
        << human(100.0 * o.depth_m / r.predicted.boundary.depth_m, 3) << " % of it\n";
  }

  io::OutputTransaction outputs;
  if (!args.outputs.csv.empty()) {
    io::CsvWriter csv(outputs.open(args.outputs.csv),
                      {"process", "time_s", "displacement_um", "force_n", "chip_thickness_um"});
    for (const Run& r : runs)
      for (std::size_t i = 0; i < r.result.time_s.size(); ++i)
        csv.row({r.name, r.result.time_s[i], units::m_to_um(r.result.displacement_m[i]),
                 r.result.force_n[i], units::m_to_um(r.result.chip_thickness_m[i])});
  }
  if (!args.outputs.json.empty()) {
    json results = json::array();
    for (const Run& r : runs) {
      const auto& s = r.result;
      // (none when a runaway stopped the run within its first revolution)
      const auto& a = s.revolution_amplitude_m;
      const json first = a.empty() ? json() : json(units::m_to_um(a.front()));
      const json last = a.empty() ? json() : json(units::m_to_um(a.back()));
      results.push_back({{"process", r.name},
                         {"chatter", s.chatter},
                         {"growth_rate_per_s", s.growth_rate_per_s},
                         {"growth_settled", s.growth_settled},
                         {"growth_components", s.growth_components},
                         {"lost_contact", s.lost_contact},
                         {"contact_loss_time_s", s.contact_loss_time_s},
                         {"duty_cycle", s.duty_cycle},
                         {"static_deflection_um", units::m_to_um(s.static_deflection_m)},
                         {"verdict", s.verdict()},
                         {"status", to_string(s.status)},
                         {"stop_time_s", s.stop_time_s},
                         {"first_revolution_amplitude_um", first},
                         {"last_revolution_amplitude_um", last},
                         {"predicted_critical_depth_mm", m_to_mm(r.predicted.boundary.depth_m)},
                         {"step_s", s.step_s},
                         {"steps", s.steps}});
    }
    json doc{{"command", "simulate"},
             {"case", io::to_json(c)},
             {"source", c.source},
             {"spindle_rpm", o.rpm},
             {"depth_mm", m_to_mm(o.depth_m)},
             {"feed_mm", m_to_mm(o.feed_m)},
             {"duration_s", o.duration_s},
             {"results", std::move(results)}};
    io::write_json(outputs.open(args.outputs.json), doc);
  }
  if (!args.outputs.plot.empty()) {
    io::PlotSpec spec;
    spec.title = fmt::format("Tool vibration at {} rpm, depth {} mm", human(o.rpm),
                             human(m_to_mm(o.depth_m)));
    spec.x_label = "time (s)";
    spec.y_label = "tool displacement in the feed direction (µm)";
    for (auto it = runs.rbegin(); it != runs.rend(); ++it) {  // the case's own process on top
      const Run& r = *it;
      io::PlotSeries s{r.name, r.result.time_s, {}, "lines"};
      for (double y : r.result.displacement_m) s.y.push_back(units::m_to_um(y));
      spec.series.push_back(std::move(s));
    }
    io::write_plot(spec, args.outputs.plot, outputs);
  }
  commit_outputs(outputs, args.outputs, out);
  return 0;
}

int run_force(const ForceArgs& args, std::ostream& out, std::ostream& err) {
  check_outputs({"", args.json, args.plot});
  const io::Case c = load_case(args.case_path, kDefaultForceCase, err);
  require_turning(c, "force");
  Validator v;
  const auto need = [&](const std::optional<double>& x, const char* key) {
    if (!x) v.add(std::string("cutting.") + key + ": missing (required by `cutdyn force`)");
  };
  if (!c.material) {
    need(c.cutting.kc_pa, "kc_n_per_mm2 (or give a [material] to predict it)");
    need(c.cutting.kt_pa, "kt_n_per_mm2 (or give a [material] to predict it)");
  }
  need(c.cutting.uncut_chip_thickness_m, "uncut_chip_thickness_mm");
  need(c.cutting.width_m, "width_mm");
  if (c.vibration && !c.vibration->duty_cycle && !c.cutting.speed_m_per_s)
    v.add(
        "cutting.speed_m_per_min: missing (required by `cutdyn force` to compute the duty cycle; "
        "or give vibration.duty_cycle)");
  v.throw_if_any(c.source);

  std::optional<OxleyPrediction> oxley;
  if (c.material) oxley = predict_with_oxley(c, "force", true);
  const double kc = oxley ? oxley->result.kc_pa : *c.cutting.kc_pa;
  const double kt = oxley ? oxley->result.kt_pa : *c.cutting.kt_pa;

  DutyCycle dc;  // conventional: r = 1
  if (c.vibration) {
    dc = c.vibration->duty_cycle
             ? fixed_duty_cycle(*c.vibration->duty_cycle, c.vibration->frequency_hz)
             : duty_cycle(*c.cutting.speed_m_per_s, c.vibration->frequency_hz,
                          *c.vibration->amplitude_m);
  }
  const double h = *c.cutting.uncut_chip_thickness_m, w = *c.cutting.width_m;
  const PulsedForces f = pulsed_forces(kc, kt, h, w, dc.ratio);

  out << "cutdyn force: " << c.source << "\n";
  json oxley_json;
  if (oxley) {
    const WorkMaterial& m = *c.material;
    const OxleyState& s = oxley->result.state;
    out << "  " << oxley_summary(c, *oxley) << "\n";
    out << "    material " << m.name << ": " << m.reference << "\n";
    out << "    shear angle " << human(units::rad_to_deg(s.phi_rad)) << "°, chip thickness "
        << human(m_to_mm(s.chip_thickness_m)) << " mm (chip ratio "
        << human(oxley->result.chip_ratio) << "), contact length "
        << human(m_to_mm(s.contact_length_m)) << " mm\n";
    out << "    strain-rate constant C0 = " << human(s.c0)
        << ", secondary zone δ = " << human(s.delta) << " of the chip thickness, friction angle "
        << human(units::rad_to_deg(s.friction_angle_rad)) << "°\n";
    out << "    temperatures: shear plane " << human(s.temperature_ab_c, 3)
        << " °C, tool–chip interface " << human(s.temperature_interface_c, 3) << " °C\n";
    out << "    flow stress in shear: shear plane " << human(s.shear_flow_stress_pa / 1e6)
        << " MPa at strain rate " << human(s.strain_rate_ab_per_s, 3) << " 1/s\n";
    for (const std::string& warning : oxley->result.warnings)
      out << "    warning: " << warning << "\n";
    oxley_json = {{"material", m.name},
                  {"shear_angle_deg", units::rad_to_deg(s.phi_rad)},
                  {"chip_thickness_mm", m_to_mm(s.chip_thickness_m)},
                  {"chip_ratio", oxley->result.chip_ratio},
                  {"strain_rate_constant", s.c0},
                  {"secondary_zone_ratio", s.delta},
                  {"contact_length_mm", m_to_mm(s.contact_length_m)},
                  {"friction_angle_deg", units::rad_to_deg(s.friction_angle_rad)},
                  {"shear_plane_temperature_c", s.temperature_ab_c},
                  {"interface_temperature_c", s.temperature_interface_c},
                  {"shear_plane_strain_rate_per_s", s.strain_rate_ab_per_s},
                  {"shear_plane_flow_stress_mpa", s.shear_flow_stress_pa / 1e6},
                  {"interface_strain_rate_per_s", s.strain_rate_interface_per_s},
                  {"warnings", oxley->result.warnings}};
  }
  out << "  Kc = " << human(units::pa_to_n_per_mm2(kc))
      << " N/mm², Kt = " << human(units::pa_to_n_per_mm2(kt)) << " N/mm²; h = " << human(m_to_mm(h))
      << " mm, w = " << human(m_to_mm(w)) << " mm";
  if (c.cutting.speed_m_per_s)
    out << ", v = " << human(units::m_per_s_to_m_per_min(*c.cutting.speed_m_per_s)) << " m/min";
  out << "\n";
  json vib;
  if (c.vibration) {
    const double T = dc.period_s;
    out << "  vibration " << human(c.vibration->frequency_hz) << " Hz";
    if (c.vibration->amplitude_m) {
      out << ", " << human(units::m_to_um(*c.vibration->amplitude_m))
          << " µm: critical speed 2πfA = "
          << human(units::m_per_s_to_m_per_min(dc.critical_speed_m_per_s)) << " m/min";
    }
    out << "\n  duty cycle r = " << human(dc.ratio) << "; period " << human(T * 1e6)
        << " µs: " << human(dc.ratio * T * 1e6) << " µs in contact, "
        << human((1.0 - dc.ratio) * T * 1e6) << " µs separated\n";
    if (dc.separates && !c.vibration->duty_cycle) {
      out << "  separation starts at phase " << human(units::rad_to_deg(dc.separation_phase_rad))
          << "°, contact resumes at " << human(units::rad_to_deg(dc.contact_phase_rad))
          << "° (ρ = v/2πfA = " << human(dc.rho) << ")\n";
    } else if (!dc.separates) {
      out << "  no separation: the cutting speed is at or above 2πfA\n";
    }
    vib = {{"duty_cycle", dc.ratio},
           {"period_s", T},
           {"contact_time_s", dc.ratio * T},
           {"separation_time_s", (1.0 - dc.ratio) * T},
           {"separates", dc.separates}};
    if (c.vibration->amplitude_m && !c.vibration->duty_cycle) {
      vib["critical_speed_m_per_min"] = units::m_per_s_to_m_per_min(dc.critical_speed_m_per_s);
      vib["rho"] = dc.rho;
      if (dc.separates) {
        vib["separation_phase_deg"] = units::rad_to_deg(dc.separation_phase_rad);
        vib["contact_phase_deg"] = units::rad_to_deg(dc.contact_phase_rad);
      }
    }
  }
  out << "  cutting force " << human(f.peak_cutting_n) << " N while cutting, mean "
      << human(f.mean_cutting_n) << " N\n";
  out << "  thrust force  " << human(f.peak_thrust_n) << " N while cutting, mean "
      << human(f.mean_thrust_n) << " N\n";

  io::OutputTransaction outputs;
  if (!args.json.empty()) {
    json doc{{"command", "force"},
             {"case", io::to_json(c)},
             {"source", c.source},
             {"kc_n_per_mm2", units::pa_to_n_per_mm2(kc)},
             {"kt_n_per_mm2", units::pa_to_n_per_mm2(kt)},
             {"coefficients", oxley ? "oxley" : "given"},
             {"cutting_force_n", f.peak_cutting_n},
             {"thrust_force_n", f.peak_thrust_n},
             {"mean_cutting_force_n", f.mean_cutting_n},
             {"mean_thrust_force_n", f.mean_thrust_n},
             {"duty_cycle", dc.ratio}};
    if (!vib.is_null()) doc["vibration"] = vib;
    if (oxley) {
      doc["shear_angle_deg"] = oxley_json["shear_angle_deg"];
      doc["chip_thickness_mm"] = oxley_json["chip_thickness_mm"];
      doc["oxley"] = oxley_json;
    }
    io::write_json(outputs.open(args.json), doc);
  }
  if (!args.plot.empty() && oxley && !c.vibration) {
    // The prediction around the case: forces and shear angle against the uncut chip
    // thickness, from h/4 to 2h (points outside the theory's validity are left out).
    io::PlotSpec spec;
    spec.title =
        fmt::format("Oxley + Johnson–Cook: {} at {} m/min, rake {}°, w = {} mm", c.material->name,
                    human(units::m_per_s_to_m_per_min(oxley->cut.speed_m_per_s)),
                    human(units::rad_to_deg(oxley->cut.rake_rad)), human(m_to_mm(w)));
    spec.x_label = "uncut chip thickness (mm)";
    spec.y_label = "force (N)";
    spec.y2_label = "shear angle (°)";
    spec.y_min = 0.0;
    io::PlotSeries fc{"cutting force", {}, {}, "linespoints"},
        ft{"thrust force", {}, {}, "linespoints"}, phi{"shear angle", {}, {}, "linespoints", true},
        here{"this cut", {m_to_mm(h), m_to_mm(h)}, {f.peak_cutting_n, f.peak_thrust_n}, "points"};
    for (int i = 0; i <= 14; ++i) {
      OrthogonalCut cut = oxley->cut;
      cut.uncut_chip_thickness_m = h * (0.25 + 1.75 * i / 14.0);
      try {
        const OxleyResult r = oxley_orthogonal(*c.material, cut, c.oxley);
        for (io::PlotSeries* series : {&fc, &ft, &phi})
          series->x.push_back(m_to_mm(cut.uncut_chip_thickness_m));
        fc.y.push_back(r.state.cutting_force_n);
        ft.y.push_back(r.state.thrust_force_n);
        phi.y.push_back(units::rad_to_deg(r.state.phi_rad));
      } catch (const InvalidInput&) {
        // outside the theory: no point
      }
    }
    spec.series = {fc, ft, here, phi};
    io::write_plot(spec, args.plot, outputs);
  } else if (!args.plot.empty()) {
    // Three vibration periods of the pulsed forces g(t)·K·h·w (or a flat line).
    const ContactWindow g = dc.window();
    const double T = c.vibration ? dc.period_s : 1e-3;
    io::PlotSpec spec;
    spec.title =
        c.vibration ? "Pulsed cutting forces of vibration-assisted turning" : "Cutting forces";
    spec.x_label = "time (µs)";
    spec.y_label = "force (N)";
    spec.y_min = 0.0;
    spec.y_max = 1.15 * std::max(f.peak_cutting_n, f.peak_thrust_n);
    io::PlotSeries fc{"cutting force", {}, {}, "lines"}, ft{"thrust force", {}, {}, "lines"};
    const int n = 1500;
    for (int i = 0; i <= n; ++i) {
      const double t = 3.0 * T * i / n;
      const double on = g.in_contact(t) ? 1.0 : 0.0;
      fc.x.push_back(t * 1e6);
      fc.y.push_back(on * f.peak_cutting_n);
      ft.x.push_back(t * 1e6);
      ft.y.push_back(on * f.peak_thrust_n);
    }
    spec.series = {fc, ft};
    io::write_plot(spec, args.plot, outputs);
  }
  outputs.commit();
  for (const std::string* file : {&args.json, &args.plot})
    if (!file->empty()) out << "  wrote " << *file << "\n";
  return 0;
}

}  // namespace cutdyn::cli
