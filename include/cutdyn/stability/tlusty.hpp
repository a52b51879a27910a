// Conventional (constant-coefficient) regenerative chatter of one direction, exactly:
// Tlusty's closed form for a linear modal structure [Tlusty1963; Altintas2012, ch. 3].
//
// With the direct FRF G(ω) of the modes in the modelled direction and the cutting
// coefficient K (N/m²), the boundary 1 + K·w·G(ω)·(1 − e^(−iωτ)) = 0 gives
//     w_lim(ω) = −1 / (2·K·Re G(ω))       where Re G(ω) < 0,
//     ω·τ = 2π·j + ε(ω),   ε = 3π + 2·arg G(ω) ∈ (π, 2π),   j = 0, 1, 2, ...
// At a spindle speed (τ = 60/n for turning) the critical depth is the smallest w_lim over all
// chatter frequencies that satisfy the phase condition; docs/models/turning.md §3.
#pragma once

#include "cutdyn/modal/modal_model.hpp"
#include "cutdyn/stability/critical_depth.hpp"

namespace cutdyn {

struct TlustyResult {
  CriticalDepth boundary;
  int lobe = 0;  // j: whole chatter waves per delay
};

/// Critical depth at delay τ for the modes of `model` in `direction` and coefficient
/// `coefficient_pa`, searched up to `depth_max_m`. Solves the phase condition for every
/// lobe j by Brent's method on a frequency grid that resolves both the delay phase and each
/// resonance peak.
TlustyResult tlusty_critical_depth(const ModalModel& model, Direction direction,
                                   double coefficient_pa, double delay_s, double depth_max_m);

/// w_lim(ω) and the delay τ of lobe j at chatter frequency ω (parametric lobe form);
/// w_lim is +inf where Re G >= 0.
struct TlustyLobePoint {
  double depth_m;
  double delay_s;
};
TlustyLobePoint tlusty_lobe_point(const ModalModel& model, Direction direction,
                                  double coefficient_pa, double omega_rad_s, int lobe);

}  // namespace cutdyn
