// Exact discrete-time steps of the structure's modes over a step h [VanLoan1978]:
//
//   zero-order hold (force constant over the step):
//     x(t + h) = Φ·x(t) + Γ·F,               Φ = e^(A·h),  Γ = ∫0^h e^(A·s) ds·B;
//   first-order hold (force linear between F0 at t and F1 at t + h):
//     x(t + h) = Φ·x(t) + Γ0·F0 + Γ1·F1,     Γ1 = (1/h)∫0^h e^(A(h−s))·s ds·B,  Γ0 = Γ − Γ1
//
// (the W0, W1 of the full discretization [Ding2010]), all from one matrix exponential of
// [[A·h, B·h, 0], [0, 0, I], [0, 0, 0]]. Exact for each linear mode — no step-size error for
// the structure itself ([Ermolaev2020, eq. 10]; docs/models/milling-simulation.md); the only error is the hold of the force.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "cutdyn/modal/modal_model.hpp"

namespace cutdyn {

class ModalStepper {
 public:
  /// The modes of `model` in `directions` (outputs in that order), step `step_s`.
  ModalStepper(const ModalModel& model, const std::vector<Direction>& directions, double step_s);

  double step_s() const { return step_s_; }
  Eigen::Index states() const { return phi_.rows(); }
  /// Zero-order hold: x ← Φ·x + Γ·force (force: one entry per direction).
  void step(Eigen::VectorXd& x, const Eigen::VectorXd& force) const;
  /// First-order hold: x ← Φ·x + Γ0·force_start + Γ1·force_end.
  void step_linear(Eigen::VectorXd& x, const Eigen::VectorXd& force_start,
                   const Eigen::VectorXd& force_end) const;
  /// Displacements (one per direction) of the state x.
  Eigen::VectorXd output(const Eigen::VectorXd& x) const { return c_ * x; }
  /// The state of static equilibrium under a constant force.
  Eigen::VectorXd static_state(const Eigen::VectorXd& force) const;
  /// Σ over the modes of q² + (q̇/ωn)²: the squared amplitude (m²) of a free vibration,
  /// constant over an undamped oscillation (twice its energy over the modal stiffness).
  double squared_amplitude(const Eigen::VectorXd& x) const;

  const Eigen::MatrixXd& phi() const { return phi_; }
  const Eigen::MatrixXd& gamma() const { return gamma_; }
  const Eigen::MatrixXd& gamma_start() const { return gamma0_; }
  const Eigen::MatrixXd& gamma_end() const { return gamma1_; }
  const Eigen::MatrixXd& output_matrix() const { return c_; }

 private:
  double step_s_;
  Eigen::MatrixXd phi_, gamma_, gamma0_, gamma1_, c_, a_, b_;
  Eigen::VectorXd inverse_wn_squared_;  // per mode
};

}  // namespace cutdyn
