// Work materials for predictive force models: the Johnson–Cook flow stress and the thermal
// properties Oxley's machining theory needs (docs/models/oxley.md §1), and a small library
// of published entries.
//
// Temperatures are in °C (Oxley's property fits are written in °C); every other quantity is SI.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "cutdyn/core/error.hpp"

namespace cutdyn {

/// Johnson–Cook flow stress [Johnson1983]:
///   σ = (A + B·εⁿ)·(1 + C·ln(ε̇/ε̇0))·(1 − T*ᵐ),   T* = (T − Tr)/(Tm − Tr).
/// Decisions: ln(ε̇/ε̇0) is taken as 0 below ε̇0 and T* is clamped to [0, 1], so σ is never
/// raised by a slow rate or a cold workpiece and is 0 at and above melting.
struct JohnsonCook {
  double a_pa = 0.0;                         // A, initial yield stress
  double b_pa = 0.0;                         // B, hardening modulus
  double n = 0.0;                            // hardening exponent
  double c = 0.0;                            // strain-rate sensitivity
  double m = 1.0;                            // thermal-softening exponent
  double reference_strain_rate_per_s = 1.0;  // ε̇0
  double reference_temperature_c = 20.0;     // Tr
  double melting_temperature_c = 0.0;        // Tm

  /// σ for equivalent plastic strain ε > 0, rate ε̇ > 0 and temperature T: the product of
  /// the three factors below.
  double flow_stress_pa(double strain, double strain_rate_per_s, double temperature_c) const {
    return hardening_pa(strain) * rate_factor(strain_rate_per_s) * softening(temperature_c);
  }
  double hardening_pa(double strain) const;            // A + B·εⁿ
  double rate_factor(double strain_rate_per_s) const;  // 1 + C·ln(ε̇/ε̇0)
  double softening(double temperature_c) const;        // 1 − T*ᵐ
  /// Strain-hardening index n_eq = ∂lnσ/∂lnε = n·B·εⁿ/(A + B·εⁿ) [Lalwani2009, eq. 7].
  double hardening_index(double strain) const;
};

/// Density and temperature-dependent specific heat and conductivity, each linear in T (°C):
/// S(T) = S0 + S1·T, K(T) = K0 + K1·T (Oxley's form for plain carbon steels).
struct ThermalProperties {
  double density_kg_per_m3 = 0.0;
  double specific_heat_j_per_kg_k = 0.0;         // S0, at 0 °C
  double specific_heat_slope_j_per_kg_k2 = 0.0;  // S1, per °C
  double conductivity_w_per_m_k = 0.0;           // K0, at 0 °C
  double conductivity_slope_w_per_m_k2 = 0.0;    // K1, per °C

  double specific_heat(double temperature_c) const {
    return specific_heat_j_per_kg_k + specific_heat_slope_j_per_kg_k2 * temperature_c;
  }
  double conductivity(double temperature_c) const {
    return conductivity_w_per_m_k + conductivity_slope_w_per_m_k2 * temperature_c;
  }
};

struct WorkMaterial {
  std::string name;
  std::string reference;  // where the parameters come from
  JohnsonCook flow;
  ThermalProperties thermal;
};

/// Records every problem with the material in `v` (field names prefixed by the validator's
/// prefix): positive A, B ≥ 0, 0 ≤ n < 1, C ≥ 0, m > 0, ε̇0 > 0, Tm > Tr, positive density,
/// and positive S(T), K(T) from Tr to Tm.
void validate(const WorkMaterial& material, Validator& v);

/// The built-in materials, each with its reference (docs/models/oxley.md §5).
const std::vector<WorkMaterial>& material_library();

/// The library entry called `name`, compared ignoring case, spaces, '-' and '_'
/// ("AISI1045" = "aisi 1045"); nullptr if there is none.
const WorkMaterial* find_material(std::string_view name);

}  // namespace cutdyn
