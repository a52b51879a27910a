// Exact discrete-time (zero-order hold) step of the structure's modes: with the force held
// constant over a step h,  x(t + h) = Φ·x(t) + Γ·F,  Φ = e^(A·h),  Γ = ∫0^h e^(A·s) ds·B,
// both from one matrix exponential of [[A, B], [0, 0]]·h (Van Loan 1978). Exact for each
// linear mode — no step-size error for the structure itself (models.md S1.4).
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
  /// x ← Φ·x + Γ·force (force: one entry per direction).
  void step(Eigen::VectorXd& x, const Eigen::VectorXd& force) const;
  /// Displacements (one per direction) of the state x.
  Eigen::VectorXd output(const Eigen::VectorXd& x) const { return c_ * x; }
  /// The state of static equilibrium under a constant force.
  Eigen::VectorXd static_state(const Eigen::VectorXd& force) const;

 private:
  double step_s_;
  Eigen::MatrixXd phi_, gamma_, c_, a_, b_;
};

}  // namespace cutdyn
