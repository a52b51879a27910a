#include "cutdyn/app/stability.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

#include "cutdyn/app/case_models.hpp"
#include "cutdyn/app/detail/text.hpp"
#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/stability/full_discretization.hpp"
#include "cutdyn/stability/method.hpp"
#include "cutdyn/stability/milling.hpp"
#include "cutdyn/stability/multi_frequency.hpp"
#include "cutdyn/stability/turning.hpp"

namespace cutdyn::app {
namespace {

using units::m_to_mm;

// The method asked for: the request's, else the case's [lobes].method.
StabilityMethod asked_method(const io::Case& c, const std::string& name,
                             const RequestNames& names) {
  if (name.empty()) return c.lobes.method;
  if (const auto m = parse_stability_method(name)) return *m;
  throw InvalidInput(
      {names.method + " = \"" + name + "\": must be one of " + kStabilityMethodNames}, names.where);
}

// ---- turning ----------------------------------------------------------------------------

}  // namespace

TurningStabilityOptions turning_stability_options(const io::Case& c, TurningMethod method) {
  TurningStabilityOptions o;
  o.method = method;
  o.depth_max_m = c.lobes.depth_max_m;
  o.harmonics = c.lobes.harmonics;
  o.fd.steps_per_period = c.lobes.steps_per_period;
  return o;
}

namespace {

// "2 modes", "measured FRF (x, y; x: 2 modes fitted …)", or both.
std::string structure_text(const ModalModel& modal,
                           const std::optional<MeasuredStructure>& measured,
                           std::string_view directions) {
  const std::size_t n = modal.modes.size();
  std::string s =
      n == 0 && measured ? "" : fmt::format("{} mode{}{}", n, n == 1 ? "" : "s", directions);
  if (!measured) return s;
  if (!s.empty()) s += " and ";
  std::vector<std::string> tables;
  if (measured->xx) tables.emplace_back("x");
  if (measured->yy) tables.emplace_back("y");
  if (measured->xy) tables.emplace_back("xy");
  s += fmt::format("measured FRF ({}; {})", fmt::join(tables, ", "),
                   fmt::join(measured->fit_notes, "; "));
  return s;
}

}  // namespace

std::string describe_turning(const io::Case& c, const TurningProcess& m) {
  std::string s =
      fmt::format("turning, {}, Kf = {} N/mm²", structure_text(m.modal, m.measured, " in x"),
                  human(units::pa_to_n_per_mm2(m.kf_pa)));
  if (c.material && !c.cutting.kf_pa)
    s += fmt::format(" (predicted for {} by Oxley's theory at {} m/min)", c.material->name,
                     human(units::m_per_s_to_m_per_min(*c.cutting.speed_m_per_s)));
  if (m.vibration) {
    s += fmt::format("; vibration {} Hz", human(m.vibration->frequency_hz));
    if (m.vibration->duty_cycle) {
      s += fmt::format(", duty cycle {} (fixed)", human(*m.vibration->duty_cycle));
    } else {
      s += fmt::format(", {} µm on a {} mm workpiece (duty cycle from the speed)",
                       human(units::m_to_um(*m.vibration->amplitude_m)),
                       human(m_to_mm(*m.vibration->workpiece_diameter_m)));
    }
  }
  return s;
}

namespace {

// The fit of the case's [[frf]] tables into a report: its modes and warnings.
template <typename Report>
void add_fit(const std::optional<MeasuredStructure>& measured, Report& r) {
  if (!measured) return;
  r.fitted_modes = measured->fitted;
  r.warnings.insert(r.warnings.end(), measured->fit_warnings.begin(), measured->fit_warnings.end());
}

// Each returns the critical depth at any speed as its lobes computed it, for the advice.
CriticalDepthAt turning_lobes(const io::Case& c, const LobesRequest& request, LobesJobReport& r) {
  const TurningProcess model = turning_process(c, "lobes");
  const TurningMethod method =
      turning_method(asked_method(c, request.method, request.names), model.vibration.has_value());
  const TurningStabilityOptions options = turning_stability_options(c, method);
  if (const auto problems = options.validate(); !problems.empty())
    throw InvalidInput(problems, c.source);
  const LobesOptions grid = lobes_grid(c, request.threads);
  rethrow_as(c.source, "lobes.rpm_min", [&] { check_speed_domain(model, grid.rpm_min); });
  const bool assisted = model.vibration.has_value();
  const auto at_speed = [&](double rpm) {
    const TurningBoundary b = turning_critical_depth(model, rpm, options);
    return LobePoint{rpm, b.boundary, b.duty_cycle, b.lobe};
  };
  r.lobes = trace_lobes(at_speed, grid, request.progress);
  // With vibration, the conventional lobes beside them (exact closed form, cheap), traced
  // with their own refinement; each curve is then completed at the other's speeds, so both
  // hold their cusps and share one row per speed.
  if (assisted) {
    TurningStabilityOptions exact = options;
    exact.method = TurningMethod::kClosedForm;
    const TurningProcess conventional = model.conventional();
    const auto conventional_at = [&](double rpm) {
      return LobePoint{rpm, turning_critical_depth(conventional, rpm, exact).boundary, 1.0, 0};
    };
    LobesReport conv = trace_lobes(conventional_at, grid);
    complete_lobes(at_speed, conv.points, r.lobes.points, grid.threads);
    complete_lobes(conventional_at, r.lobes.points, conv.points, grid.threads);
    for (const LobePoint& p : conv.points) r.reference.push_back(p.boundary);
    r.reference_label = "conventional (closed form)";
    r.duty_cycle = true;
  }
  r.description = describe_turning(c, model);
  add_fit(model.measured, r);
  r.method = to_string(method);
  r.depth_max_m = options.depth_max_m;
  r.title = assisted ? "Stability lobes: vibration-assisted and conventional turning"
                     : "Stability lobes: turning";
  r.label =
      fmt::format("{} ({})", assisted ? "vibration-assisted" : "conventional", to_string(method));
  return [model, options](double rpm) {
    return turning_critical_depth(model, rpm, options).boundary.depth_m;
  };
}

void turning_check(const io::Case& c, const CheckRequest& request, CheckJobReport& r) {
  const TurningProcess model = turning_process(c, "check");
  rethrow_as(request.names.where, request.names.rpm,
             [&] { check_speed_domain(model, request.rpm); });
  const TurningMethod method =
      turning_method(asked_method(c, request.method, request.names), model.vibration.has_value());
  TurningStabilityOptions options = turning_stability_options(c, method);
  // Search far enough above the requested depth to say how much margin there is.
  options.depth_max_m = std::max(options.depth_max_m, std::min(4.0 * request.depth_m, kMaxDepthM));
  if (const auto problems = options.validate(); !problems.empty())
    throw InvalidInput(problems, c.source);
  const TurningBoundary b = turning_critical_depth(model, request.rpm, options);
  r.description = describe_turning(c, model);
  add_fit(model.measured, r);
  r.method = to_string(method);
  r.boundary = b.boundary;
  r.lobe = b.lobe;
  r.duty_cycle = b.duty_cycle;
  if (model.vibration) {
    TurningStabilityOptions exact = options;
    exact.method = TurningMethod::kClosedForm;
    const TurningBoundary cb = turning_critical_depth(model.conventional(), request.rpm, exact);
    r.conventional = CheckJobReport::Conventional{
        cb.boundary, !cb.boundary.found || request.depth_m < cb.boundary.depth_m};
  }
}

}  // namespace

// ---- milling ----------------------------------------------------------------------------

void check_milling_speed(int teeth, double top_mode_hz, double rpm) {
  constexpr double kMaxModeCycles = 500.0;
  Validator v;
  v.require_positive("spindle speed", rpm, "rpm");
  v.throw_if_any();
  const double tooth_period = 60.0 / (rpm * teeth);
  if (tooth_period * top_mode_hz > kMaxModeCycles) {
    v.add(fmt::format(
        "spindle speed = {} rpm: one tooth period spans {:.0f} periods of the {} Hz mode; the "
        "milling stability methods and the regenerative simulation take at most {:.0f} (raise "
        "the speed)",
        human(rpm), tooth_period * top_mode_hz, human(top_mode_hz), kMaxModeCycles));
  }
  v.throw_if_any();
}

namespace {

void check_milling_speed(const MillingProcess& m, double rpm) {
  app::check_milling_speed(m.tool.teeth, units::rad_per_s_to_hz(m.modal.max_natural_rad_s()), rpm);
}

MillingStabilityOptions milling_options(const io::Case& c, MillingMethod method) {
  MillingStabilityOptions o;
  o.method = method;
  o.depth_max_m = c.lobes.depth_max_m;
  o.harmonics = c.lobes.harmonics;
  o.fd.steps_per_period = c.lobes.steps_per_period;
  // Full discretization: a coarse scan of 16 depths brackets the first unstable one (islands
  // above a stable band are not skipped), then Brent's method on the spectral radius to 0.1 %.
  o.rel_tol = 1e-3;
  o.coarse_steps = 16;
  return o;
}

// "4 teeth, helix 30°, pitch 70/110/70/110°".
std::string cutter(const MillingProcess& m) {
  std::string teeth = fmt::format("{} teeth", m.tool.teeth);
  if (m.tool.helix_rad > 0.0)
    teeth += fmt::format(", helix {}°", human(units::rad_to_deg(m.tool.helix_rad)));
  if (!m.tool.even_pitch()) {
    std::string pitch;
    for (double p : m.tool.pitch_rad) {
      if (!pitch.empty()) pitch += '/';
      pitch += human(units::rad_to_deg(p));
    }
    teeth += ", pitch " + pitch + "°";
  }
  return teeth;
}

// "a_e/D = 0.5, down-milling", or for a window given as angles
// "entry 90°, exit 180° (a_e/D = 0.5)".
std::string engagement(const MillingProcess& m) {
  if (m.engagement.entry_rad)
    return fmt::format("entry {}°, exit {}° (a_e/D = {})",
                       human(units::rad_to_deg(m.engagement.entry_angle()), 4),
                       human(units::rad_to_deg(m.engagement.exit_angle()), 4),
                       human(m.engagement.engaged_immersion(), 4));
  return fmt::format("a_e/D = {}, {}", human(m.engagement.radial_immersion),
                     m.engagement.down_milling ? "down-milling" : "up-milling");
}

std::string describe(const MillingProcess& m) {
  return fmt::format("milling, {}, {}, Kt = {} N/mm², Kr = {} N/mm², {}", cutter(m),
                     structure_text(m.modal, m.measured, ""),
                     human(units::pa_to_n_per_mm2(m.cutting.kt_pa)),
                     human(units::pa_to_n_per_mm2(m.cutting.kr_pa)), engagement(m));
}

CriticalDepthAt milling_lobes(const io::Case& c, const LobesRequest& request, LobesJobReport& r) {
  const MillingProcess model = milling_process(c, "lobes");
  const MillingMethod method = milling_method(asked_method(c, request.method, request.names));
  const LobesOptions grid = lobes_grid(c, request.threads);
  const MillingStabilityOptions options = milling_options(c, method);
  rethrow_as(c.source, "lobes.rpm_min", [&] { check_milling_speed(model, grid.rpm_min); });
  r.lobes = trace_milling_lobes(model, options, grid, request.progress);
  r.description = describe(model);
  add_fit(model.measured, r);
  r.method = to_string(method);
  r.depth_max_m = c.lobes.depth_max_m;
  r.title = "Stability lobes: milling";
  r.label = fmt::format("{}, {} ({})", cutter(model), engagement(model), to_string(method));
  if (auto caveat = milling_method_caveat(model, method, grid.rpm_min, grid.rpm_max))
    r.warnings.push_back(*caveat);
  return [model, options](double rpm) {
    return milling_critical_depth(model, rpm, options).boundary.depth_m;
  };
}

void milling_check(const io::Case& c, const CheckRequest& request, CheckJobReport& r) {
  const RequestNames& names = request.names;
  const MillingProcess model = milling_process(c, "check");
  rethrow_as(names.where, names.rpm, [&] { check_milling_speed(model, request.rpm); });
  const MillingMethod method = milling_method(asked_method(c, request.method, names));
  // The lobes' search; where it finds no boundary, carried on past the depth asked (to tell
  // its margin) on the same depth grid, so the critical depth is that of the lobes whatever
  // the depth asked.
  const MillingStabilityOptions options = milling_options(c, method);
  MillingBoundary b = milling_critical_depth(model, request.rpm, options);
  const double reach = 1.25 * request.depth_m;
  if (!b.boundary.found && reach > options.depth_max_m) {
    if (reach > kMaxSearchExtension * options.depth_max_m) {
      throw InvalidInput(
          {fmt::format("{} = {}: stable up to lobes.depth_max_mm = {} mm at this speed, and the "
                       "depth asked is more than {} times that; raise lobes.depth_max_mm in the "
                       "case to search that deep",
                       names.depth, human(m_to_mm(request.depth_m)),
                       human(m_to_mm(options.depth_max_m)), human(kMaxSearchExtension / 1.25))},
          names.where);
    }
    b = milling_critical_depth(model, request.rpm, extend_search(options, reach));
  }
  r.description = describe(model);
  add_fit(model.measured, r);
  r.method = to_string(method);
  r.boundary = b.boundary;
  r.lobe = b.lobe;
  if (auto caveat = milling_method_caveat(model, method, request.rpm, request.rpm))
    r.warnings.push_back(*caveat);
}

}  // namespace

LobesJobReport run_lobes(const io::Case& c, const LobesRequest& request) {
  if (request.target_depth_m) {
    Validator v;
    require_depth(v, request.names.depth, *request.target_depth_m);
    v.throw_if_any(request.names.where);
  }
  LobesJobReport r;
  const CriticalDepthAt depth_at = c.process == io::Process::kMilling
                                       ? milling_lobes(c, request, r)
                                       : turning_lobes(c, request, r);
  const auto& pts = r.lobes.points;
  for (std::size_t i = 1; i < pts.size(); ++i)
    if (pts[i].boundary.depth_m < pts[r.lowest].boundary.depth_m) r.lowest = i;
  r.pockets = stable_pockets(pts, 3);
  if (std::string w = spindle_warning(c, c.lobes.grid.rpm_max, "lobes.rpm_max"); !w.empty())
    r.warnings.push_back(std::move(w));
  if (request.target_depth_m) {
    r.target_depth_m = request.target_depth_m;
    // The ends found between the traced speeds (the margin holds over the whole interval).
    r.stable_ranges = stable_ranges(pts, *request.target_depth_m, depth_at);
    r.advice = recommend_speed(pts, *request.target_depth_m, depth_at);
  }
  return r;
}

CheckJobReport run_check(const io::Case& c, const CheckRequest& request) {
  Validator v;
  v.require_positive(request.names.rpm, request.rpm, "rpm");
  require_depth(v, request.names.depth, request.depth_m);
  v.throw_if_any(request.names.where);
  CheckJobReport r;
  r.rpm = request.rpm;
  r.depth_m = request.depth_m;
  if (c.process == io::Process::kMilling)
    milling_check(c, request, r);
  else
    turning_check(c, request, r);
  if (std::string w = spindle_warning(c, request.rpm, request.names.rpm); !w.empty())
    r.warnings.push_back(std::move(w));
  r.stable = !r.boundary.found || request.depth_m < r.boundary.depth_m;
  if (r.boundary.depth_m > 0.0)
    r.margin = (r.boundary.depth_m - request.depth_m) / r.boundary.depth_m;
  return r;
}

}  // namespace cutdyn::app
