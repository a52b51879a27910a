// Cutting force from the motor current of a feed axis, sample by sample [Zheng2012, eq. 4];
// docs/models/monitor.md §4.
//
//   Fc = (s·KT·Id − X·ω̂ − Tnzm·sign(ω̂) − J·ε̂) / KBlf
//
// with ω̂ and ε̂ from an acceleration observer on the measured speed (AccelerationObserver: a
// fixed-gain alpha–beta filter, the steady-state Kalman filter of a constant-acceleration
// model, its two poles at exp(−2π·f_b·Δt)), not a raw difference. Each estimate carries its
// standard uncertainty (what it includes: docs/models/monitor.md §4.3).
#pragma once

#include <string>
#include <vector>

#include "cutdyn/monitor/calibration.hpp"

namespace cutdyn {

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
  void update(double speed_rad_s, double dt_s);
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

struct EstimatorOptions {
  double bandwidth_hz = 50.0;  // f_b of the acceleration observer, > 0
  // Below this |ω̂| the axis is at standstill: the motor torque keeps the sign of the last
  // motion (+ at first), the friction term is taken as 0 and its standard uncertainty
  // Tnzm/√3 (static friction anywhere in ±Tnzm) is added.
  double standstill_rad_s = 0.5;

  std::vector<std::string> validate() const;
};

struct ForceEstimate {
  double force_n = 0.0;  // Fc
  // Its standard uncertainty: the whole of it when `sigma_known`; otherwise only the part
  // the calibration's noise and sigma give (0 for the literature coefficients), a lower bound.
  double force_sigma_n = 0.0;
  double speed_rad_s = 0.0;   // ω̂
  double accel_rad_s2 = 0.0;  // ε̂
  bool standstill = false;
  bool sigma_known = true;  // false: the calibration's uncertainty is unknown
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
  ForceEstimate update(double time_s, double iu_a, double iv_a, double iw_a, double speed_rad_s);
  void reset();

  const AxisCalibration& calibration() const { return cal_; }
  const EstimatorOptions& options() const { return options_; }

 private:
  void set_step(double dt_s);
  AxisCalibration cal_;
  EstimatorOptions options_;
  AccelerationObserver observer_;
  double last_time_ = 0.0;
  bool started_ = false;
  bool step_checked_ = false;
  double sign_ = 1.0;
  // Per-step constants, recomputed when the step changes.
  double dt_ = -1.0;
  double var_obs_nm2_ = 0.0;  // variance of X·ω̂ + J·ε̂ from speed noise [N·m]²
  // Per-calibration constants.
  double kt_ = 0.0, x_ = 0.0, tf_ = 0.0, j_ = 0.0, inv_k_ = 0.0, id_noise_ = 0.0;
};

}  // namespace cutdyn
