#include "cutdyn/forces/duty_cycle.hpp"

#include <algorithm>
#include <cmath>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/detail/roots.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn {

using units::kTwoPi;

bool ContactWindow::in_contact(double t) const {
  if (duty_cycle >= 1.0) return true;
  double phase = std::fmod(t - start_s, period_s);
  if (phase < 0.0) phase += period_s;
  return phase < duty_cycle * period_s;
}

double ContactWindow::mean(double t0, double t1) const {
  if (duty_cycle >= 1.0) return 1.0;
  // Contact time in [start, s) measured from a period start: C(s) = T·floor(s/T)·r + min(s mod T,
  // rT).
  const auto contact_until = [&](double t) {
    const double s = t - start_s;
    const double periods = std::floor(s / period_s);
    const double rest = s - periods * period_s;
    return periods * duty_cycle * period_s + std::min(rest, duty_cycle * period_s);
  };
  return (contact_until(t1) - contact_until(t0)) / (t1 - t0);
}

ContactWindow DutyCycle::window() const {
  if (!separates) return ContactWindow{period_s, 1.0, 0.0};
  double start = (contact_phase_rad - kTwoPi) / kTwoPi * period_s;
  if (start < 0.0) start += period_s;
  return ContactWindow{period_s, ratio, start};
}

DutyCycle duty_cycle(double v, double frequency_hz, double amplitude_m) {
  Validator check;
  check.require(v >= 0.0, "cutting_speed", v, "m/s", "must not be negative");
  check.require_positive("frequency", frequency_hz, "Hz");
  check.require_positive("amplitude", amplitude_m, "m");
  check.throw_if_any("duty cycle");

  DutyCycle d;
  d.period_s = 1.0 / frequency_hz;
  d.critical_speed_m_per_s = kTwoPi * frequency_hz * amplitude_m;
  d.rho = v / d.critical_speed_m_per_s;
  d.separates = d.rho < 1.0;
  if (!d.separates) return d;

  // [Chikishev2018, eq. 1], kinematics restated in docs/models/turning.md §1.
  const double rho = d.rho;
  const double u1 = std::acos(-rho);
  const double level = rho * u1 + std::sin(u1);
  // p(u)/A = ρu + sin u falls from u1 to 2π − u1 and rises on (2π − u1, 2π + u1), where it
  // crosses its earlier maximum once. At ρ = 0 the crossing is the end point (r = 0).
  const auto f = [&](double u) { return rho * u + std::sin(u) - level; };
  double lo = kTwoPi - u1;
  double hi = kTwoPi + u1;
  double u2 = hi;
  if (f(lo) < 0.0 && f(hi) > 0.0) {
    u2 = brent_root(f, lo, hi, 1e-15)->x;
  }
  d.separation_phase_rad = u1;
  d.contact_phase_rad = u2;
  d.ratio = std::clamp((u1 + kTwoPi - u2) / kTwoPi, 0.0, 1.0);
  return d;
}

DutyCycle fixed_duty_cycle(double ratio, double frequency_hz) {
  Validator check;
  check.require(ratio > 0.0 && ratio <= 1.0, "duty_cycle", ratio, "",
                "must be greater than 0 and at most 1");
  check.require_positive("frequency", frequency_hz, "Hz");
  check.throw_if_any("duty cycle");
  DutyCycle d;
  d.ratio = ratio;
  d.period_s = 1.0 / frequency_hz;
  d.separates = ratio < 1.0;
  // Contact on [0, rT): in phase, contact resumes at u2 = 2π and ends at u1 = 2πr.
  d.separation_phase_rad = kTwoPi * ratio;
  d.contact_phase_rad = kTwoPi;
  return d;
}

PulsedForces pulsed_forces(double kc_pa, double kt_pa, double h, double w, double r) {
  PulsedForces f;
  f.peak_cutting_n = kc_pa * h * w;
  f.peak_thrust_n = kt_pa * h * w;
  f.mean_cutting_n = r * f.peak_cutting_n;
  f.mean_thrust_n = r * f.peak_thrust_n;
  return f;
}

}  // namespace cutdyn
