#include "cutdyn/monitor/force_estimator.hpp"

#include <Eigen/Dense>
#include <algorithm>
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

}  // namespace

AccelerationObserver::AccelerationObserver(double bandwidth_hz) : bandwidth_hz_(bandwidth_hz) {}

void AccelerationObserver::set_step(double dt) {
  double beta = 0.0;
  gains(bandwidth_hz_, dt, alpha_, beta);
  beta_over_dt_ = beta / dt;
  dt_ = dt;
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

std::complex<double> EstimateFilter::response(double f) const {
  const double r = std::exp(-units::kTwoPi * bandwidth_hz * dt_s);
  const double w = units::kTwoPi * f * dt_s;
  const double x = units::kPi * f * dt_s;
  const double sinc = x == 0.0 ? 1.0 : std::sin(x) / x;
  const std::complex<double> stage = (1.0 - r) / (1.0 - r * std::polar(1.0, -w));
  return sinc * std::polar(1.0, -0.5 * w) * stage * stage;
}

double EstimateFilter::lag_deg(double f) const {
  const double r = std::exp(-units::kTwoPi * bandwidth_hz * dt_s);
  const double w = units::kTwoPi * f * dt_s;
  // Each stage lags by atan2(r·sin w, 1 − r·cos w) (continuous: 1 − r·cos w > 0 for r < 1);
  // the step mean by w/2 (its sinc is positive below the sampling rate).
  return (0.5 * w + 2.0 * std::atan2(r * std::sin(w), 1.0 - r * std::cos(w))) * 180.0 / units::kPi;
}

double EstimateFilter::minus_3db_hz() const {
  const double nyquist = 0.5 / dt_s;
  const double target = std::sqrt(0.5);
  if (gain(nyquist) >= target) return nyquist;
  double lo = 0.0, hi = nyquist;  // the gain falls monotonically on (0, Nyquist)
  for (int i = 0; i < 200 && hi - lo > 1e-12 * nyquist; ++i) {
    const double mid = 0.5 * (lo + hi);
    (gain(mid) > target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double EstimateFilter::delay_s() const {
  const double r = std::exp(-units::kTwoPi * bandwidth_hz * dt_s);
  return 2.0 * r * dt_s / (1.0 - r) + 0.5 * dt_s;
}

const char* EstimateFilter::formula() {
  return "H(f) = sinc(f*dt)*exp(-j*pi*f*dt)*((1 - r)/(1 - r*exp(-j*2*pi*f*dt)))^2, "
         "r = exp(-2*pi*f_b*dt)";
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
  id_square_factor_ = m.measure == CurrentMeasure::kRms ? 1.0 / 3.0 : 2.0 / 3.0;
  two_var_id_ = 2.0 * id_noise_ * id_noise_;
  reset();
}

void AxisForceEstimator::reset() {
  observer_.reset();
  started_ = false;
  step_checked_ = false;
  sign_ = 1.0;
  dt_ = -1.0;
  first_dt_ = 0.0;
  r_ = 0.0;
  // Until the step is known (the first sample): no filtering, the speed noise enters
  // through X·ω only.
  var_current_gain_ = 1.0;
  var_obs_nm2_ = x_ * x_ * cal_.speed_noise_rad_s * cal_.speed_noise_rad_s;
  set_fixed_variance();
}

namespace {

// Σh² of the impulse response of Q(z)·(a + b·z⁻¹), Q = ((1 − r)/(1 − r·z⁻¹))²: Q's response
// is q_n = (1 − r)²(n + 1)rⁿ, so Σq_n² = (1 − r)⁴(1 + r²)/(1 − r²)³ and
// Σq_n·q_{n−1} = (1 − r)⁴·2r/(1 − r²)³.
double filtered_white_gain(double r, double a, double b) {
  const double rho = r * r, c = std::pow(1.0 - r, 4) / std::pow(1.0 - rho, 3);
  return (a * a + b * b) * c * (1.0 + rho) + 2.0 * a * b * c * 2.0 * r;
}

}  // namespace

void AxisForceEstimator::set_step(double dt) {
  dt_ = dt;
  inv_dt_ = 1.0 / dt;
  r_ = std::exp(-units::kTwoPi * options_.bandwidth_hz * dt);
  // White noise on Id through ½(1 + z⁻¹)·Q; on ω through Q·(−X/2 − J/Δt + (−X/2 + J/Δt)·z⁻¹).
  var_current_gain_ = filtered_white_gain(r_, 0.5, 0.5);
  const double sw = cal_.speed_noise_rad_s;
  var_obs_nm2_ = sw * sw * filtered_white_gain(r_, -0.5 * x_ - j_ / dt, -0.5 * x_ + j_ / dt);
  three_sigma_accel_torque_ =
      3.0 * (j_ * sw * std::sqrt(filtered_white_gain(r_, 1.0 / dt, -1.0 / dt)));
  set_fixed_variance();
}

void AxisForceEstimator::check_first_step(double dt) {
  step_checked_ = true;
  first_dt_ = dt;
  const double nyquist_hz = 0.5 / dt;
  if (!(options_.bandwidth_hz < nyquist_hz))
    throw InvalidInput({"bandwidth_hz = " + format_value(options_.bandwidth_hz) +
                        " Hz: must be below the Nyquist frequency of the samples, " +
                        format_value(nyquist_hz) + " Hz (half the rate of the first step, " +
                        format_value(dt) + " s)"});
}

void AxisForceEstimator::set_fixed_variance() {
  const double kt_noise = kt_ * id_noise_, friction_sigma = cal_.sigma.friction_nm;
  const double noise = kt_noise * kt_noise * var_current_gain_ + var_obs_nm2_;
  var_fixed_nm2_[0] = noise + friction_sigma * friction_sigma;
  var_fixed_nm2_[1] = noise + tf_ * tf_ / 3.0;  // static friction anywhere in ±Tnzm
}

template <bool kSigned>
[[gnu::always_inline]] inline ForceEstimate AxisForceEstimator::estimate(
    double t, double iu, double iv, double iw, double w, [[maybe_unused]] double rotor_angle) {
  // equivalent_current(iu, iv, iw, measure), its factor taken once.
  const double id_square = (iu * iu + iv * iv + iw * iw) * id_square_factor_;
  const double id = std::sqrt(id_square);
  double dt = 0.0;
  if (started_) {
    dt = t - last_time_;
    if (!step_checked_) [[unlikely]]
      check_first_step(dt);
    if (!detail::same_step(dt, dt_)) set_step(dt);
    observer_.update(w, dt);
  } else {
    observer_.update(w, 0.0);
  }
  last_time_ = t;
  ForceEstimate e;
  e.speed_rad_s = observer_.speed();
  const double ws = e.speed_rad_s;
  e.standstill = std::abs(ws) < options_.standstill_rad_s;
  if (!e.standstill) sign_ = ws > 0.0 ? 1.0 : -1.0;
  const double friction = e.standstill ? 0.0 : tf_ * sign_;
  // The torque balance without its inertia term, at this sample [Zheng2012, eq. 4]: the signed
  // torque current where the rotor angle is known, else the magnitude with the sign of motion.
  // The magnitude is biased up by noise: E[Id] ≈ Id_true + σ_Id²/Id_true (second order,
  // docs/models/monitor.md §1), so it is corrected to sqrt(max(Id² − 2σ_Id², 0)), whose mean is
  // Id_true to that order; the size of the correction enters σ (below), since near Id ≈ σ_Id
  // the correction itself is uncertain.
  // The chain from the currents to the force is the estimate's longest: what does not depend
  // on Id (the correction's factor, the sign, KT, the speed and friction terms) is made while
  // its square root is under way, and joins it in one product and one difference.
  double bias = 0.0, kt_current = 0.0;  // KT times the torque current
  if constexpr (kSigned) {
    kt_current = kt_ * signed_equivalent_current(iu, iv, iw, rotor_angle, cal_.model.measure);
  } else if (id_noise_ > 0.0) {
    const double x = two_var_id_ / id_square;  // inf at id = 0: the sqrt branch
    // id·(1 − sqrt(1 − x)) = id·(x/2 + x²/8 + x³/16 + …): the series to 1e-7 relative for x <
    // 0.01, without the square root.
    if (x < 0.01) {
      const double q = x * (0.5 + x * (0.125 + 0.0625 * x));
      bias = id * q;
      kt_current = id * (kt_ * sign_ * (1.0 - q));
    } else {
      const double corrected = std::sqrt(std::max(id_square - two_var_id_, 0.0));
      bias = id - corrected;
      kt_current = kt_ * sign_ * corrected;
    }
  } else {
    kt_current = id * (kt_ * sign_);
  }
  const double rest = x_ * w + friction;  // u = KT·(torque current) − rest
  const double u = kt_current - rest;
  if (!started_) {
    // The first sample: taken as steady (no acceleration), the filter at rest there.
    y1_ = y2_ = u * inv_k_;
    c1_ = c2_ = id;
    a1_ = a2_ = 0.0;
    prev_id_ = id;
    started_ = true;
  } else {
    // The mean load torque over the step: the current term by the trapezoid rule, the
    // inertia term exactly (J times the mean acceleration), then Q.
    const double accel = (w - prev_w_) * inv_dt_;
    // Q's two stages as y ← r·y + g·x, in newtons (the load over KBlf): the first,
    // y1 ← r·y1 + (g/KBlf)·(½(KT·Id − rest) + ½u_prev − J·accel), with the terms without Id
    // summed first, so that Id enters last.
    const double g = 1.0 - r_, gain = g * inv_k_;
    const double before_current = r_ * y1_ + gain * (0.5 * (prev_u_ - rest) - j_ * accel);
    y1_ = before_current + (0.5 * gain) * kt_current;
    y2_ = r_ * y2_ + g * y1_;
    c1_ += g * (id - c1_);
    c2_ += g * (c1_ - c2_);
    a1_ += g * (accel - a1_);
    a2_ += g * (a1_ - a2_);
  }
  e.force_n = y2_;
  e.accel_rad_s2 = a2_;
  const double eps = a2_;
  if (!kSigned && !e.standstill) {
    // The magnitude cannot show a torque against the motion (§4.5 of docs/models/monitor.md).
    // It may be there where (a) the motor gives less than half the friction torque, or less
    // than three noise σ (this sample's, or the filtered magnitude's: a current below the
    // noise has samples above 3σ), or less than its own change over the last step (it may pass
    // through zero within a step): a load aiding the motion takes part of the friction; or (b)
    // the axis decelerates faster than friction alone can brake it (beyond three noise σ).
    const double friction_torque = tf_ + x_ * std::abs(ws), torque = kt_ * id;
    e.torque_sign_doubtful = torque <= 0.5 * friction_torque ||
                             std::min(id, c2_) <= 3.0 * id_noise_ ||
                             torque <= kt_ * std::abs(id - prev_id_) ||
                             sign_ * j_ * eps < -friction_torque - three_sigma_accel_torque_;
  }
  prev_u_ = u;
  prev_w_ = w;
  prev_id_ = id;

  // The variance: the step's constant part (var_fixed_nm2_: the filtered noise, and static
  // friction anywhere in ±Tnzm at a standstill or the friction's uncertainty in motion), then
  // the terms that scale with the current, the speed and the acceleration, and last the one of
  // the force (the last value to be known).
  const AxisUncertainty& un = cal_.sigma;
  const double kt_u = c2_ * un.torque_constant_nm_per_a, kt_bias = kt_ * bias;
  double var = var_fixed_nm2_[e.standstill] + kt_u * kt_u + kt_bias * kt_bias;
  var += ws * ws * un.viscous_nm_s_per_rad * un.viscous_nm_s_per_rad;
  if (!e.standstill) var += 2.0 * ws * sign_ * un.friction_viscous_covariance;
  var += eps * eps * un.inertia_kg_m2 * un.inertia_kg_m2;
  const double fk = e.force_n * un.force_gain_m;
  var += fk * fk;
  e.force_sigma_n = std::sqrt(std::max(0.0, var)) * inv_k_;
  e.sigma_known = cal_.uncertainty_known;
  return e;
}

ForceEstimate AxisForceEstimator::update(double t, double iu, double iv, double iw, double w,
                                         double rotor_angle) {
  return estimate<true>(t, iu, iv, iw, w, rotor_angle);
}

ForceEstimate AxisForceEstimator::update(double t, double iu, double iv, double iw, double w) {
  return estimate<false>(t, iu, iv, iw, w, 0.0);
}

}  // namespace cutdyn
