#include "cutdyn/simulate/detail/modal_stepper.hpp"

#include <unsupported/Eigen/MatrixFunctions>

namespace cutdyn {

ModalStepper::ModalStepper(const ModalModel& model, const std::vector<Direction>& directions,
                           double step_s)
    : step_s_(step_s) {
  const auto ss = modal_state_space(model, directions);
  const auto d = ss.A.rows(), r = ss.B.cols();
  // [VanLoan1978, thm. 1]: exp([[A, B, 0], [0, 0, I], [0, 0, 0]]·h) holds Φ, ∫e^(As)ds·B and
  // ∫e^(A(h−s))·B·s ds; with the middle block scaled by h the last one is Γ1 directly.
  Eigen::MatrixXd aug = Eigen::MatrixXd::Zero(d + 2 * r, d + 2 * r);
  aug.topLeftCorner(d, d) = ss.A * step_s;
  aug.block(0, d, d, r) = ss.B * step_s;
  aug.block(d, d + r, r, r) = Eigen::MatrixXd::Identity(r, r);
  const Eigen::MatrixXd e = aug.exp();
  phi_ = e.topLeftCorner(d, d);
  gamma_ = e.block(0, d, d, r);
  gamma1_ = e.block(0, d + r, d, r);
  gamma0_ = gamma_ - gamma1_;
  c_ = ss.C;
  a_ = ss.A;
  b_ = ss.B;
  inverse_wn_squared_.resize(d / 2);
  for (Eigen::Index i = 0; i < d / 2; ++i) inverse_wn_squared_(i) = -1.0 / ss.A(2 * i + 1, 2 * i);
}

void ModalStepper::step(Eigen::VectorXd& x, const Eigen::VectorXd& force) const {
  x = phi_ * x + gamma_ * force;
}

void ModalStepper::step_linear(Eigen::VectorXd& x, const Eigen::VectorXd& force_start,
                               const Eigen::VectorXd& force_end) const {
  x = phi_ * x + gamma0_ * force_start + gamma1_ * force_end;
}

Eigen::VectorXd ModalStepper::static_state(const Eigen::VectorXd& force) const {
  // 0 = A·x + B·F.
  return a_.partialPivLu().solve(-b_ * force);
}

double ModalStepper::squared_amplitude(const Eigen::VectorXd& x) const {
  double sum = 0.0;
  for (Eigen::Index i = 0; i < inverse_wn_squared_.size(); ++i)
    sum += x(2 * i) * x(2 * i) + x(2 * i + 1) * x(2 * i + 1) * inverse_wn_squared_(i);
  return sum;
}

}  // namespace cutdyn
