// Regenerative chatter in milling [Altintas & Budak 1995; Insperger & Stépán 2004;
// Ding et al. 2010]; docs/models/milling-stability.md.
//
// Tooth j of z sits at the angle φj(t) = Ω·t + 2πj/z, measured clockwise from the +y axis
// (models.md S1.2). In cut (φst < φj < φex) it takes the chip h = Δx·sin φj + Δy·cos φj
// (Δ = r(t) − r(t − τ), r the cutter's displacement) and pushes the cutter with
//     Fx = −Ft·cos φj − Fr·sin φj,   Fy = Ft·sin φj − Fr·cos φj,   Ft = Kt·a·h, Fr = Kr·a·h.
// Summed over the teeth: F = (a/2)·Kt·A(t)·Δ with Altintas' directional matrix A(t), so the
// neutral description has H(t) = −(Kt/2)·A(t), period and delay τ = 60/(n·z).
#pragma once

#include <string>
#include <vector>

#include "cutdyn/modal/modal_model.hpp"
#include "cutdyn/stability/delayed_system.hpp"

namespace cutdyn {

struct MillingModel {
  ModalModel modal;               // modes in x (feed) and y
  double kt_pa = 0.0;             // tangential cutting coefficient, N/m²
  double kr_pa = 0.0;             // radial cutting coefficient, N/m²
  int teeth = 2;                  // z, evenly spaced
  double radial_immersion = 1.0;  // a_e / D, 0 < . <= 1
  bool down_milling = true;

  std::vector<std::string> validate() const;
  /// Entry and exit angles (rad) of a tooth: down-milling [acos(2a_e/D − 1), π],
  /// up-milling [0, acos(1 − 2a_e/D)].
  double entry_angle() const;
  double exit_angle() const;
};

/// The neutral description at spindle speed `rpm`: x = the modal states of the x and y modes,
/// y = (x, y) displacements of the cutter, H(t) = −(Kt/2)·A(t) with exact step means and
/// Fourier coefficients, τ = T = 60/(rpm·z).
DelayedSystem milling_system(const MillingModel& model, double rpm);

/// Altintas' directional matrix per tooth in cut, per unit Kt·a/2, at angle φ (Kr = kr/kt).
Eigen::Matrix2d milling_directional_matrix(double phi, double kr_ratio);

}  // namespace cutdyn
