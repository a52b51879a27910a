// `cutdyn lobes` and `check` for milling.
#include <fmt/format.h>

#include <cmath>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/stability/full_discretization.hpp"
#include "cutdyn/stability/multi_frequency.hpp"

namespace cutdyn::cli {
namespace {

using units::m_to_mm;
using units::mm_to_m;

MillingMethod resolve(const io::Case& c, const std::string& flag) {
  return milling_method(asked_method(c, flag));
}

// The full discretization's work grows with the structural periods in one tooth period.
void check_milling_speed(const MillingModel& m, double rpm) {
  constexpr double kMaxModeCycles = 500.0;
  Validator v;
  v.require_positive("spindle speed", rpm, "rpm");
  v.throw_if_any();
  const double tooth_period = 60.0 / (rpm * m.teeth);
  const double f_top = units::rad_per_s_to_hz(m.modal.max_natural_rad_s());
  if (tooth_period * f_top > kMaxModeCycles) {
    v.add(
        fmt::format("spindle speed = {} rpm: one tooth period spans {:.0f} periods of the {} Hz "
                    "mode; the milling stability methods take at most {:.0f} (raise the speed)",
                    human(rpm), tooth_period * f_top, human(f_top), kMaxModeCycles));
  }
  v.throw_if_any();
}

MillingStabilityOptions stability_options(const io::Case& c, MillingMethod method) {
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
std::string cutter(const MillingModel& m) {
  std::string teeth = fmt::format("{} teeth", m.teeth);
  if (m.helix_rad > 0.0) teeth += fmt::format(", helix {}°", human(units::rad_to_deg(m.helix_rad)));
  if (!m.even_pitch()) {
    std::string pitch;
    for (double p : m.pitch_rad) {
      if (!pitch.empty()) pitch += '/';
      pitch += human(units::rad_to_deg(p));
    }
    teeth += ", pitch " + pitch + "°";
  }
  return teeth;
}

// "a_e/D = 0.5, down-milling", or for a window given as angles
// "entry 90°, exit 180° (a_e/D = 0.5)".
std::string engagement(const MillingModel& m) {
  if (m.window_entry_rad)
    return fmt::format(
        "entry {}°, exit {}° (a_e/D = {})", human(units::rad_to_deg(m.entry_angle()), 4),
        human(units::rad_to_deg(m.exit_angle()), 4), human(m.engaged_immersion(), 4));
  return fmt::format("a_e/D = {}, {}", human(m.radial_immersion),
                     m.down_milling ? "down-milling" : "up-milling");
}

std::string describe(const MillingModel& m) {
  const std::string teeth = cutter(m);
  return fmt::format("milling, {}, {} mode{}, Kt = {} N/mm², Kr = {} N/mm², {}", teeth,
                     m.modal.modes.size(), m.modal.modes.size() == 1 ? "" : "s",
                     human(units::pa_to_n_per_mm2(m.kt_pa)), human(units::pa_to_n_per_mm2(m.kr_pa)),
                     engagement(m));
}

}  // namespace

int run_lobes_milling(const LobesArgs& args, const io::Case& c, std::ostream& out,
                      std::ostream& err) {
  const MillingModel model = milling_model(c, "lobes");
  const MillingMethod method = resolve(c, args.method);
  const LobesOptions grid = lobes_grid(c, args.threads);
  const MillingStabilityOptions options = stability_options(c, method);
  rethrow_as(c.source, "lobes.rpm_min", [&] { check_milling_speed(model, grid.rpm_min); });
  const LobesReport report = trace_lobes(
      [&](double rpm) {
        const MillingBoundary b = milling_critical_depth(model, rpm, options);
        return LobePoint{rpm, b.boundary, 1.0, b.lobe};
      },
      grid, progress_reporter(err, "lobes"));
  LobesView view;
  view.description = describe(model);
  view.method = to_string(method);
  view.depth_max_m = c.lobes.depth_max_m;
  view.title = "Stability lobes: milling";
  view.label = fmt::format("{}, {} ({})", cutter(model), engagement(model), to_string(method));
  if (args.target_depth_mm) view.target_depth_m = mm_to_m(*args.target_depth_mm);
  if (auto caveat = milling_method_caveat(model, method, grid.rpm_min, grid.rpm_max))
    view.warnings.push_back(*caveat);
  report_lobes(c, report, view, args.outputs, out, err);
  return 0;
}

int run_check_milling(const CheckArgs& args, const io::Case& c, std::ostream& out) {
  const MillingModel model = milling_model(c, "check");
  rethrow_as("command line", "--rpm", [&] { check_milling_speed(model, args.rpm); });
  const MillingMethod method = resolve(c, args.method);
  // The lobes' search; where it finds no boundary, carried on past the depth asked (to tell
  // its margin) on the same depth grid, so the critical depth is that of the lobes whatever
  // the depth asked.
  const MillingStabilityOptions options = stability_options(c, method);
  MillingBoundary b = milling_critical_depth(model, args.rpm, options);
  const double reach = 1.25 * mm_to_m(args.depth_mm);
  if (!b.boundary.found && reach > options.depth_max_m) {
    if (reach > kMaxSearchExtension * options.depth_max_m) {
      throw InvalidInput(
          {fmt::format("--depth-mm = {}: stable up to lobes.depth_max_mm = {} mm at this speed, "
                       "and the depth asked is more than {} times that; raise "
                       "lobes.depth_max_mm in the case to search that deep",
                       human(args.depth_mm), human(m_to_mm(options.depth_max_m)),
                       human(kMaxSearchExtension / 1.25))},
          "command line");
    }
    b = milling_critical_depth(model, args.rpm, extend_search(options, reach));
  }
  CheckView view;
  view.description = describe(model);
  view.method = to_string(method);
  view.lobe = b.lobe;
  if (auto caveat = milling_method_caveat(model, method, args.rpm, args.rpm)) {
    view.notes.push_back("warning: " + *caveat);
    view.extra["warnings"] = std::vector<std::string>{*caveat};
  }
  report_check(c, args, b.boundary, view, out);
  return 0;
}

}  // namespace cutdyn::cli
