#include "cutdyn/app/force.hpp"

#include <string>

#include "cutdyn/core/error.hpp"
#include "cutdyn/forces/oxley.hpp"

namespace cutdyn::app {
namespace {

void require_keys(const io::Case& c) {
  Validator v;
  if (c.process == io::Process::kMilling)
    v.add(
        "process = \"milling\": `cutdyn force` computes the forces of an orthogonal (turning) "
        "cut; the milling forces come from `cutdyn simulate`");
  const auto need = [&](const std::optional<double>& x, const char* key) {
    if (!x) v.add(std::string("cutting.") + key + ": missing (required by `cutdyn force`)");
  };
  if (!c.material) {
    need(c.cutting.kc_pa, "kc_n_per_mm2 (or give a [material] to predict it)");
    need(c.cutting.kf_pa, "kf_n_per_mm2 (or give a [material] to predict it)");
  }
  need(c.cutting.uncut_chip_thickness_m, "uncut_chip_thickness_mm");
  need(c.cutting.width_m, "width_mm");
  if (c.vibration && !c.vibration->duty_cycle && !c.cutting.speed_m_per_s)
    v.add(
        "cutting.speed_m_per_min: missing (required by `cutdyn force` to compute the duty cycle; "
        "or give vibration.duty_cycle)");
  v.throw_if_any(c.source);
}

std::vector<ChipThicknessPoint> around(const io::Case& c, const OxleyPrediction& p) {
  std::vector<ChipThicknessPoint> out;
  const double h = p.cut.uncut_chip_thickness_m;
  for (int i = 0; i <= 14; ++i) {
    OrthogonalCut cut = p.cut;
    cut.uncut_chip_thickness_m = h * (0.25 + 1.75 * i / 14.0);
    try {
      const OxleyResult r = oxley_orthogonal(*c.material, cut, c.oxley);
      out.push_back({cut.uncut_chip_thickness_m, r.state.cutting_force_n, r.state.thrust_force_n,
                     r.state.phi_rad});
    } catch (const InvalidInput&) {
      // outside the theory: no point
    }
  }
  return out;
}

}  // namespace

ForceJobReport run_force(const io::Case& c) {
  require_keys(c);
  ForceJobReport r;
  if (c.material) r.oxley = predict_with_oxley(c, "force", true);
  r.kc_pa = r.oxley ? r.oxley->result.kc_pa : *c.cutting.kc_pa;
  r.kf_pa = r.oxley ? r.oxley->result.kt_pa : *c.cutting.kf_pa;
  r.vibration = c.vibration.has_value();
  if (c.vibration) {
    r.duty_cycle = c.vibration->duty_cycle
                       ? fixed_duty_cycle(*c.vibration->duty_cycle, c.vibration->frequency_hz)
                       : duty_cycle(*c.cutting.speed_m_per_s, c.vibration->frequency_hz,
                                    *c.vibration->amplitude_m);
  }
  r.uncut_chip_thickness_m = *c.cutting.uncut_chip_thickness_m;
  r.width_m = *c.cutting.width_m;
  r.speed_m_per_s = c.cutting.speed_m_per_s;
  r.forces =
      pulsed_forces(r.kc_pa, r.kf_pa, r.uncut_chip_thickness_m, r.width_m, r.duty_cycle.ratio);
  if (r.oxley && !c.vibration) r.around = around(c, *r.oxley);
  return r;
}

}  // namespace cutdyn::app
