// The turning reports rendered: the text and figures of `cutdyn simulate` for turning and of
// `cutdyn force` (the pulsed forces of vibration-assisted turning and Oxley's prediction;
// docs/models/turning.md, docs/models/oxley.md).
#include <fmt/format.h>

#include <algorithm>
#include <string>

#include "cutdyn/app/detail/render_text.hpp"
#include "cutdyn/app/detail/text.hpp"
#include "cutdyn/app/render.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/forces/duty_cycle.hpp"
#include "cutdyn/simulate/turning_simulation.hpp"

namespace cutdyn::app {
namespace {

using units::m_to_mm;

std::string oxley_summary(const io::Case& c, const OxleyPrediction& p) {
  return fmt::format(
      "Kc and Kt predicted by Oxley's theory with Johnson–Cook flow stress: {} at {} m/min, "
      "h = {} mm, rake {}°",
      c.material->name, human(units::m_per_s_to_m_per_min(p.cut.speed_m_per_s)),
      human(units::m_to_mm(p.cut.uncut_chip_thickness_m)),
      human(units::rad_to_deg(p.cut.rake_rad)));
}

// The Oxley lines of the force report (text) and their JSON.
void print_oxley(const io::Case& c, const OxleyPrediction& p, std::ostream& out) {
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
io::PlotSpec oxley_plot(const io::Case& c, const ForceJobReport& r) {
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
  for (const ChipThicknessPoint& p : r.around) {
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
io::PlotSpec pulse_plot(const ForceJobReport& r) {
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

void write_text(std::ostream& out, const io::Case& c, const TurningSimulationJobReport& job) {
  const TurningSimulationOptions& o = job.options;
  const auto& runs = job.runs;
  using Run = TurningSimulationRun;
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
}

io::PlotSpec figure(const TurningSimulationJobReport& job) {
  const TurningSimulationOptions& o = job.options;
  const auto& runs = job.runs;
  using Run = TurningSimulationRun;
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

void write_text(std::ostream& out, const io::Case& c, const ForceJobReport& r) {
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
}

io::PlotSpec figure(const io::Case& c, const ForceJobReport& r) {
  return r.oxley && !r.vibration ? oxley_plot(c, r) : pulse_plot(r);
}

}  // namespace cutdyn::app
