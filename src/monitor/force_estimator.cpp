#include "cutdyn/monitor/force_estimator.hpp"

#include <Eigen/Dense>
#include <cmath>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn {
namespace {

// Gains of the observer for step dt: both poles at r = exp(−2π f_b dt).
void gains(double bandwidth_hz, double dt, double& alpha, double& beta) {
  const double r = std::exp(-units::kTwoPi * bandwidth_hz * dt);
  alpha = 1.0 - r * r;
  beta = (1.0 - r) * (1.0 - r);
}

bool same_step(double a, double b) { return std::abs(a - b) <= 1e-6 * b; }

}  // namespace

AccelerationObserver::AccelerationObserver(double bandwidth_hz) : bandwidth_hz_(bandwidth_hz) {}

void AccelerationObserver::set_step(double dt) {
  double beta = 0.0;
  gains(bandwidth_hz_, dt, alpha_, beta);
  beta_over_dt_ = beta / dt;
  dt_ = dt;
}

void AccelerationObserver::update(double w, double dt) {
  if (!started_) {
    w_ = w;
    e_ = 0.0;
    started_ = true;
    return;
  }
  if (!same_step(dt, dt_)) set_step(dt);
  const double predicted = w_ + e_ * dt;
  const double residual = w - predicted;
  w_ = predicted + alpha_ * residual;
  e_ += beta_over_dt_ * residual;
}

AccelerationObserver::NoiseGain AccelerationObserver::noise_gain(double bandwidth_hz, double dt) {
  double alpha = 0.0, beta = 0.0;
  gains(bandwidth_hz, dt, alpha, beta);
  // Error dynamics e⁺ = (I − K·H)·F·e + K·v, K = (α, β/Δt): the stationary covariance solves
  // P = A·P·Aᵀ + K·Kᵀ (a discrete Lyapunov equation, vectorised with the Kronecker product).
  Eigen::Matrix2d a;
  a << 1.0 - alpha, (1.0 - alpha) * dt, -beta / dt, 1.0 - beta;
  const Eigen::Vector2d k(alpha, beta / dt);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int p = 0; p < 2; ++p)
        for (int q = 0; q < 2; ++q) m(2 * i + p, 2 * j + q) -= a(i, j) * a(p, q);
  const Eigen::Matrix2d kk = k * k.transpose();
  Eigen::Vector4d rhs(kk(0, 0), kk(0, 1), kk(1, 0), kk(1, 1));
  const Eigen::Vector4d p = m.partialPivLu().solve(rhs);
  NoiseGain g;
  g.speed = std::sqrt(p(0));
  g.accel = std::sqrt(p(3));
  g.correlation = p(1) / (g.speed * g.accel);
  return g;
}

std::vector<std::string> EstimatorOptions::validate() const {
  Validator v("estimator");
  v.require_positive("bandwidth_hz", bandwidth_hz, "Hz");
  v.require(standstill_rad_s >= 0.0, "standstill_rad_s", standstill_rad_s, "rad/s", "must be >= 0");
  return v.problems();
}

AxisForceEstimator::AxisForceEstimator(const AxisCalibration& c, const EstimatorOptions& o)
    : cal_(c), options_(o), observer_(o.bandwidth_hz) {
  Validator v;
  v.merge(c.validate());
  v.merge(o.validate());
  v.throw_if_any();
  const AxisModel& m = c.model;
  kt_ = m.torque_constant_nm_per_a;
  x_ = m.viscous_nm_s_per_rad;
  tf_ = m.friction_nm;
  j_ = m.inertia_kg_m2;
  inv_k_ = 1.0 / m.force_gain_m;
  id_noise_ = c.current_noise_a;
  reset();
}

void AxisForceEstimator::reset() {
  observer_.reset();
  started_ = false;
  step_checked_ = false;
  sign_ = 1.0;
  dt_ = -1.0;
  // Until the step is known: the speed noise enters through X·ω only.
  var_obs_nm2_ = x_ * x_ * cal_.speed_noise_rad_s * cal_.speed_noise_rad_s;
}

void AxisForceEstimator::set_step(double dt) {
  dt_ = dt;
  const double sw = cal_.speed_noise_rad_s;
  if (sw == 0.0) {
    var_obs_nm2_ = 0.0;
    return;
  }
  const auto g = AccelerationObserver::noise_gain(options_.bandwidth_hz, dt);
  const double a = x_ * g.speed, b = j_ * g.accel;
  var_obs_nm2_ = sw * sw * (a * a + b * b + 2.0 * a * b * g.correlation);
}

ForceEstimate AxisForceEstimator::update(double t, double iu, double iv, double iw, double w) {
  const double id = equivalent_current(iu, iv, iw, cal_.model.measure);
  if (started_) {
    const double dt = t - last_time_;
    if (!step_checked_) {
      step_checked_ = true;
      const double nyquist_hz = 0.5 / dt;
      if (!(options_.bandwidth_hz < nyquist_hz))
        throw InvalidInput({"bandwidth_hz = " + format_value(options_.bandwidth_hz) +
                            " Hz: must be below the Nyquist frequency of the samples, " +
                            format_value(nyquist_hz) + " Hz (half the rate of the first step, " +
                            format_value(dt) + " s)"});
    }
    if (!same_step(dt, dt_)) set_step(dt);
    observer_.update(w, dt);
  } else {
    observer_.update(w, 0.0);
    started_ = true;
  }
  last_time_ = t;
  ForceEstimate e;
  e.speed_rad_s = observer_.speed();
  e.accel_rad_s2 = observer_.accel();
  const double ws = e.speed_rad_s, eps = e.accel_rad_s2;
  e.standstill = std::abs(ws) < options_.standstill_rad_s;
  if (!e.standstill) sign_ = ws > 0.0 ? 1.0 : -1.0;
  const double friction = e.standstill ? 0.0 : tf_ * sign_;
  // [Zheng2012, eq. 4] with ω̂, ε̂ of the observer.
  const double load = sign_ * kt_ * id - x_ * ws - friction - j_ * eps;
  e.force_n = load * inv_k_;

  const AxisUncertainty& u = cal_.sigma;
  const double kt_noise = kt_ * id_noise_, kt_u = id * u.torque_constant_nm_per_a;
  double var = kt_noise * kt_noise + kt_u * kt_u + var_obs_nm2_;
  var += ws * ws * u.viscous_nm_s_per_rad * u.viscous_nm_s_per_rad;
  if (e.standstill) {
    var += tf_ * tf_ / 3.0;  // static friction anywhere in ±Tnzm
  } else {
    var += u.friction_nm * u.friction_nm + 2.0 * ws * sign_ * u.friction_viscous_covariance;
  }
  var += eps * eps * u.inertia_kg_m2 * u.inertia_kg_m2;
  const double fk = e.force_n * u.force_gain_m;
  var += fk * fk;
  e.force_sigma_n = std::sqrt(std::max(0.0, var)) * inv_k_;
  e.sigma_known = cal_.uncertainty_known;
  return e;
}

}  // namespace cutdyn
