// Cutting force from the motor current of a feed axis, sample by sample [Zheng2012, eq. 4];
// docs/models/monitor.md §4.
//
// A disturbance observer: the load torque of each sample step,
//   τ̄_k = ½(u_k + u_{k−1}) − J·(ω_k − ω_{k−1})/Δt,   u = s·KT·Id − X·ω − Tnzm·sign(ω̂),
// (the mean of KBlf·Fc over the step: the current and the acceleration terms taken over the
// same step) passes through one low-pass Q(z) = ((1 − r)/(1 − r·z⁻¹))², r = exp(−2π f_b Δt),
// and Fc = Q·τ̄/KBlf. The estimate is thus the true force through a stated filter
// (EstimateFilter); ω̂ of an alpha–beta observer (AccelerationObserver) gives the direction of
// motion and the speed and acceleration columns. Each estimate carries the standard
// uncertainty of that filtered force (what it covers: docs/models/monitor.md §4.3).
#pragma once

#include <cmath>
#include <complex>
#include <optional>
#include <string>
#include <vector>

#include "cutdyn/monitor/calibration.hpp"

namespace cutdyn {

namespace detail {
/// Steps equal to 1e-6 relative are the same step (the filters keep their gains).
inline bool same_step(double a, double b) { return std::abs(a - b) <= 1e-6 * b; }
}  // namespace detail

/// Fixed-gain alpha–beta observer of speed and acceleration. Per sample (step Δt):
///   predict ω⁻ = ω̂ + ε̂·Δt, ε⁻ = ε̂; residual e = ω − ω⁻;
///   ω̂ = ω⁻ + α·e, ε̂ = ε⁻ + (β/Δt)·e, with r = exp(−2π f_b Δt), α = 1 − r², β = (1 − r)²,
/// which puts both poles of the error dynamics at r (critically damped, bandwidth f_b).
/// It follows a constant acceleration without lag; its first sample sets ω̂ = ω, ε̂ = 0.
class AccelerationObserver {
 public:
  explicit AccelerationObserver(double bandwidth_hz = 50.0);

  /// Updates with the speed measured `dt_s` (> 0) after the previous sample (ignored for the
  /// first sample).
  void update(double speed_rad_s, double dt_s) {
    if (!started_) {
      w_ = speed_rad_s;
      e_ = 0.0;
      started_ = true;
      return;
    }
    if (!detail::same_step(dt_s, dt_)) set_step(dt_s);
    const double predicted = w_ + e_ * dt_s;
    const double residual = speed_rad_s - predicted;
    w_ = predicted + alpha_ * residual;
    e_ += beta_over_dt_ * residual;
  }
  void reset() { started_ = false; }

  double speed() const { return w_; }
  double accel() const { return e_; }
  double bandwidth_hz() const { return bandwidth_hz_; }

  /// Stationary standard deviations of ω̂ and ε̂ and their correlation coefficient when the
  /// measured speed carries white noise of standard deviation 1 and the step is `dt_s`.
  struct NoiseGain {
    double speed = 0.0, accel = 0.0, correlation = 0.0;
  };
  static NoiseGain noise_gain(double bandwidth_hz, double dt_s);

 private:
  void set_step(double dt_s);
  double bandwidth_hz_;
  double dt_ = -1.0, alpha_ = 1.0, beta_over_dt_ = 0.0;
  double w_ = 0.0, e_ = 0.0;
  bool started_ = false;
};

/// The filter between the true force and its estimate for a constant step Δt (docs/models/
/// monitor.md §4.1): the mean over each sample step, then Q(z) = ((1 − r)/(1 − r·z⁻¹))² with
/// r = exp(−2π f_b Δt). For a force component e^{j2πft}:
///   H(f) = sinc(fΔt)·e^{−jπfΔt}·((1 − r)/(1 − r·e^{−j2πfΔt}))²,   sinc x = sin(πx)/(πx),
/// about (2πf_b)²/(s + 2πf_b)² delayed by Δt/2 when f_b ≪ 1/Δt: gain 0.5 and lag 90° at f_b,
/// −3 dB at 0.644·f_b.
struct EstimateFilter {
  double bandwidth_hz = 50.0;  // f_b
  double dt_s = 1e-3;          // Δt

  std::complex<double> response(double f_hz) const;
  double gain(double f_hz) const { return std::abs(response(f_hz)); }
  /// Phase lag in degrees (positive: the estimate lags), continuous in f from 0.
  double lag_deg(double f_hz) const;
  /// Where the gain is 1/√2 (at most the Nyquist frequency 1/(2Δt)).
  double minus_3db_hz() const;
  /// The low-frequency delay, −dφ/dω at 0: 2·r·Δt/(1 − r) + Δt/2.
  double delay_s() const;
  /// "H(f) = sinc(f·Δt)·exp(−jπf·Δt)·((1 − r)/(1 − r·exp(−j2πf·Δt)))², r = exp(−2π·f_b·Δt)".
  static const char* formula();
};

struct EstimatorOptions {
  double bandwidth_hz = 50.0;  // f_b of the acceleration observer, > 0
  // Below this |ω̂| the axis is at standstill: the motor torque keeps the sign of the last
  // motion (+ at first), the friction term is taken as 0 and its standard uncertainty
  // Tnzm/√3 (static friction anywhere in ±Tnzm) is added.
  double standstill_rad_s = 0.5;

  std::vector<std::string> validate() const;
};

struct ForceEstimate {
  double force_n = 0.0;  // Fc through the stated filter (EstimateFilter)
  // The standard uncertainty of force_n as an estimate of the FILTERED force (noise and the
  // calibration's uncertainties; docs/models/monitor.md §4.3), not of the unfiltered Fc: the
  // difference between the two is the stated filter, not an error. The whole of it when
  // `sigma_known`; otherwise only the part the calibration's noise and sigma give (0 for the
  // literature coefficients), a lower bound.
  double force_sigma_n = 0.0;
  double speed_rad_s = 0.0;   // ω̂
  double accel_rad_s2 = 0.0;  // ε̂
  bool standstill = false;
  bool sigma_known = true;  // false: the calibration's uncertainty is unknown
  // Without the rotor angle only: the motor torque may have the sign opposite to the motion
  // here (an aiding load or braking), so the motoring assumption and force_n may be wrong
  // (docs/models/monitor.md §4.5). Never set when the angle is given (the torque is signed).
  bool torque_sign_doubtful = false;
};

/// The streaming estimator of one axis: no allocation per sample.
class AxisForceEstimator {
 public:
  /// Throws InvalidInput if the calibration or the options are invalid.
  AxisForceEstimator(const AxisCalibration& calibration, const EstimatorOptions& options = {});

  /// One sample; times must increase (a programming error otherwise: checked by the readers).
  /// The first step of the axis (after construction or reset) sets the Nyquist frequency
  /// 1/(2Δt): a bandwidth at or above it throws InvalidInput naming both (the observer cannot
  /// follow anything faster than the samples show).
  /// With `rotor_angle_rad` (the electrical angle θe) the torque current is signed
  /// (signed_equivalent_current); without it, it is sign(ω̂)·Id and the estimate flags the
  /// samples where the torque may be negative (ForceEstimate::torque_sign_doubtful).
  ForceEstimate update(double time_s, double iu_a, double iv_a, double iw_a, double speed_rad_s,
                       double rotor_angle_rad);
  ForceEstimate update(double time_s, double iu_a, double iv_a, double iw_a, double speed_rad_s);
  /// The one or the other, as `rotor_angle_rad` holds an angle or not.
  ForceEstimate update(double time_s, double iu_a, double iv_a, double iw_a, double speed_rad_s,
                       std::optional<double> rotor_angle_rad) {
    return rotor_angle_rad ? update(time_s, iu_a, iv_a, iw_a, speed_rad_s, *rotor_angle_rad)
                           : update(time_s, iu_a, iv_a, iw_a, speed_rad_s);
  }
  void reset();

  const AxisCalibration& calibration() const { return cal_; }
  const EstimatorOptions& options() const { return options_; }
  /// The step of the first two samples (the one the filter is stated for), 0 before them.
  double first_step_s() const { return first_dt_; }

 private:
  void set_step(double dt_s);
  void set_fixed_variance();
  // The first step of the axis: kept, and the bandwidth checked against its Nyquist frequency.
  [[gnu::noinline]] void check_first_step(double dt_s);
  // update's body, with the rotor angle (kSigned) or without; one per form, so that neither
  // tests at run time which it is.
  template <bool kSigned>
  ForceEstimate estimate(double time_s, double iu_a, double iv_a, double iw_a, double speed_rad_s,
                         double rotor_angle_rad);
  AxisCalibration cal_;
  EstimatorOptions options_;
  AccelerationObserver observer_;
  double last_time_ = 0.0;
  bool started_ = false;
  bool step_checked_ = false;
  double sign_ = 1.0;
  // Per-step constants, recomputed when the step changes.
  double dt_ = -1.0, inv_dt_ = 0.0, first_dt_ = 0.0;
  double r_ = 0.0;                 // pole of Q for the step
  double var_current_gain_ = 1.0;  // variance of the filtered current term per unit white noise
  double var_obs_nm2_ = 0.0;       // variance of the filtered X·ω + J·Δω/Δt from speed noise
  // 3σ of J times the filtered acceleration from speed noise.
  double three_sigma_accel_torque_ = 0.0;
  double var_fixed_nm2_[2] = {0.0, 0.0};  // the step's constant variance: moving, standstill
  double prev_id_ = 0.0;                  // |Id| of the previous sample
  // Filter states: load torque over KBlf (N), |current| and acceleration (two first-order
  // stages each).
  double y1_ = 0.0, y2_ = 0.0, c1_ = 0.0, c2_ = 0.0, a1_ = 0.0, a2_ = 0.0;
  double prev_u_ = 0.0, prev_w_ = 0.0;
  // Per-calibration constants.
  double kt_ = 0.0, x_ = 0.0, tf_ = 0.0, j_ = 0.0, inv_k_ = 0.0, id_noise_ = 0.0;
  double id_square_factor_ = 1.0 / 3.0;  // Id² = (iu² + iv² + iw²)·this, for the measure
  double two_var_id_ = 0.0;  // 2σ_Id²
};

}  // namespace cutdyn
