#include "cutdyn/forces/work_material.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace cutdyn {

// [Johnson1983]; the clamps are documented in the header. The three factors of eq. OX-1
// (docs/models/oxley.md).
double JohnsonCook::hardening_pa(double strain) const { return a_pa + b_pa * std::pow(strain, n); }

double JohnsonCook::rate_factor(double strain_rate_per_s) const {
  return 1.0 + c * std::max(0.0, std::log(strain_rate_per_s / reference_strain_rate_per_s));
}

double JohnsonCook::softening(double temperature_c) const {
  const double t_star = std::clamp(
      (temperature_c - reference_temperature_c) / (melting_temperature_c - reference_temperature_c),
      0.0, 1.0);
  return 1.0 - std::pow(t_star, m);
}

double JohnsonCook::hardening_index(double strain) const {
  // [Lalwani2009, eq. 7]; n_eq of eq. OX-2 (docs/models/oxley.md).
  const double b_term = b_pa * std::pow(strain, n);
  return n * b_term / (a_pa + b_term);
}

void validate(const WorkMaterial& material, Validator& v) {
  const JohnsonCook& jc = material.flow;
  v.require_positive("johnson_cook.a_mpa", jc.a_pa / 1e6, "MPa");
  v.require(std::isfinite(jc.b_pa) && jc.b_pa >= 0.0, "johnson_cook.b_mpa", jc.b_pa / 1e6, "MPa",
            "must be >= 0");
  v.require(std::isfinite(jc.n) && jc.n >= 0.0 && jc.n < 1.0, "johnson_cook.n", jc.n, "",
            "must be in [0, 1)");
  v.require(std::isfinite(jc.c) && jc.c >= 0.0 && jc.c < 1.0, "johnson_cook.c", jc.c, "",
            "must be in [0, 1)");
  v.require(std::isfinite(jc.m) && jc.m > 0.0 && jc.m <= 10.0, "johnson_cook.m", jc.m, "",
            "must be in (0, 10]");
  v.require_positive("johnson_cook.reference_strain_rate_per_s", jc.reference_strain_rate_per_s,
                     "1/s");
  v.require(std::isfinite(jc.reference_temperature_c) && jc.reference_temperature_c > -273.15,
            "johnson_cook.reference_temperature_c", jc.reference_temperature_c, "°C",
            "must be above absolute zero");
  v.require(std::isfinite(jc.melting_temperature_c) &&
                jc.melting_temperature_c > jc.reference_temperature_c,
            "johnson_cook.melting_temperature_c", jc.melting_temperature_c, "°C",
            "must be above the reference temperature");
  const ThermalProperties& th = material.thermal;
  v.require_positive("thermal.density_kg_per_m3", th.density_kg_per_m3, "kg/m³");
  v.require(std::isfinite(th.specific_heat_slope_j_per_kg_k2),
            "thermal.specific_heat_slope_j_per_kg_k2", th.specific_heat_slope_j_per_kg_k2, "",
            "must be finite");
  v.require(std::isfinite(th.conductivity_slope_w_per_m_k2),
            "thermal.conductivity_slope_w_per_m_k2", th.conductivity_slope_w_per_m_k2, "",
            "must be finite");
  // Linear in T: positive at both ends of [Tr, Tm] means positive throughout.
  for (const double t : {jc.reference_temperature_c, jc.melting_temperature_c}) {
    if (!std::isfinite(t)) continue;
    v.require(std::isfinite(th.specific_heat(t)) && th.specific_heat(t) > 0.0,
              "thermal.specific_heat_j_per_kg_k", th.specific_heat_j_per_kg_k, "J/(kg·K)",
              "S(T) = S0 + S1·T must be positive from the reference to the melting temperature");
    v.require(std::isfinite(th.conductivity(t)) && th.conductivity(t) > 0.0,
              "thermal.conductivity_w_per_m_k", th.conductivity_w_per_m_k, "W/(m·K)",
              "K(T) = K0 + K1·T must be positive from the reference to the melting temperature");
  }
}

const std::vector<WorkMaterial>& material_library() {
  // Sources and notes: docs/models/oxley.md §5.
  static const std::vector<WorkMaterial> library = {
      {"AISI1045",
       "Johnson–Cook: Jaspers & Dautzenberg, J. Mater. Process. Technol. 122 (2002) 322–330; "
       "thermal: Oxley, Mechanics of Machining (1989), as used by Lalwani et al., J. Mater. "
       "Process. Technol. 209 (2009) 5305–5312",
       {553.1e6, 600.8e6, 0.234, 0.0134, 1.0, 1.0, 20.0, 1460.0},
       {7862.0, 420.0, 0.504, 52.61, -0.0281}},
      {"AA5083-H116",
       "Johnson–Cook: Clausen, Børvik, Hopperstad & Benallal, Mater. Sci. Eng. A 364 (2004) "
       "260–272 (reference rate 5e-4 1/s, Tr = 293 K, Tm = 893 K); density, specific heat and "
       "conductivity: typical handbook values for 5083 (constant)",
       {167.0e6, 596.0e6, 0.551, 0.001, 0.859, 5e-4, 20.0, 620.0},
       {2660.0, 900.0, 0.0, 117.0, 0.0}},
      {"AISI4340",
       "Johnson–Cook: Johnson & Cook, Eng. Fract. Mech. 21 (1985) 31–48 (Tm = 1793 K); density "
       "and specific heat from Johnson & Cook (1983); conductivity: typical handbook value "
       "(constant)",
       {792.0e6, 510.0e6, 0.26, 0.014, 1.03, 1.0, 20.0, 1520.0},
       {7830.0, 477.0, 0.0, 44.5, 0.0}},
  };
  return library;
}

namespace {

std::string normalised(std::string_view name) {
  std::string out;
  for (const char ch : name) {
    if (ch == ' ' || ch == '-' || ch == '_') continue;
    out.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(ch))));
  }
  return out;
}

}  // namespace

const WorkMaterial* find_material(std::string_view name) {
  const std::string key = normalised(name);
  for (const WorkMaterial& m : material_library())
    if (normalised(m.name) == key) return &m;
  return nullptr;
}

}  // namespace cutdyn
