#include "cutdyn/drive/feed_drive.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn {

std::vector<std::string> Transmission::validate() const {
  Validator v;
  if (kind == Kind::kLeverArm) {
    v.require_positive("output_diameter_m", output_diameter_m, "m");
    v.require_positive("ratio", ratio, "");
  } else {
    v.require_positive("lead_m", lead_m, "m");
    v.require(efficiency > 0.0 && efficiency <= 1.0, "efficiency", efficiency, "",
              "must be greater than 0 and at most 1");
    v.require_positive("gear_ratio", gear_ratio, "");
  }
  v.require(std::isfinite(idle_torque_nm), "idle_torque_nm", idle_torque_nm, "N·m",
            "must be finite");
  return v.problems();
}

double Transmission::travel_per_rad() const {
  return kind == Kind::kLeverArm ? 0.5 * output_diameter_m * ratio
                                 : lead_m / (units::kTwoPi * gear_ratio);
}

double Transmission::torque_per_newton() const {
  // [Ermolaev2020, eq. 12]; ball screw: the screw's lead over 2π, through the gear and losses.
  return kind == Kind::kLeverArm ? 0.5 * output_diameter_m * ratio
                                 : lead_m / (units::kTwoPi * efficiency * gear_ratio);
}

double Transmission::back_driving_efficiency() const {
  // A screw that converts torque to force with η = tan λ/tan(λ + ρ) converts force to torque,
  // back-driven, with η' = tan(λ − ρ)/tan λ; for small angles η ≈ 1 − ρ/λ and η' ≈ 1 − ρ/λ
  // ≈ 2 − 1/η (docs/models/feed-drive.md).
  return kind == Kind::kLeverArm ? 1.0 : 2.0 - 1.0 / efficiency;
}

double Transmission::torque_per_newton(double axis_force_n) const {
  if (axis_force_n >= 0.0 || kind == Kind::kLeverArm) return torque_per_newton();
  return lead_m * back_driving_efficiency() / (units::kTwoPi * gear_ratio);
}

double Transmission::load_torque(double axis_force_n) const {
  return torque_per_newton(axis_force_n) * axis_force_n + idle_torque_nm;
}

std::vector<std::string> FeedDrive::validate() const {
  Validator v;
  v.merge(transmission.validate());
  if (model == Model::kStatic) {
    v.require_positive("stiffness_nm_s_per_rad", std::abs(stiffness_nm_s_per_rad),
                       "N·m·s/rad (|β|)");
  } else {
    v.require_positive("inertia_kg_m2", inertia_kg_m2, "kg·m²");
    v.require(viscous_nm_s_per_rad >= 0.0, "viscous_nm_s_per_rad", viscous_nm_s_per_rad,
              "N·m·s/rad", "must not be negative");
    v.require_positive("kp_nm_s_per_rad", kp_nm_s_per_rad, "N·m·s/rad");
    v.require(ki_nm_per_rad >= 0.0, "ki_nm_per_rad", ki_nm_per_rad, "N·m/rad",
              "must not be negative");
    v.require(torque_limit_nm >= 0.0, "torque_limit_nm", torque_limit_nm, "N·m",
              "must not be negative (0: no limit)");
  }
  return v.problems();
}

const char* to_string(Verdict v) {
  switch (v) {
    case Verdict::kAcceptable:
      return "acceptable";
    case Verdict::kMarginal:
      return "marginal";
    case Verdict::kBeyondLimit:
      return "beyond-limit";
  }
  return "?";
}

const char* describe(Verdict v) {
  switch (v) {
    case Verdict::kAcceptable:
      return "acceptable (≤ 0.2)";
    case Verdict::kMarginal:
      return "marginal (0.2 … 0.4)";
    case Verdict::kBeyondLimit:
      return "non-uniform beyond the source's 0.4 limit for regulated drives";
  }
  return "?";
}

Verdict nonuniformity_verdict(double k_delta) {
  // [Ermolaev2020, p. 15]: kδ <= 0.2 for a regulated drive; above 0.4 the source says the drive
  // loses stability, which a linear drive model cannot: the verdict names the limit instead.
  if (k_delta <= 0.2) return Verdict::kAcceptable;
  if (k_delta <= 0.4) return Verdict::kMarginal;
  return Verdict::kBeyondLimit;
}

double nonuniformity(double speed_min, double speed_max) {
  // [Ermolaev2020, eq. 1]: kδ = ΔΩ/Ω̄ = 2(Ωmax − Ωmin)/(Ωmax + Ωmin), range over mean.
  const double sum = speed_max + speed_min;
  return sum > 0.0 ? 2.0 * (speed_max - speed_min) / sum : 2.0;
}

double torque_ripple(const Transmission& t, double force_min_n, double force_max_n,
                     double angle_rad) {
  // [Ermolaev2020, eq. 14] with the transmission's torque per newton.
  return 0.5 * t.torque_per_newton() * std::cos(angle_rad) * (force_max_n - force_min_n);
}

namespace {

// printf-style text for the warnings.
template <typename... Args>
std::string format(const char* pattern, Args... args) {
  char text[400];
  std::snprintf(text, sizeof text, pattern, args...);
  return text;
}

// Ω at time τ (t0 <= τ <= tend), linear between samples.
double interpolate(const std::vector<double>& t, const std::vector<double>& w, double tau) {
  auto it = std::lower_bound(t.begin(), t.end(), tau);
  if (it == t.end()) return w.back();
  const auto k = static_cast<std::size_t>(it - t.begin());
  if (k == 0 || *it == tau) return w[k];
  const double a = (tau - t[k - 1]) / (t[k] - t[k - 1]);
  return w[k - 1] + a * (w[k] - w[k - 1]);
}

struct SteadyWindow {
  bool checked = false, steady = true;
  double from = 0.0, change = 0.0;
  int periods = 0;
  std::string why;  // why not steady
};

// The periodic steady state of Ω(t) at the period T (docs/models/feed-drive.md). The periods are
// counted back from the end of the trace: b_j = tend − (P − j)·T, j = 0 … P. d_j is the largest
// |Ω(t + T) − Ω(t)| over period j; the distance of period j from the limit cycle is at most
// Σ_{k>=j} d_k, the known differences plus a geometric tail d_last·r/(1 − r), r the ratio of
// the last two. The steady window starts at the first period whose bound is within the
// tolerance: a fraction of the peak-to-peak speed in the last period.
SteadyWindow find_steady_state(const std::vector<double>& t, const std::vector<double>& w,
                               double omega0, double floor_rad_s, const SteadyStateOptions& o) {
  SteadyWindow s;
  s.from = t.front();
  if (!(o.period_s > 0.0)) return s;
  s.checked = true;
  const double period = o.period_s, t0 = t.front(), tend = t.back();
  const int p = static_cast<int>(std::floor((tend - t0) / period * (1.0 + 1e-12)));
  if (p < 3) {
    s.steady = false;
    s.from = p >= 1 ? tend - period : t0;
    s.periods = p >= 1 ? 1 : 0;
    s.why = format(
        "the run is %.4g forcing periods long; the steady state needs at least 3 to "
        "be detected",
        (tend - t0) / period);
    return s;
  }
  const auto boundary = [&](int j) { return std::max(t0, tend - (p - j) * period); };
  double lo = 1e300, hi = -1e300, largest = 0.0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    largest = std::max(largest, std::abs(w[i]));
    if (t[i] >= boundary(p - 1)) {
      lo = std::min(lo, w[i]);
      hi = std::max(hi, w[i]);
    }
  }
  // Plus `floor_rad_s`: a change between periods too small to move the axis by 1 nm in a
  // period (a lightly damped cutter mode can keep a static drive's speed beating at 1e-9 of
  // it), and 1e-12 of the speed (rounding).
  const double tol =
      o.relative_tolerance * (hi - lo) + floor_rad_s + 1e-12 * std::max(std::abs(omega0), largest);
  std::vector<double> d(static_cast<std::size_t>(p - 1), 0.0);
  std::size_t i = 0;
  for (int j = 0; j + 1 < p; ++j) {
    const double b0 = boundary(j), b1 = boundary(j + 1);
    while (i < t.size() && t[i] < b0) ++i;
    double worst = std::abs(interpolate(t, w, b0 + period) - interpolate(t, w, b0));
    for (; i < t.size() && t[i] < b1; ++i)
      worst = std::max(worst, std::abs(interpolate(t, w, t[i] + period) - w[i]));
    d[static_cast<std::size_t>(j)] = worst;
  }
  const double last = d.back(), before = d[d.size() - 2];
  double tail = 0.0;
  if (last > 1e-3 * tol) {
    const double r = before > 0.0 ? last / before : 1.0;
    tail = r < 1.0 ? last * r / (1.0 - r) : 1e300;
  }
  s.change = last;
  double bound = tail;
  int first = p;  // first steady period
  for (int j = p - 2; j >= 0; --j) {
    bound += d[static_cast<std::size_t>(j)];
    if (bound > tol) break;
    first = j;
  }
  if (first >= p) {
    s.steady = false;
    s.from = boundary(p - 1);
    s.periods = 1;
    s.why = format(
        "the speed still changes by %.3g rad/s from one forcing period to the next at "
        "the end of the run (tolerance %.3g rad/s, %.3g %% of its peak-to-peak); the "
        "summary is of the last period",
        last, tol, 100.0 * o.relative_tolerance);
    return s;
  }
  s.from = boundary(first);
  s.periods = p - first;
  return s;
}

// Time average of v over [from, tend] (trapezoidal; `from` on or before a sample).
double time_average(const std::vector<double>& t, const std::vector<double>& v, double from) {
  double sum = 0.0;
  for (std::size_t i = 1; i < t.size(); ++i) {
    if (t[i] <= from) continue;
    const double a = std::max(t[i - 1], from);
    const double va = t[i - 1] >= from ? v[i - 1] : interpolate(t, v, from);
    sum += 0.5 * (va + v[i]) * (t[i] - a);
  }
  return t.back() > from ? sum / (t.back() - from) : v.back();
}

}  // namespace

namespace {

// The dynamic drive over one interval with the load torque linear between its end samples:
// RK4 on (Ω, ∫e), sub-stepped so that the loop's fastest rate is resolved.
struct DynamicState {
  double speed = 0.0;
  double integral = 0.0;  // ∫(Ω0 − Ω) dt
  double torque = 0.0;    // Te at the end of the last step
};

double motor_torque(const FeedDrive& d, double error, double integral) {
  double te = d.kp_nm_s_per_rad * error + d.ki_nm_per_rad * integral;
  if (d.torque_limit_nm > 0.0) te = std::clamp(te, -d.torque_limit_nm, d.torque_limit_nm);
  return te;
}

void advance(const FeedDrive& d, double omega0, double load0, double load1, double dt,
             DynamicState& s) {
  const double rate = (d.kp_nm_s_per_rad + d.viscous_nm_s_per_rad) / d.inertia_kg_m2 +
                      std::sqrt(d.ki_nm_per_rad / d.inertia_kg_m2);
  const int n = std::max(1, static_cast<int>(std::ceil(dt * rate / 0.2)));
  const double h = dt / n;
  const auto derivative = [&](double tau, double w, double integral, double& dw, double& di) {
    const double load = load0 + (load1 - load0) * tau / dt;
    const double e = omega0 - w;
    double te = motor_torque(d, e, integral);
    // Anti-windup: stop integrating while the torque is at its limit and the error pushes on.
    di = e;
    if (d.torque_limit_nm > 0.0 && std::abs(te) >= d.torque_limit_nm && te * e > 0.0) di = 0.0;
    dw = (te - load - d.viscous_nm_s_per_rad * w) / d.inertia_kg_m2;
  };
  for (int k = 0; k < n; ++k) {
    double w1, i1, w2, i2, w3, i3, w4, i4;
    const double tau = k * h;
    derivative(tau, s.speed, s.integral, w1, i1);
    derivative(tau + 0.5 * h, s.speed + 0.5 * h * w1, s.integral + 0.5 * h * i1, w2, i2);
    derivative(tau + 0.5 * h, s.speed + 0.5 * h * w2, s.integral + 0.5 * h * i2, w3, i3);
    derivative(tau + h, s.speed + h * w3, s.integral + h * i3, w4, i4);
    s.speed += h / 6.0 * (w1 + 2 * w2 + 2 * w3 + w4);
    s.integral += h / 6.0 * (i1 + 2 * i2 + 2 * i3 + i4);
  }
  s.torque = motor_torque(d, omega0 - s.speed, s.integral);
}

}  // namespace

FeedDriveResult simulate_feed_drive(const FeedAxis& axis, const std::vector<double>& t,
                                    const std::vector<double>& fx, const std::vector<double>& fy,
                                    const std::vector<double>& fz, double feed_speed,
                                    bool start_at_mean_load, const SteadyStateOptions& steady) {
  Validator v;
  v.merge(axis.drive.validate());
  const double norm = std::hypot(axis.direction[0], axis.direction[1], axis.direction[2]);
  v.require(std::abs(norm - 1.0) < 1e-6, "direction", norm, "(its length)",
            "must be a unit vector");
  v.require(t.size() >= 2, "time_s", static_cast<double>(t.size()), "samples",
            "needs at least 2 samples");
  v.require(fx.size() == t.size() && fy.size() == t.size() && fz.size() == t.size(), "forces",
            static_cast<double>(fx.size()), "samples", "must have one value per time");
  v.require(feed_speed >= 0.0 && std::isfinite(feed_speed), "feed_speed_m_per_s", feed_speed, "m/s",
            "must be finite and not negative");
  for (std::size_t i = 1; i < t.size() && v.ok(); ++i)
    v.require(t[i] > t[i - 1], "time_s[" + std::to_string(i) + "]", t[i], "s", "must increase");

  v.require(steady.period_s >= 0.0 && std::isfinite(steady.period_s), "period_s", steady.period_s,
            "s", "must be finite and not negative (0: unknown)");
  v.require(steady.relative_tolerance > 0.0 && steady.relative_tolerance < 1.0,
            "relative_tolerance", steady.relative_tolerance, "", "must be between 0 and 1");
  v.throw_if_any("feed drive " + axis.name);

  const FeedDrive& d = axis.drive;
  const Transmission& tr = d.transmission;
  FeedDriveResult r;
  r.commanded_speed_rad_s = feed_speed / tr.travel_per_rad();
  const double omega0 = r.commanded_speed_rad_s;
  const std::size_t n = t.size();
  r.time_s = t;
  const double motion = omega0 > 0.0 ? 1.0 : omega0 < 0.0 ? -1.0 : 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    // [Ermolaev2020, eq. 11] as a projection (decision): the resistance to the axis' motion is
    // the component of the force on the cutter against it.
    const double fn =
        -(fx[i] * axis.direction[0] + fy[i] * axis.direction[1] + fz[i] * axis.direction[2]);
    r.axis_force_n.push_back(fn);
    // Idle torque Mc0 opposes the motion (none for an axis at rest); an aiding force back-drives
    // a ball screw (back-driving efficiency).
    r.load_torque_nm.push_back(tr.torque_per_newton(fn) * fn + motion * tr.idle_torque_nm);
  }
  // The starting load: the mean over the trace (or the first sample's).
  const double start_load =
      start_at_mean_load ? time_average(t, r.load_torque_nm, t.front()) : r.load_torque_nm[0];
  const double beta = std::abs(d.stiffness_nm_s_per_rad);
  if (d.model == FeedDrive::Model::kStatic) {
    for (std::size_t i = 0; i < n; ++i) {
      r.speed_rad_s.push_back(omega0 - r.load_torque_nm[i] / beta);  // [Ermolaev2020, eq. 13]
      r.motor_torque_nm.push_back(r.load_torque_nm[i]);              // the drive carries the load
    }
  } else {
    // The equilibrium under the starting load: with an integrator Ω = Ω0 and ∫e carries the
    // torque; P-only, Kp·(Ω0 − Ω) = Mc + b·Ω.
    DynamicState s;
    const double kp = d.kp_nm_s_per_rad, b = d.viscous_nm_s_per_rad;
    if (d.ki_nm_per_rad > 0.0) {
      s.speed = omega0;
      s.integral = (start_load + b * omega0) / d.ki_nm_per_rad;
    } else {
      s.speed = (kp * omega0 - start_load) / (kp + b);
    }
    s.torque = motor_torque(d, omega0 - s.speed, s.integral);
    // With an integrator, ∫(Ω0 − Ω)dt is the motor's lag behind its programmed angle; the
    // cut's share is what exceeds the idle motion's, (Mc0 + b·Ω0)/Ki.
    const double idle_integral =
        d.ki_nm_per_rad > 0.0 ? (motion * tr.idle_torque_nm + b * omega0) / d.ki_nm_per_rad : 0.0;
    const auto record = [&] {
      r.speed_rad_s.push_back(s.speed);
      r.motor_torque_nm.push_back(s.torque);
      if (d.ki_nm_per_rad > 0.0)
        r.load_lag_m.push_back(tr.travel_per_rad() * (s.integral - idle_integral));
    };
    record();
    for (std::size_t i = 1; i < n; ++i) {
      advance(d, omega0, r.load_torque_nm[i - 1], r.load_torque_nm[i], t[i] - t[i - 1], s);
      record();
    }
  }
  // The periodic steady state, detected on the speed.
  // A speed change between periods that moves the axis by less than 1 nm over a period.
  const double floor_rad_s =
      steady.period_s > 0.0 ? 1e-9 / (steady.period_s * tr.travel_per_rad()) : 0.0;
  const SteadyWindow w = find_steady_state(t, r.speed_rad_s, omega0, floor_rad_s, steady);
  r.steady_checked = w.checked;
  r.steady = w.steady;
  r.steady_from_s = w.from;
  r.steady_periods = w.periods;
  r.periodicity_change_rad_s = w.change;
  if (!w.checked && d.model == FeedDrive::Model::kDynamic)
    r.warnings.push_back(
        "no forcing period given: the summary is of the whole run, start-up "
        "transient included (steady state not checked)");
  if (w.checked && !w.steady)
    r.warnings.push_back("no periodic steady state within the run: " + w.why);
  // Summary over the window.
  const auto first = static_cast<std::size_t>(
      std::lower_bound(t.begin(), t.end(), w.from - 1e-12 * (1.0 + std::abs(w.from))) - t.begin());
  const auto range = [&](const std::vector<double>& trace) {
    // Extremes over the window; its start interpolated when it falls between samples.
    double lo = interpolate(t, trace, w.from), hi = lo;
    for (std::size_t i = first; i < n; ++i) {
      lo = std::min(lo, trace[i]);
      hi = std::max(hi, trace[i]);
    }
    return std::pair{lo, hi};
  };
  r.mean_load_torque_nm = time_average(t, r.load_torque_nm, w.from);
  const auto [tmin, tmax] = range(r.load_torque_nm);
  r.torque_ripple_nm = 0.5 * (tmax - tmin);
  const auto [wmin, wmax] = range(r.speed_rad_s);
  r.speed_ripple_rad_s = 0.5 * (wmax - wmin);
  r.mean_speed_rad_s = time_average(t, r.speed_rad_s, w.from);
  r.moving = omega0 > 0.0;
  if (r.moving) {
    r.k_delta = nonuniformity(wmin, wmax);
    if (wmin <= 0.0)
      r.warnings.push_back(
          format("the motor stalls or reverses (lowest speed %.4g rad/s against "
                 "%.4g commanded)",
                 wmin, omega0));
    // δ = (Ω0 − Ω̄)/Ω0; for the static characteristic exactly mean Mc/(Ω0·|β|).
    r.static_error = d.model == FeedDrive::Model::kStatic ? r.mean_load_torque_nm / (omega0 * beta)
                                                          : (omega0 - r.mean_speed_rad_s) / omega0;
  }
  r.k_delta_verdict = nonuniformity_verdict(r.k_delta);
  r.static_error_ok = r.static_error <= 0.1;
  // Position error about uniform motion at the steady mean speed (trapezoidal integral).
  double angle = 0.0;
  r.position_error_m.push_back(0.0);
  for (std::size_t i = 1; i < n; ++i) {
    angle += 0.5 * (r.speed_rad_s[i] + r.speed_rad_s[i - 1] - 2.0 * r.mean_speed_rad_s) *
             (t[i] - t[i - 1]);
    r.position_error_m.push_back(tr.travel_per_rad() * angle);
  }
  const auto [pmin, pmax] = range(r.position_error_m);
  r.position_error_pp_m = pmax - pmin;
  if (!r.load_lag_m.empty()) {
    const auto [lmin, lmax] = range(r.load_lag_m);
    r.load_lag_max_m = std::abs(lmax) >= std::abs(lmin) ? lmax : lmin;
  }
  return r;
}

}  // namespace cutdyn
