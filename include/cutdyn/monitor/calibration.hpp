// Calibration of the axis torque balance from logs [Zheng2012, eq. 5 and step 2];
// docs/models/monitor.md §3.
//
// Step 1 (idle runs, no cutting, several constant speeds of either sign): in the steady part
// of each run s·KT·Id − J·ε = Tnzm·sign(ω) + X·ω; least squares for Tnzm and X.
// Step 2 (loaded runs with a reference force F): s·KT·Id − X·ω − Tnzm·sign(ω) − J·ε = KBlf·F;
// least squares through the origin for KBlf, on steady windows as step 1.
// Both steps use the means over windows of `window_s` (the acceleration of a window is the
// slope of the least-squares line through its speeds), so that the residuals are close to
// independent and the uncertainties honest for coloured noise too.
#pragma once

#include <string>
#include <vector>

#include "cutdyn/monitor/axis_model.hpp"

namespace cutdyn {

/// One logged sample of one axis.
struct AxisSample {
  double time_s = 0.0;
  double iu_a = 0.0, iv_a = 0.0, iw_a = 0.0;
  double speed_rad_s = 0.0;
  double force_n = 0.0;  // reference force (step 2 only)
  // The electrical rotor angle θe, where the log has it: the torque current is then signed
  // (signed_equivalent_current), not the magnitude with the sign of the motion.
  bool has_rotor_angle = false;
  double rotor_angle_rad = 0.0;
};

/// s·Id of a sample: the signed equivalent current where it has the rotor angle, else
/// sign(ω)·Id (the motoring assumption, docs/models/monitor.md §2; +Id at ω = 0).
double torque_current_a(const AxisSample& sample, CurrentMeasure measure);

/// A log of one axis: samples in increasing time. Runs are separate logs (windows never
/// span two runs).
using AxisRun = std::vector<AxisSample>;

/// Standard uncertainties of the parameters (standard deviations; a covariance for the pair
/// Tnzm, X that step 1 fits together). Zero where a value was given, not fitted, unless the
/// caller sets it.
struct AxisUncertainty {
  double inertia_kg_m2 = 0.0;
  double torque_constant_nm_per_a = 0.0;
  double viscous_nm_s_per_rad = 0.0;
  double friction_nm = 0.0;
  double friction_viscous_covariance = 0.0;  // cov(Tnzm, X) [N·m · N·m·s/rad]
  double force_gain_m = 0.0;
};

/// What the estimator needs for one axis: the model, its uncertainties and the noise of the
/// measurements (measured in the idle runs, or given).
struct AxisCalibration {
  AxisModel model;
  AxisUncertainty sigma;
  double current_noise_a = 0.0;    // standard deviation of the equivalent current per sample
  double speed_noise_rad_s = 0.0;  // standard deviation of the measured speed per sample
  /// False when a value comes from elsewhere with no known uncertainty (the literature
  /// coefficients of zheng2012_calibration: another machine, units in doubt): `sigma` and the
  /// noise are then not the whole uncertainty, and the estimates say so (ForceEstimate).
  bool uncertainty_known = true;

  std::vector<std::string> validate() const;
};

/// `zheng2012_axis(axis)`: the source's coefficients, of the source's machine, with their
/// units in doubt (docs/models/monitor.md). Their uncertainty for any machine is unknown, so
/// `uncertainty_known` is false (docs/models/monitor.md §4.3); sigma and noise are zero.
AxisCalibration zheng2012_calibration(char axis);

struct CalibrationOptions {
  double window_s = 0.05;  // averaging window, > 0
  // A window is steady (step 1) when its speed changes by at most this fraction of its mean
  // speed across the window (slope·window), and its neighbours in the run are steady too.
  double steady_tolerance = 0.01;
  // Windows with any |ω| below this are not used (the direction of friction is unknown).
  double standstill_rad_s = 0.5;
  int min_samples_per_window = 4;

  std::vector<std::string> validate() const;
};

enum class CalibrationStatus {
  kSuccess,
  kTooFewWindows,  // fewer usable windows than parameters + 1
  kTooFewSpeeds,   // step 1: the speeds do not determine Tnzm and X (one speed, one sign)
  kNoForce,        // step 2: the reference force is zero in every window
  kNotFinite,      // a value of the logs is beyond what the fit can take (near overflow)
};
const char* to_string(CalibrationStatus status);

/// A least-squares fit and its quality.
struct FitReport {
  CalibrationStatus status = CalibrationStatus::kSuccess;
  std::string message;
  int windows = 0;                    // windows used (rows of the fit)
  int windows_rejected = 0;           // not steady, too short or at standstill
  int distinct_speeds = 0;            // step 1: speed groups differing by more than 2 %
  double r_squared = 0.0;             // 1 − SS_res/SS_tot
  double residual_rms_nm = 0.0;       // sqrt(SS_res/n), torque of the window means
  double residual_sigma_nm = 0.0;     // sqrt(SS_res/(n − p)), what the uncertainties use
  std::vector<std::string> warnings;  // e.g. X clamped to 0
};

struct IdleFit {
  FitReport report;
  double friction_nm = 0.0, viscous_nm_s_per_rad = 0.0;
  double friction_sigma_nm = 0.0, viscous_sigma = 0.0, covariance = 0.0;
  // Noise of the measurements within steady windows (pooled standard deviation of the
  // samples about each window's mean current and about its speed line).
  double current_noise_a = 0.0, speed_noise_rad_s = 0.0;
};

/// Step 1 for one axis. `model` gives J, KT and the measure (its X, Tnzm, KBlf are unused).
IdleFit fit_idle(const AxisModel& model, const std::vector<AxisRun>& runs,
                 const CalibrationOptions& options = {});

struct LoadFit {
  FitReport report;
  double force_gain_m = 0.0, force_gain_sigma_m = 0.0;
  // Part of force_gain_sigma_m that comes from the uncertainty of Tnzm and X (the rest from
  // the scatter of the fit).
  double force_gain_sigma_from_idle_m = 0.0;
};

/// Step 2 for one axis. `calibration` gives J, KT, X, Tnzm and the covariance of the last two
/// (propagated into the uncertainty of KBlf).
LoadFit fit_load(const AxisCalibration& calibration, const std::vector<AxisRun>& runs,
                 const CalibrationOptions& options = {});

}  // namespace cutdyn
