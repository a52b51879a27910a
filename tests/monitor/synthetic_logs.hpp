// Synthetic servo logs for the monitor tests: a speed profile of ramps and holds, the force
// on the axis, and the phase currents the torque balance needs (axis_model.hpp), with
// optional white noise on each phase current and on the measured speed.
#pragma once

#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cutdyn/core/units.hpp"
#include "cutdyn/monitor/calibration.hpp"

namespace cutdyn::testing {

/// Ramp (constant acceleration) from the previous speed to `speed` in `ramp_s`, then hold
/// it for `hold_s`; `force_n` acts during the hold.
struct Segment {
  double speed_rad_s = 0.0;
  double hold_s = 0.5;
  double force_n = 0.0;
  double ramp_s = 0.1;
};

struct LogNoise {
  double phase_current_a = 0.0;  // per phase
  double speed_rad_s = 0.0;
};

/// The log of one axis, sampled every `dt` from t = 0, starting at rest (or at the first
/// segment's speed when `start_at_speed`).
inline AxisRun synthetic_run(const AxisModel& m, const std::vector<Segment>& segments,
                             double dt = 1e-3, LogNoise noise = {}, unsigned seed = 1,
                             bool start_at_speed = false) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  AxisRun run;
  double w0 = start_at_speed && !segments.empty() ? segments.front().speed_rad_s : 0.0;
  double t0 = 0.0, angle = 0.0;
  const double pole_pairs = 4.0;
  long long k = 0;
  for (const Segment& s : segments) {
    const double ramp = (start_at_speed && &s == &segments.front()) ? 0.0 : s.ramp_s;
    const double end = t0 + ramp + s.hold_s;
    for (double t = static_cast<double>(k) * dt; t < end - 1e-12;
         t = static_cast<double>(++k) * dt) {
      double w = s.speed_rad_s, eps = 0.0, f = s.force_n;
      if (ramp > 0.0 && t < t0 + ramp) {
        eps = (s.speed_rad_s - w0) / ramp;
        w = w0 + eps * (t - t0);
        f = 0.0;
      }
      const double id = m.equivalent_current_a(f, w, eps);
      angle += pole_pairs * w * dt;
      const double peak = m.measure == CurrentMeasure::kRms ? std::sqrt(2.0) * id : id;
      AxisSample a;
      a.time_s = t;
      a.iu_a = peak * std::cos(angle) + noise.phase_current_a * gauss(rng);
      a.iv_a = peak * std::cos(angle - units::kTwoPi / 3) + noise.phase_current_a * gauss(rng);
      a.iw_a = peak * std::cos(angle + units::kTwoPi / 3) + noise.phase_current_a * gauss(rng);
      a.speed_rad_s = w + noise.speed_rad_s * gauss(rng);
      a.force_n = f;
      run.push_back(a);
    }
    w0 = s.speed_rad_s;
    t0 = end;
  }
  return run;
}

/// Idle runs at five speeds of both signs, as calibration step 1 wants.
inline std::vector<Segment> idle_profile(double hold_s = 0.5) {
  return {
      {20.0, hold_s}, {60.0, hold_s}, {120.0, hold_s}, {-40.0, hold_s, 0.0, 0.2}, {-150.0, hold_s}};
}

/// A loaded run at 50 rad/s with force levels (step 2).
inline std::vector<Segment> loaded_profile(double hold_s = 0.3) {
  return {{50.0, hold_s, 0.0},
          {50.0, hold_s, 1500.0, 0.0},
          {50.0, hold_s, 4000.0, 0.0},
          {80.0, hold_s, 2500.0},
          {-60.0, hold_s, -3000.0, 0.2}};
}

/// The run as the CSV `monitor` reads (with a force_n column).
inline std::string to_csv(const AxisRun& run, const std::string& axis, bool with_force = false) {
  std::ostringstream s;
  s.precision(17);
  s << "time_s,axis,iu_a,iv_a,iw_a,speed_rad_s" << (with_force ? ",force_n" : "") << "\n";
  for (const AxisSample& a : run) {
    s << a.time_s << "," << axis << "," << a.iu_a << "," << a.iv_a << "," << a.iw_a << ","
      << a.speed_rad_s;
    if (with_force) s << "," << a.force_n;
    s << "\n";
  }
  return s.str();
}

}  // namespace cutdyn::testing

namespace cutdyn::testing {

/// A speed-controlled axis (a second-order speed loop of natural frequency `loop_hz` and
/// damping `loop_damping`) following a reference that ramps at `accel_rad_s2` from one speed
/// of `speeds_rad_s` to the next and holds each for `hold_s`. Unlike synthetic_run the speed
/// lags the ramp, overshoots and rings before it settles, as a servo axis does; the currents
/// are those of the torque balance (magnitude of J·ε + X·ω + Tnzm·sign ω, idle), with white
/// noise as in synthetic_run.
inline AxisRun servo_run(const AxisModel& m, const std::vector<double>& speeds_rad_s,
                         double accel_rad_s2, double hold_s, double loop_hz, double loop_damping,
                         double dt = 1e-3, LogNoise noise = {}, unsigned seed = 1) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  // The reference: ramps and holds.
  std::vector<double> t_knot{0.0}, w_knot{0.0};
  for (double s : speeds_rad_s) {
    t_knot.push_back(t_knot.back() + std::abs(s - w_knot.back()) / accel_rad_s2);
    w_knot.push_back(s);
    t_knot.push_back(t_knot.back() + hold_s);
    w_knot.push_back(s);
  }
  const auto reference = [&](double t) {
    for (std::size_t i = 1; i < t_knot.size(); ++i)
      if (t <= t_knot[i])
        return t_knot[i] > t_knot[i - 1]
                   ? w_knot[i - 1] + (w_knot[i] - w_knot[i - 1]) * (t - t_knot[i - 1]) /
                                         (t_knot[i] - t_knot[i - 1])
                   : w_knot[i];
    return w_knot.back();
  };
  const double wn = units::kTwoPi * loop_hz;
  // ω'' = ωn²(ω_ref − ω) − 2ζωn·ω', by RK4 with 20 sub-steps per sample.
  const auto deriv = [&](double t, double w, double e, double& dw, double& de) {
    dw = e;
    de = wn * wn * (reference(t) - w) - 2.0 * loop_damping * wn * e;
  };
  AxisRun run;
  double w = 0.0, e = 0.0, angle = 0.0;
  const int sub = 20;
  const double h = dt / sub;
  const double pole_pairs = 4.0;
  for (long long k = 0; static_cast<double>(k) * dt < t_knot.back(); ++k) {
    const double t = static_cast<double>(k) * dt;
    const double id = m.equivalent_current_a(0.0, w, e);
    const double peak = m.measure == CurrentMeasure::kRms ? std::sqrt(2.0) * id : id;
    AxisSample a;
    a.time_s = t;
    a.iu_a = peak * std::cos(angle) + noise.phase_current_a * gauss(rng);
    a.iv_a = peak * std::cos(angle - units::kTwoPi / 3) + noise.phase_current_a * gauss(rng);
    a.iw_a = peak * std::cos(angle + units::kTwoPi / 3) + noise.phase_current_a * gauss(rng);
    a.speed_rad_s = w + noise.speed_rad_s * gauss(rng);
    run.push_back(a);
    for (int s = 0; s < sub; ++s) {
      const double ts = t + s * h;
      double k1w, k1e, k2w, k2e, k3w, k3e, k4w, k4e;
      deriv(ts, w, e, k1w, k1e);
      deriv(ts + h / 2, w + h / 2 * k1w, e + h / 2 * k1e, k2w, k2e);
      deriv(ts + h / 2, w + h / 2 * k2w, e + h / 2 * k2e, k3w, k3e);
      deriv(ts + h, w + h * k3w, e + h * k3e, k4w, k4e);
      angle += pole_pairs * h * w;
      w += h / 6 * (k1w + 2 * k2w + 2 * k3w + k4w);
      e += h / 6 * (k1e + 2 * k2e + 2 * k3e + k4e);
    }
  }
  return run;
}

}  // namespace cutdyn::testing
