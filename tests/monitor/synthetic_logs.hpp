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
