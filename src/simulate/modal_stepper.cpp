#include "cutdyn/simulate/modal_stepper.hpp"

#include <unsupported/Eigen/MatrixFunctions>

namespace cutdyn {

ModalStepper::ModalStepper(const ModalModel& model, const std::vector<Direction>& directions,
                           double step_s)
    : step_s_(step_s) {
  const auto ss = modal_state_space(model, directions);
  const auto d = ss.A.rows(), r = ss.B.cols();
  Eigen::MatrixXd aug = Eigen::MatrixXd::Zero(d + r, d + r);
  aug.topLeftCorner(d, d) = ss.A * step_s;
  aug.topRightCorner(d, r) = ss.B * step_s;
  const Eigen::MatrixXd e = aug.exp();
  phi_ = e.topLeftCorner(d, d);
  gamma_ = e.topRightCorner(d, r);
  c_ = ss.C;
  a_ = ss.A;
  b_ = ss.B;
}

void ModalStepper::step(Eigen::VectorXd& x, const Eigen::VectorXd& force) const {
  x = phi_ * x + gamma_ * force;
}

Eigen::VectorXd ModalStepper::static_state(const Eigen::VectorXd& force) const {
  // 0 = A·x + B·F.
  return a_.partialPivLu().solve(-b_ * force);
}

}  // namespace cutdyn
