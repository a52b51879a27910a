// `cutdyn lobes`, `check`, `simulate` and `force` for turning, conventional and
// vibration-assisted.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/milling_setup.hpp"
#include "cutdyn/app/force.hpp"
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

}  // namespace

int run_lobes(const LobesArgs& args, std::ostream& out, std::ostream& err) {
  check_outputs(args.outputs);
  const io::Case c = load_case(args.case_path, kDefaultTurningCase, err);
  app::LobesRequest request;  // the job checks the request (a positive target depth, …)
  request.method = args.method;
  request.threads = args.threads;
  if (args.target_depth_mm) request.target_depth_m = mm_to_m(*args.target_depth_mm);
  request.progress = progress_reporter(err, "lobes");
  request.names = flag_names();
  request.names.depth = "--target-depth-mm";
  report_lobes(c, app::run_lobes(c, request), args.outputs, out, err);
  return 0;
}

int run_check(const CheckArgs& args, std::ostream& out, std::ostream& err) {
  Validator v;
  check_output_folder(v, "--json", args.json);
  v.throw_if_any("command line");
  const io::Case c = load_case(args.case_path, kDefaultTurningCase, err);
  app::CheckRequest request;
  request.rpm = args.rpm;
  request.depth_m = mm_to_m(args.depth_mm);
  request.method = args.method;
  request.names = flag_names();
  report_check(c, args, app::run_check(c, request), out);
  return 0;
}

namespace {

void print_turning(const io::Case& c, const app::TurningSimulationJobReport& job, std::ostream& out,
                   std::ostream& err) {
  const TurningSimulationOptions& o = job.options;
  const auto& runs = job.runs;
  using Run = app::TurningSimulationRun;
  out << "cutdyn simulate: " << c.source << " at " << human(o.rpm) << " rpm, depth "
      << human(m_to_mm(o.depth_m)) << " mm, feed " << human(m_to_mm(o.feed_m)) << " mm/rev, "
      << human(o.duration_s) << " s\n";
  out << "  " << job.description << "\n";
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
    out << "  " << std::string(20, ' ') << "predicted critical depth "
        << depth_text(r.predicted.boundary) << " → depth is "
        << human(100.0 * o.depth_m / r.predicted.boundary.depth_m, 3) << " % of it\n";
  }

  for (const std::string& w : job.warnings)
    err << "cutdyn: warning: " << c.source << ": " << w << "\n";
}

io::PlotSpec turning_plot(const app::TurningSimulationJobReport& job) {
  const TurningSimulationOptions& o = job.options;
  const auto& runs = job.runs;
  using Run = app::TurningSimulationRun;
  io::PlotSpec spec;
  spec.title =
      fmt::format("Tool vibration at {} rpm, depth {} mm", human(o.rpm), human(m_to_mm(o.depth_m)));
  spec.x_label = "time (s)";
  spec.y_label = "tool displacement in the feed direction (µm)";
  for (auto it = runs.rbegin(); it != runs.rend(); ++it) {  // the case's own process on top
    const Run& r = *it;
    io::PlotSeries s{r.name, r.result.time_s, {}, "lines"};
    for (double y : r.result.displacement_m) s.y.push_back(units::m_to_um(y));
    spec.series.push_back(io::envelope(s, 2000));  // the whole run, thinned to its envelope
  }
  return spec;
}

}  // namespace

int run_simulate(const SimulateArgs& args, std::ostream& out, std::ostream& err) {
  check_outputs(args.outputs);
  const io::Case c = load_case(args.case_path, kDefaultTurningCase, err);
  if (c.process == io::Process::kMilling) return run_simulate_milling(args, c, out, err);
  if (!args.sweep.empty() || !args.metric.empty())
    throw InvalidInput({"--sweep, --metric: sweeps take milling cases in this version"},
                       "command line");
  const app::TurningSimulationJobReport job = app::simulate_turning_case(c, simulate_request(args));
  const auto& runs = job.runs;
  using Run = app::TurningSimulationRun;

  print_turning(c, job, out, err);
  io::OutputTransaction outputs;
  if (!args.outputs.csv.empty()) {
    io::CsvWriter csv(outputs.open(args.outputs.csv),
                      {"process", "time_s", "displacement_um", "force_n", "chip_thickness_um"});
    for (const Run& r : runs)
      for (std::size_t i = 0; i < r.result.time_s.size(); ++i)
        csv.row({r.name, r.result.time_s[i], units::m_to_um(r.result.displacement_m[i]),
                 r.result.force_n[i], units::m_to_um(r.result.chip_thickness_m[i])});
  }
  if (!args.outputs.json.empty())
    io::write_json(outputs.open(args.outputs.json), app::to_json(c, job));
  if (!args.outputs.plot.empty()) io::write_plot(turning_plot(job), args.outputs.plot, outputs);
  commit_outputs(outputs, args.outputs, out);
  return 0;
}

namespace {

// The Oxley lines of the force report (text) and their JSON.
void print_oxley(const io::Case& c, const app::OxleyPrediction& p, std::ostream& out) {
  const WorkMaterial& m = *c.material;
  const OxleyState& s = p.result.state;
  out << "  " << oxley_summary(c, p) << "\n";
  out << "    material " << m.name << ": " << m.reference << "\n";
  out << "    shear angle " << human(units::rad_to_deg(s.phi_rad)) << "°, chip thickness "
      << human(m_to_mm(s.chip_thickness_m)) << " mm (chip ratio " << human(p.result.chip_ratio)
      << "), contact length " << human(m_to_mm(s.contact_length_m)) << " mm\n";
  out << "    strain-rate constant C0 = " << human(s.c0)
      << ", secondary zone δ = " << human(s.delta) << " of the chip thickness, friction angle "
      << human(units::rad_to_deg(s.friction_angle_rad)) << "°\n";
  out << "    temperatures: shear plane " << human(s.temperature_ab_c, 3)
      << " °C, tool–chip interface " << human(s.temperature_interface_c, 3) << " °C\n";
  out << "    flow stress in shear: shear plane " << human(s.shear_flow_stress_pa / 1e6)
      << " MPa at strain rate " << human(s.strain_rate_ab_per_s, 3) << " 1/s\n";
  for (const std::string& warning : p.result.warnings) out << "    warning: " << warning << "\n";
}

// The vibration lines of the force report (text) and their JSON.
void print_vibration(const VibrationAssist& v, const DutyCycle& dc, std::ostream& out) {
  const double T = dc.period_s;
  out << "  vibration " << human(v.frequency_hz) << " Hz";
  if (v.amplitude_m) {
    out << ", " << human(units::m_to_um(*v.amplitude_m)) << " µm: critical speed 2πfA = "
        << human(units::m_per_s_to_m_per_min(dc.critical_speed_m_per_s)) << " m/min";
  }
  out << "\n  duty cycle r = " << human(dc.ratio) << "; period " << human(T * 1e6)
      << " µs: " << human(dc.ratio * T * 1e6) << " µs in contact, "
      << human((1.0 - dc.ratio) * T * 1e6) << " µs separated\n";
  if (dc.separates && !v.duty_cycle) {
    out << "  separation starts at phase " << human(units::rad_to_deg(dc.separation_phase_rad))
        << "°, contact resumes at " << human(units::rad_to_deg(dc.contact_phase_rad))
        << "° (ρ = v/2πfA = " << human(dc.rho) << ")\n";
  } else if (!dc.separates) {
    out << "  no separation: the cutting speed is at or above 2πfA\n";
  }
}

// Oxley's prediction around the cut: forces and shear angle against the uncut chip thickness.
io::PlotSpec oxley_plot(const io::Case& c, const app::ForceJobReport& r) {
  io::PlotSpec spec;
  spec.title =
      fmt::format("Oxley + Johnson–Cook: {} at {} m/min, rake {}°, w = {} mm", c.material->name,
                  human(units::m_per_s_to_m_per_min(r.oxley->cut.speed_m_per_s)),
                  human(units::rad_to_deg(r.oxley->cut.rake_rad)), human(m_to_mm(r.width_m)));
  spec.x_label = "uncut chip thickness (mm)";
  spec.y_label = "force (N)";
  spec.y2_label = "shear angle (°)";
  spec.y_min = 0.0;
  const double h = m_to_mm(r.uncut_chip_thickness_m);
  io::PlotSeries fc{"cutting force", {}, {}, "linespoints"},
      ft{"thrust force", {}, {}, "linespoints"},
      phi{"shear angle (right axis)", {}, {}, "linespoints", true},
      here{"this cut", {h, h}, {r.forces.peak_cutting_n, r.forces.peak_thrust_n}, "marker"};
  here.color = "#000000";  // the cut itself, black on both force curves
  for (const app::ChipThicknessPoint& p : r.around) {
    for (io::PlotSeries* series : {&fc, &ft, &phi})
      series->x.push_back(m_to_mm(p.uncut_chip_thickness_m));
    fc.y.push_back(p.cutting_force_n);
    ft.y.push_back(p.thrust_force_n);
    phi.y.push_back(units::rad_to_deg(p.shear_angle_rad));
  }
  spec.series = {fc, ft, here, phi};
  return spec;
}

// Three vibration periods of the pulsed forces g(t)·K·h·w (or a flat line).
io::PlotSpec pulse_plot(const app::ForceJobReport& r) {
  const ContactWindow g = r.duty_cycle.window();
  const double T = r.vibration ? r.duty_cycle.period_s : 1e-3;
  io::PlotSpec spec;
  spec.title =
      r.vibration ? "Pulsed cutting forces of vibration-assisted turning" : "Cutting forces";
  spec.x_label = "time (µs)";
  spec.y_label = "force (N)";
  spec.y_min = 0.0;
  spec.y_max = 1.15 * std::max(r.forces.peak_cutting_n, r.forces.peak_thrust_n);
  io::PlotSeries fc{"cutting force", {}, {}, "lines"}, ft{"thrust force", {}, {}, "lines"};
  const int n = 1500;
  for (int i = 0; i <= n; ++i) {
    const double t = 3.0 * T * i / n;
    const double on = g.in_contact(t) ? 1.0 : 0.0;
    fc.x.push_back(t * 1e6);
    fc.y.push_back(on * r.forces.peak_cutting_n);
    ft.x.push_back(t * 1e6);
    ft.y.push_back(on * r.forces.peak_thrust_n);
  }
  spec.series = {fc, ft};
  return spec;
}

}  // namespace

int run_force(const ForceArgs& args, std::ostream& out, std::ostream& err) {
  check_outputs({"", args.json, args.plot});
  const io::Case c = load_case(args.case_path, kDefaultForceCase, err);
  const app::ForceJobReport r = app::run_force(c);
  const PulsedForces& f = r.forces;
  out << "cutdyn force: " << c.source << "\n";
  if (r.oxley) print_oxley(c, *r.oxley, out);
  out << "  Kc = " << human(units::pa_to_n_per_mm2(r.kc_pa))
      << " N/mm², Kf = " << human(units::pa_to_n_per_mm2(r.kf_pa))
      << " N/mm²; h = " << human(m_to_mm(r.uncut_chip_thickness_m))
      << " mm, w = " << human(m_to_mm(r.width_m)) << " mm";
  if (r.speed_m_per_s)
    out << ", v = " << human(units::m_per_s_to_m_per_min(*r.speed_m_per_s)) << " m/min";
  out << "\n";
  if (c.vibration) print_vibration(*c.vibration, r.duty_cycle, out);
  out << "  cutting force " << human(f.peak_cutting_n) << " N while cutting, mean "
      << human(f.mean_cutting_n) << " N\n";
  out << "  thrust force  " << human(f.peak_thrust_n) << " N while cutting, mean "
      << human(f.mean_thrust_n) << " N\n";

  io::OutputTransaction outputs;
  if (!args.json.empty()) io::write_json(outputs.open(args.json), app::to_json(c, r));
  if (!args.plot.empty())
    io::write_plot(r.oxley && !r.vibration ? oxley_plot(c, r) : pulse_plot(r), args.plot, outputs);
  outputs.commit();
  for (const std::string* file : {&args.json, &args.plot})
    if (!file->empty()) out << "  wrote " << *file << "\n";
  return 0;
}

}  // namespace cutdyn::cli
