#include "cutdyn/monitor/calibration.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <map>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn {

std::vector<std::string> AxisCalibration::validate() const {
  Validator v;
  v.merge(model.validate());
  const auto nonneg = [&](const char* field, double value, const char* unit) {
    v.require(value >= 0.0, field, value, unit, "must be >= 0");
  };
  nonneg("sigma.inertia_kg_m2", sigma.inertia_kg_m2, "kg·m²");
  nonneg("sigma.torque_constant_nm_per_a", sigma.torque_constant_nm_per_a, "N·m/A");
  nonneg("sigma.viscous_nm_s_per_rad", sigma.viscous_nm_s_per_rad, "N·m·s/rad");
  nonneg("sigma.friction_nm", sigma.friction_nm, "N·m");
  nonneg("sigma.force_gain_m", sigma.force_gain_m, "m");
  v.require(std::isfinite(sigma.friction_viscous_covariance), "sigma.friction_viscous_covariance",
            sigma.friction_viscous_covariance, "", "must be finite");
  nonneg("current_noise_a", current_noise_a, "A");
  nonneg("speed_noise_rad_s", speed_noise_rad_s, "rad/s");
  return v.problems();
}

AxisCalibration zheng2012_calibration(char axis) {
  AxisCalibration c;
  c.model = zheng2012_axis(axis);
  c.uncertainty_known = false;
  return c;
}

std::vector<std::string> CalibrationOptions::validate() const {
  Validator v("calibration");
  v.require_positive("window_s", window_s, "s");
  v.require(steady_tolerance >= 0.0, "steady_tolerance", steady_tolerance, "", "must be >= 0");
  v.require(standstill_rad_s >= 0.0, "standstill_rad_s", standstill_rad_s, "rad/s", "must be >= 0");
  v.require(min_samples_per_window >= 3, "min_samples_per_window", min_samples_per_window, "",
            "must be at least 3");
  return v.problems();
}

namespace {

bool all_finite(std::initializer_list<double> values) {
  return std::all_of(values.begin(), values.end(), [](double x) { return std::isfinite(x); });
}

// A fit that overflowed: a current, speed or force of the logs near the range of a double.
std::string not_finite_message(const std::string& step) {
  return step + ": the fit is not finite: a current, speed or force of the logs is beyond what "
                "it can take (a value near the range of a double); check the logs' units and "
                "columns";
}

}  // namespace

const char* to_string(CalibrationStatus status) {
  switch (status) {
    case CalibrationStatus::kSuccess:
      return "success";
    case CalibrationStatus::kTooFewWindows:
      return "too few windows";
    case CalibrationStatus::kTooFewSpeeds:
      return "too few speeds";
    case CalibrationStatus::kNoForce:
      return "no force";
    case CalibrationStatus::kNotFinite:
      return "not finite";
  }
  return "?";
}

double torque_current_a(const AxisSample& s, CurrentMeasure measure) {
  if (s.has_rotor_angle)
    return signed_equivalent_current(s.iu_a, s.iv_a, s.iw_a, s.rotor_angle_rad, measure);
  const double id = equivalent_current(s.iu_a, s.iv_a, s.iw_a, measure);
  return s.speed_rad_s < 0.0 ? -id : id;
}

namespace {

// Means over one window of one run.
struct Window {
  int n = 0;
  double speed = 0.0;        // mean ω
  double accel = 0.0;        // slope of the least-squares line ω(t)
  double accel_sigma = 0.0;  // its standard error
  double sign = 0.0;         // the common sign of ω (0: standstill or a change of sign)
  double current = 0.0;      // mean s·Id
  double torque = 0.0;       // mean s·KT·Id
  double force = 0.0;        // mean reference force
  double current_ss = 0.0;   // Σ(Id − mean)²
  double zero_ss = 0.0;      // Σ(i0 − mean)², i0 = (iu + iv + iw)/3 the zero-sequence current
  int stretch = 0;           // which run of consecutive used windows (one level) it belongs to
  double speed_ss = 0.0;     // Σ of squared residuals of ω about its line
  bool steady = false;
  // What the fits use: means with the weight w(t) = sin²(π(t − t_first)/(t_last − t_first)),
  // which is zero at both ends, so that the weighted mean of J·ε is exactly −J·∫w'ω/∫w (by
  // parts) for any load, periodic ripple included; the acceleration of each sample is the
  // central difference of its neighbours.
  double fit_speed = 0.0, fit_torque = 0.0, fit_force = 0.0, fit_accel = 0.0;
  double fit_current_abs = 0.0;  // weighted mean of |Id| where the current is a magnitude
  bool magnitude = false;        // no rotor angle: Id is a magnitude, biased up by noise
};

// Removes the noise bias from the windows' torque means (signed like the motion). The mean of
// a noisy magnitude is σ·M(a/σ) for a true current a (docs/models/monitor.md §1, at any
// signal-to-noise ratio), so its bias is b = m̄ − g(m̄), g = magnitude_from_mean. The bias
// depends on the level a only, which is the same in every window of a stretch (consecutive
// steady windows of one run: one speed, one load): b is evaluated once per stretch at its
// pooled mean magnitude m̄ and subtracted from each window. (Inverting each window's own mean
// would be biased itself where ν = a/σ is small: M is flat there, so a window's scatter moves
// the inverse a lot, and not symmetrically.)
//
// The correction is common to the windows of a stretch, so the scatter of the windows about
// the fit does not show its error: where ν is small g' = 1/M'(ν) is large (≈ 3 at ν = 0.6) and
// the stretch's level carries g'²·var(m̄) (var(m̄) = magnitude_variance·1.5/N for N samples
// under the sin² weights), and every stretch shares the error of σ. Both are returned and
// added to the fits' covariance (correction_covariance).
struct BiasCorrection {
  std::map<int, double> level_var_nm2;   // per stretch: var of KT·b from its pooled mean
  std::map<int, double> dtorque_dsigma;  // per stretch: ∂(KT·b)/∂σ, N·m/A
};

BiasCorrection correct_magnitude_bias(std::vector<Window>& rows, const AxisModel& m, double sigma) {
  BiasCorrection out;
  const double kt = m.torque_constant_nm_per_a;
  std::size_t first = 0;
  while (first < rows.size()) {
    std::size_t last = first;
    double sum = 0.0, count = 0.0;
    while (last < rows.size() && rows[last].stretch == rows[first].stretch) {
      if (rows[last].magnitude) {
        sum += rows[last].fit_current_abs * rows[last].n;
        count += rows[last].n;
      }
      ++last;
    }
    if (count > 0.0 && sigma > 0.0) {
      const double mean = sum / count;
      const MagnitudeBias b = magnitude_bias(mean, sigma);
      for (std::size_t k = first; k < last; ++k)
        if (rows[k].magnitude) rows[k].fit_torque -= rows[k].sign * kt * b.bias_a;
      const double var_mean = 1.5 * magnitude_variance(mean - b.bias_a, sigma) / count;
      const int id = rows[first].stretch;
      out.level_var_nm2[id] = kt * kt * b.d_mean * b.d_mean * var_mean;
      out.dtorque_dsigma[id] = kt * b.d_sigma;
    }
    first = last;
  }
  return out;
}

// The covariance the bias correction adds to a linear least-squares fit θ = inv·Aᵀy of the
// windows (A: one row per window), y_w carrying −sign_w·KT·b_s of its stretch s:
// inv·(Σ_s var_s·u_s·u_sᵀ + var(σ)·d·dᵀ)·inv, u_s = Σ_{w∈s} sign_w·A_w, d = Σ_s ∂(KT·b_s)/∂σ·u_s.
Eigen::MatrixXd correction_covariance(const std::vector<Window>& rows, const Eigen::MatrixXd& a,
                                      const Eigen::MatrixXd& inv, const BiasCorrection& c,
                                      double sigma_var) {
  const Eigen::Index p = a.cols();
  Eigen::MatrixXd middle = Eigen::MatrixXd::Zero(p, p);
  Eigen::VectorXd d = Eigen::VectorXd::Zero(p);
  std::map<int, Eigen::VectorXd> u;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    if (!rows[k].magnitude || !c.level_var_nm2.count(rows[k].stretch)) continue;
    auto [it, fresh] = u.try_emplace(rows[k].stretch, Eigen::VectorXd::Zero(p));
    it->second += rows[k].sign * a.row(static_cast<Eigen::Index>(k)).transpose();
  }
  for (const auto& [id, us] : u) {
    middle += c.level_var_nm2.at(id) * us * us.transpose();
    d += c.dtorque_dsigma.at(id) * us;
  }
  middle += sigma_var * d * d.transpose();
  return inv * middle * inv;
}

// σ of the equivalent current from the pooled scatter of |Id| in steady windows. Where the
// current is a magnitude, its scatter is σ²·V(ν) with V = 3 + ν² − M(ν)², which falls to 3 −
// 8/π ≈ 0.45 as ν = a/σ → 0: σ² = Σ SS_w / Σ (n_w − 1)·V(ν_w), ν_w from each window's mean
// magnitude, iterated from V = 1 (a fixed point; at a high signal-to-noise ratio V = 1 and
// the scatter is σ² itself).
double current_noise_from_scatter(const std::vector<Window>& rows, double current_ss, double dof) {
  if (!(dof > 0.0)) return 0.0;
  double sigma = std::sqrt(current_ss / dof);
  for (int iteration = 0; iteration < 50 && sigma > 0.0; ++iteration) {
    double expected = 0.0;  // Σ (n_w − 1)·V(ν_w)
    for (const Window& w : rows) {
      const double mean = std::abs(w.current);
      const double a = w.magnitude ? magnitude_from_mean(mean, sigma) : mean;
      const double v = w.magnitude ? magnitude_variance(a, sigma) / (sigma * sigma) : 1.0;
      expected += (w.n - 1.0) * v;
    }
    const double next = std::sqrt(current_ss / expected);
    const bool done = std::abs(next - sigma) <= 1e-10 * sigma;
    sigma = next;
    if (done) break;
  }
  return sigma;
}

// σ of the equivalent current. The true phase currents of a three-phase motor sum to zero, so
// where the three are measured with independent noise σ_ph the zero-sequence current i0 =
// (iu + iv + iw)/3 is noise alone, of variance σ_ph²/3 whatever the load: σ_ph² = 3·(pooled
// scatter of i0) is then exact at any signal-to-noise ratio, which the noise-bias correction
// needs (at ν = a/σ ≈ 0.5 a 3 % error in σ moves a by a third). Where the phases sum to zero
// (one computed from the other two) the scatter of |Id| stands in, and a warning says so if
// the current is then within three noise σ somewhere.
double current_noise_of(const std::vector<Window>& rows, const AxisModel& m,
                        std::vector<std::string>& warnings, double& variance) {
  double current_ss = 0.0, zero_ss = 0.0, dof = 0.0;
  for (const Window& w : rows) {
    current_ss += w.current_ss;
    zero_ss += w.zero_ss;
    dof += w.n - 1.0;
  }
  variance = 0.0;
  if (!(dof > 0.0)) return 0.0;
  // Either estimate is a pooled variance of dof degrees of freedom: var(σ̂) = σ²/(2·dof).
  const auto with_variance = [&](double sigma) {
    variance = sigma * sigma / (2.0 * dof);
    return sigma;
  };
  // The zero-sequence noise against the raw scatter of |Id| (the iterated estimate below is
  // needed only where the zero sequence is missing).
  const double zero_sequence = equivalent_current_sigma(std::sqrt(3.0 * zero_ss / dof), m.measure);
  if (zero_sequence > 0.01 * std::sqrt(current_ss / dof)) return with_variance(zero_sequence);
  const double scatter = current_noise_from_scatter(rows, current_ss, dof);
  double weakest = std::numeric_limits<double>::infinity();
  for (const Window& w : rows)
    if (w.magnitude) weakest = std::min(weakest, std::abs(w.current));
  if (weakest < 3.0 * scatter)
    warnings.push_back(
        "the phase currents sum to zero (one of them computed?), so the current noise (" +
        format_value(scatter) +
        " A) is estimated from the scatter of |Id|; the smallest mean "
        "current, " +
        format_value(weakest) +
        " A, is within three noise sigma of zero, where the "
        "correction of the magnitude's noise bias depends on that estimate: log the rotor angle "
        "for a signed current without that bias");
  return with_variance(scatter);
}

// Robust standard deviation of the white noise on the measured speed of one run, from the
// second differences of the samples (zero for any straight piece of the speed, so ramps,
// holds and slow transients do not inflate it): each difference, normalised to unit variance
// for white noise, and σ = 1.4826·median|d| (the median absolute deviation; a corner or a
// spike moves it little).
double speed_noise_of(const AxisRun& run) {
  std::vector<double> d;
  d.reserve(run.size());
  for (std::size_t k = 1; k + 1 < run.size(); ++k) {
    const double h0 = run[k].time_s - run[k - 1].time_s, h1 = run[k + 1].time_s - run[k].time_s;
    const double norm = std::sqrt(h1 * h1 + (h0 + h1) * (h0 + h1) + h0 * h0);
    if (!(norm > 0.0)) continue;
    d.push_back(std::abs(h1 * run[k - 1].speed_rad_s - (h0 + h1) * run[k].speed_rad_s +
                         h0 * run[k + 1].speed_rad_s) /
                norm);
  }
  if (d.empty()) return 0.0;
  const auto mid = d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2);
  std::nth_element(d.begin(), mid, d.end());
  return 1.4826 * *mid;
}

// Upper 99.9 % point of χ²(k)/k (Wilson–Hilferty; within 1 % for k >= 2).
double chi2_999_over_k(double k) {
  const double a = 2.0 / (9.0 * k);
  const double c = 1.0 - a + 3.0902 * std::sqrt(a);
  return c * c * c;
}

std::vector<Window> windows_of(const AxisModel& m, const AxisRun& run,
                               const CalibrationOptions& o) {
  std::vector<Window> out;
  const double noise = speed_noise_of(run);
  std::size_t i = 0;
  while (i < run.size()) {
    std::size_t j = i;
    const double t_end = run[i].time_s + o.window_s;
    while (j < run.size() && run[j].time_s < t_end) ++j;
    Window w;
    w.n = static_cast<int>(j - i);
    if (w.n >= o.min_samples_per_window) {
      double t_mean = 0.0, moving_sign = 0.0;
      bool standstill = false;
      for (std::size_t k = i; k < j; ++k) {
        const AxisSample& s = run[k];
        const double id = torque_current_a(s, m.measure);
        const double sg = motion_sign(s.speed_rad_s);
        if (std::abs(s.speed_rad_s) < o.standstill_rad_s ||
            (moving_sign != 0.0 && sg != moving_sign))
          standstill = true;
        moving_sign = sg;
        t_mean += s.time_s;
        w.speed += s.speed_rad_s;
        w.current += id;
        w.torque += m.torque_constant_nm_per_a * id;
        w.force += s.force_n;
      }
      const double n = w.n;
      t_mean /= n;
      w.speed /= n;
      w.current /= n;
      w.torque /= n;
      w.force /= n;
      w.sign = standstill ? 0.0 : moving_sign;
      double stt = 0.0, stw = 0.0, zero_sum = 0.0, zero_sq = 0.0;
      for (std::size_t k = i; k < j; ++k) {
        const double dt = run[k].time_s - t_mean;
        stt += dt * dt;
        stw += dt * (run[k].speed_rad_s - w.speed);
        const double id = torque_current_a(run[k], m.measure);
        w.current_ss += (id - w.current) * (id - w.current);
        const double i0 = (run[k].iu_a + run[k].iv_a + run[k].iw_a) / 3.0;
        zero_sum += i0;
        zero_sq += i0 * i0;
      }
      w.zero_ss = std::max(zero_sq - zero_sum * zero_sum / n, 0.0);
      w.accel = stt > 0.0 ? stw / stt : 0.0;
      for (std::size_t k = i; k < j; ++k) {
        const double r = run[k].speed_rad_s - w.speed - w.accel * (run[k].time_s - t_mean);
        w.speed_ss += r * r;
      }
      if (w.n >= 3) {
        const double t0 = run[i].time_s, span = run[j - 1].time_s - t0;
        double sw = 0.0;
        for (std::size_t k = i + 1; k + 1 < j; ++k) {
          const double sn = std::sin(units::kPi * (run[k].time_s - t0) / span);
          const double wk = sn * sn;
          const AxisSample& s = run[k];
          sw += wk;
          w.fit_speed += wk * s.speed_rad_s;
          const double ic = torque_current_a(s, m.measure);
          w.fit_torque += wk * m.torque_constant_nm_per_a * ic;
          w.fit_current_abs += wk * std::abs(ic);
          w.magnitude = !s.has_rotor_angle;
          w.fit_force += wk * s.force_n;
          w.fit_accel += wk * (run[k + 1].speed_rad_s - run[k - 1].speed_rad_s) /
                         (run[k + 1].time_s - run[k - 1].time_s);
        }
        if (sw > 0.0) {
          w.fit_speed /= sw;
          w.fit_torque /= sw;
          w.fit_force /= sw;
          w.fit_accel /= sw;
          w.fit_current_abs /= sw;
        }
      }
      // The standard error of the slope for the run's white speed noise (not this window's
      // scatter, which a transient inflates).
      w.accel_sigma = stt > 0.0 ? noise / std::sqrt(stt) : 0.0;
      // Steady = acceleration and speed within limits over the whole window:
      // (1) the speed line changes across the window by at most the tolerance of the mean
      //     speed, allowing for three standard errors of its slope;
      // (2) the speed stays on that line: the scatter about it is what the white noise
      //     explains (below the 99.9 % point of χ²), plus a tenth of the tolerance. A window
      //     in which the speed still overshoots, rings or settles after a speed change fails
      //     (2) even where its line is flat, and J·(its slope) would not be its mean J·ε.
      const double change = std::abs(w.accel) * o.window_s;
      const double allowed = 0.1 * o.steady_tolerance * std::abs(w.speed);
      const double scatter_limit =
          n > 2.0 ? (n - 2.0) * (noise * noise * chi2_999_over_k(n - 2.0) + allowed * allowed)
                  : 0.0;
      w.steady =
          w.sign != 0.0 &&
          change <= o.steady_tolerance * std::abs(w.speed) + 3.0 * w.accel_sigma * o.window_s &&
          w.speed_ss <= scatter_limit;
      out.push_back(w);
    }
    i = j;
  }
  return out;
}

// The steady windows of the runs, each marked with its stretch (a new one at each run and
// after each window left out), and the count of those left out. A window is used if it is
// steady and so are its neighbours: the edges of a speed change are left out (J·ε of a window
// that holds a corner of the speed profile is not its speed line's slope).
std::vector<Window> used_windows(const AxisModel& m, const std::vector<AxisRun>& runs,
                                 const CalibrationOptions& o, int& rejected,
                                 std::vector<double>* rejected_ripple = nullptr) {
  std::vector<Window> rows;
  int stretch = 0;
  for (const AxisRun& run : runs) {
    const std::vector<Window> ws = windows_of(m, run, o);
    ++stretch;
    for (std::size_t k = 0; k < ws.size(); ++k) {
      const bool use =
          ws[k].steady && (k == 0 || ws[k - 1].steady) && (k + 1 == ws.size() || ws[k + 1].steady);
      if (!use) {
        ++rejected;
        ++stretch;
        // The RMS scatter of a moving window's speed about its line, relative to its mean.
        if (rejected_ripple && ws[k].sign != 0.0 && ws[k].n > 2)
          rejected_ripple->push_back(std::sqrt(ws[k].speed_ss / ws[k].n) / std::abs(ws[k].speed));
        continue;
      }
      rows.push_back(ws[k]);
      rows.back().stretch = stretch;
    }
  }
  return rows;
}

int distinct_speeds(std::vector<double> speeds) {
  std::sort(speeds.begin(), speeds.end());
  int groups = 0;
  double last = 0.0;
  for (double s : speeds) {
    if (groups == 0 || s - last > 0.02 * std::max(s, 1e-9)) ++groups;
    last = s;
  }
  return groups;
}

}  // namespace

IdleFit fit_idle(const AxisModel& m, const std::vector<AxisRun>& runs,
                 const CalibrationOptions& o) {
  Validator v;
  v.merge(o.validate());
  v.require_positive("torque_constant_nm_per_a", m.torque_constant_nm_per_a, "N·m/A");
  v.require(m.inertia_kg_m2 >= 0.0, "inertia_kg_m2", m.inertia_kg_m2, "kg·m²", "must be >= 0");
  v.throw_if_any();

  IdleFit fit;
  std::vector<Window> rows = used_windows(m, runs, o, fit.report.windows_rejected);
  double speed_ss = 0.0, speed_dof = 0.0;
  for (const Window& w : rows) {
    speed_ss += w.speed_ss;
    speed_dof += w.n - 2.0;
  }
  FitReport& r = fit.report;
  r.windows = static_cast<int>(rows.size());
  std::vector<double> magnitudes;
  for (const Window& w : rows) magnitudes.push_back(std::abs(w.speed));
  r.distinct_speeds = distinct_speeds(magnitudes);
  double noise_var = 0.0;
  fit.current_noise_a = current_noise_of(rows, m, fit.report.warnings, noise_var);
  if (speed_dof > 0.0) fit.speed_noise_rad_s = std::sqrt(speed_ss / speed_dof);
  const BiasCorrection bias = correct_magnitude_bias(rows, m, fit.current_noise_a);
  if (r.windows < 3) {
    r.status = CalibrationStatus::kTooFewWindows;
    r.message = "step 1 needs at least 3 steady windows; found " + std::to_string(r.windows) +
                " (" + std::to_string(r.windows_rejected) +
                " rejected as not steady or at standstill)";
    return fit;
  }
  if (r.distinct_speeds < 2) {
    r.status = CalibrationStatus::kTooFewSpeeds;
    r.message = "step 1 needs steady runs at two or more different speed magnitudes; found " +
                std::to_string(r.distinct_speeds);
    return fit;
  }

  // [Zheng2012, eq. 5] with friction opposing motion: s·KT·Id − J·ε = Tnzm·sign(ω) + X·ω.
  const Eigen::Index n = r.windows;
  Eigen::MatrixXd a(n, 2);
  Eigen::VectorXd y(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const Window& w = rows[static_cast<std::size_t>(k)];
    a(k, 0) = w.sign;
    a(k, 1) = w.fit_speed;
    y(k) = w.fit_torque - m.inertia_kg_m2 * w.fit_accel;
  }
  const Eigen::Matrix2d ata = a.transpose() * a;
  const Eigen::Matrix2d inv = ata.inverse();
  const Eigen::Vector2d theta = inv * (a.transpose() * y);
  const Eigen::VectorXd res = y - a * theta;
  const double ss_res = res.squaredNorm();
  const double ss_tot = (y.array() - y.mean()).square().sum();
  r.r_squared = ss_tot > 0.0 ? 1.0 - ss_res / ss_tot : 1.0;
  r.residual_rms_nm = std::sqrt(ss_res / static_cast<double>(n));
  const double var = ss_res / static_cast<double>(n - 2);
  r.residual_sigma_nm = std::sqrt(var);
  fit.friction_nm = theta(0);
  fit.viscous_nm_s_per_rad = theta(1);
  const Eigen::MatrixXd extra = correction_covariance(rows, a, inv, bias, noise_var);
  fit.friction_sigma_nm = std::sqrt(var * inv(0, 0) + extra(0, 0));
  fit.viscous_sigma = std::sqrt(var * inv(1, 1) + extra(1, 1));
  fit.covariance = var * inv(0, 1) + extra(0, 1);
  // Tnzm ≥ 0 and X ≥ 0 (friction cannot feed the axis): fitted under those bounds. Least squares
  // over the quadrant is convex, so when the free optimum lies outside it the constrained one
  // is the best of the fits inside it with one coefficient at 0 (the other refitted alone) or
  // both, whatever σ is (noise-free logs of an axis without viscous loss give σ ≈ 0 and a free
  // X a rounding or model error below 0). A coefficient held keeps the free fit's σ and adds
  // how far the logs pulled it below the bound (the truth may lie up to there); the other's σ is
  // that of its fit alone, the covariance 0 (docs/models/monitor.md, "X at its bound").
  if (fit.friction_nm < 0.0 || fit.viscous_nm_s_per_rad < 0.0) {
    struct Held {
      double t, x;
      bool hold_t, hold_x;
    };
    const auto ss_of = [&](const Held& h) {
      return (y - a.col(0) * h.t - a.col(1) * h.x).squaredNorm();
    };
    const double sww = a.col(1).squaredNorm();
    std::vector<Held> inside{{0.0, 0.0, true, true}};
    if (const double t = a.col(0).dot(y) / static_cast<double>(n); t >= 0.0)  // sign² = 1
      inside.push_back({t, 0.0, false, true});
    if (const double x = sww > 0.0 ? a.col(1).dot(y) / sww : 0.0; x >= 0.0)
      inside.push_back({0.0, x, true, false});
    const Held best =
        *std::min_element(inside.begin(), inside.end(),
                          [&](const Held& p, const Held& q) { return ss_of(p) < ss_of(q); });
    const auto held_warning = [&](const std::string& what, const std::string& unit, double free,
                                  double sigma, const std::string& other, const std::string& none) {
      const bool within = free >= -3.0 * sigma;
      r.warnings.push_back(
          what + ", fitted freely, is " + format_value(free) + " " + unit +
          " (σ = " + format_value(sigma) + "): held at its bound 0, " + other +
          (within ? " (within 3σ of 0: the axis shows no " + none + ")"
                  : std::string(" (more than 3σ below 0: the idle logs and the model disagree; "
                                "check the inertia J, KT and the steady windows)")));
    };
    if (best.hold_x)
      held_warning("the viscous coefficient X", "N·m·s/rad", theta(1), fit.viscous_sigma,
                   best.hold_t ? "Tnzm held too" : "Tnzm refitted alone", "viscous loss");
    if (best.hold_t)
      held_warning("the Coulomb friction Tnzm", "N·m", theta(0), fit.friction_sigma_nm,
                   best.hold_x ? "X held too" : "X refitted alone", "Coulomb friction");
    const double ss1 = ss_of(best);
    const int kept = (best.hold_t ? 0 : 1) + (best.hold_x ? 0 : 1);
    const double var1 = ss1 / static_cast<double>(n - kept);
    // The coefficient refitted alone: its σ from that one-column fit.
    const auto alone_sigma = [&](Eigen::Index column) {
      const double norm = a.col(column).squaredNorm();
      const Eigen::MatrixXd inv1 = Eigen::MatrixXd::Constant(1, 1, 1.0 / norm);
      const Eigen::MatrixXd extra1 =
          correction_covariance(rows, a.middleCols(column, 1), inv1, bias, noise_var);
      return std::sqrt(var1 / norm + extra1(0, 0));
    };
    fit.friction_sigma_nm =
        best.hold_t ? std::hypot(fit.friction_sigma_nm, std::min(theta(0), 0.0)) : alone_sigma(0);
    fit.viscous_sigma =
        best.hold_x ? std::hypot(fit.viscous_sigma, std::min(theta(1), 0.0)) : alone_sigma(1);
    fit.friction_nm = best.t;
    fit.viscous_nm_s_per_rad = best.x;
    fit.covariance = 0.0;
    r.residual_sigma_nm = std::sqrt(var1);
    r.residual_rms_nm = std::sqrt(ss1 / static_cast<double>(n));
  }
  if (!all_finite({fit.friction_nm, fit.viscous_nm_s_per_rad, fit.friction_sigma_nm,
                   fit.viscous_sigma, fit.covariance, fit.current_noise_a, fit.speed_noise_rad_s,
                   r.r_squared, r.residual_rms_nm, r.residual_sigma_nm})) {
    r.status = CalibrationStatus::kNotFinite;
    r.message = not_finite_message("step 1");
    return fit;
  }
  r.message = "step 1: " + std::to_string(r.windows) + " steady windows at " +
              std::to_string(r.distinct_speeds) + " speeds";
  return fit;
}

LoadFit fit_load(const AxisCalibration& c, const std::vector<AxisRun>& runs,
                 const CalibrationOptions& o) {
  Validator v;
  v.merge(o.validate());
  const AxisModel& m = c.model;
  v.require_positive("torque_constant_nm_per_a", m.torque_constant_nm_per_a, "N·m/A");
  v.throw_if_any();

  LoadFit fit;
  FitReport& r = fit.report;
  std::vector<double> ripple;
  std::vector<Window> rows = used_windows(m, runs, o, r.windows_rejected, &ripple);
  r.windows = static_cast<int>(rows.size());
  const BiasCorrection bias = correct_magnitude_bias(rows, m, c.current_noise_a);
  if (r.windows < 2) {
    r.status = CalibrationStatus::kTooFewWindows;
    r.message = "step 2 needs at least 2 steady windows; found " + std::to_string(r.windows) +
                " (" + std::to_string(r.windows_rejected) +
                " rejected as not steady or at standstill)";
    if (!ripple.empty()) {
      // Criterion (2) of a steady window allows a scatter of 0.1·steady_tolerance of the
      // speed: a periodic cut that ripples the speed needs ten times its ripple. The sin²-
      // weighted means stay exact for such a ripple (docs/models/monitor.md §3).
      const auto mid = ripple.begin() + static_cast<std::ptrdiff_t>(ripple.size() / 2);
      std::nth_element(ripple.begin(), mid, ripple.end());
      char text[240];
      std::snprintf(text, sizeof text,
                    "; the speed of the rejected moving windows scatters about its line by %.2g %% "
                    "of its mean (median): if it ripples periodically under a cut, a steady "
                    "tolerance (steady_tolerance) of %.2f or more accepts those windows",
                    100.0 * *mid, std::ceil(12.0 * *mid * 100.0) / 100.0);
      r.message += text;
    }
    return fit;
  }
  // Step 2: y = s·KT·Id − X·ω − Tnzm·sign(ω) − J·ε = KBlf·F, through the origin.
  double sxx = 0.0, sxy = 0.0, sxw = 0.0, sxs = 0.0, sxt = 0.0, sxa = 0.0, ymean = 0.0;
  std::vector<double> y(rows.size());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const Window& w = rows[k];
    y[k] = w.fit_torque - m.viscous_nm_s_per_rad * w.fit_speed - m.friction_nm * w.sign -
           m.inertia_kg_m2 * w.fit_accel;
    sxx += w.fit_force * w.fit_force;
    sxy += w.fit_force * y[k];
    sxw += w.fit_force * w.fit_speed;
    sxs += w.fit_force * w.sign;
    sxt += w.fit_force * w.fit_torque;
    sxa += w.fit_force * w.fit_accel;
    ymean += y[k];
  }
  ymean /= static_cast<double>(rows.size());
  if (!(sxx > 0.0)) {
    r.status = CalibrationStatus::kNoForce;
    r.message = "step 2: the reference force is zero in every window";
    return fit;
  }
  const double k = sxy / sxx;
  double ss_res = 0.0, ss_tot = 0.0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ss_res += (y[i] - k * rows[i].fit_force) * (y[i] - k * rows[i].fit_force);
    ss_tot += (y[i] - ymean) * (y[i] - ymean);
  }
  const double n = static_cast<double>(rows.size());
  r.r_squared = ss_tot > 0.0 ? 1.0 - ss_res / ss_tot : 1.0;
  r.residual_rms_nm = std::sqrt(ss_res / n);
  r.residual_sigma_nm = std::sqrt(ss_res / (n - 1.0));
  // The scatter about the fit, and the error of the noise-bias correction common to each
  // stretch (the calibration's σ of the current noise is taken as exact here: its own error
  // matters where the current is within a few σ of zero, which loaded runs are not).
  Eigen::MatrixXd forces(static_cast<Eigen::Index>(rows.size()), 1);
  for (std::size_t i = 0; i < rows.size(); ++i)
    forces(static_cast<Eigen::Index>(i), 0) = rows[i].fit_force;
  const double var_bias = correction_covariance(
      rows, forces, Eigen::MatrixXd::Constant(1, 1, 1.0 / sxx), bias, 0.0)(0, 0);
  const double var_fit = ss_res / (n - 1.0) / sxx + var_bias;
  // Propagated from step 1 and the given constants: K = Σ F·y / Σ F², y linear in them.
  const double g_x = -sxw / sxx, g_t = -sxs / sxx;
  const double g_kt = sxt / m.torque_constant_nm_per_a / sxx, g_j = -sxa / sxx;
  const AxisUncertainty& u = c.sigma;
  const double var_idle = g_x * g_x * u.viscous_nm_s_per_rad * u.viscous_nm_s_per_rad +
                          g_t * g_t * u.friction_nm * u.friction_nm +
                          2.0 * g_x * g_t * u.friction_viscous_covariance +
                          g_kt * g_kt * u.torque_constant_nm_per_a * u.torque_constant_nm_per_a +
                          g_j * g_j * u.inertia_kg_m2 * u.inertia_kg_m2;
  fit.force_gain_m = k;
  fit.force_gain_sigma_from_idle_m = std::sqrt(std::max(0.0, var_idle));
  fit.force_gain_sigma_m = std::sqrt(var_fit + std::max(0.0, var_idle));
  if (!all_finite({fit.force_gain_m, fit.force_gain_sigma_m, fit.force_gain_sigma_from_idle_m,
                   r.r_squared, r.residual_rms_nm, r.residual_sigma_nm})) {
    r.status = CalibrationStatus::kNotFinite;
    r.message = not_finite_message("step 2");
    return fit;
  }
  r.message = "step 2: " + std::to_string(r.windows) + " steady windows";
  return fit;
}

}  // namespace cutdyn
