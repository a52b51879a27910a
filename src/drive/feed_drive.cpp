#include "cutdyn/drive/feed_drive.hpp"

#include <algorithm>
#include <cmath>

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

double Transmission::load_torque(double axis_force_n) const {
  return torque_per_newton() * axis_force_n + idle_torque_nm;
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
    case Verdict::kUnstable:
      return "unstable";
  }
  return "?";
}

Verdict nonuniformity_verdict(double k_delta) {
  // [Ermolaev2020, p. 15]: kδ <= 0.2 for a regulated drive; above 0.4 it loses stability.
  if (k_delta <= 0.2) return Verdict::kAcceptable;
  if (k_delta <= 0.4) return Verdict::kMarginal;
  return Verdict::kUnstable;
}

double torque_ripple(const Transmission& t, double force_min_n, double force_max_n,
                     double angle_rad) {
  // [Ermolaev2020, eq. 14] with the transmission's torque per newton.
  return 0.5 * t.torque_per_newton() * std::cos(angle_rad) * (force_max_n - force_min_n);
}

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
                                    bool start_at_mean_load) {
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
  v.throw_if_any("feed drive " + axis.name);

  const FeedDrive& d = axis.drive;
  const Transmission& tr = d.transmission;
  FeedDriveResult r;
  r.commanded_speed_rad_s = feed_speed / tr.travel_per_rad();
  const double omega0 = r.commanded_speed_rad_s;
  const std::size_t n = t.size();
  r.time_s = t;
  double load_sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    // [Ermolaev2020, eq. 11] as a projection (decision): the resistance to the axis' motion is
    // the component of the force on the cutter against it.
    const double fn =
        -(fx[i] * axis.direction[0] + fy[i] * axis.direction[1] + fz[i] * axis.direction[2]);
    r.axis_force_n.push_back(fn);
    // Idle torque Mc0 opposes the motion (none for an axis at rest).
    r.load_torque_nm.push_back(tr.torque_per_newton() * fn + (omega0 > 0.0   ? 1.0
                                                              : omega0 < 0.0 ? -1.0
                                                                             : 0.0) *
                                                                 tr.idle_torque_nm);
    load_sum += r.load_torque_nm.back();
  }
  r.mean_load_torque_nm = load_sum / static_cast<double>(n);
  const double beta = std::abs(d.stiffness_nm_s_per_rad);
  if (d.model == FeedDrive::Model::kStatic) {
    for (std::size_t i = 0; i < n; ++i) {
      r.speed_rad_s.push_back(omega0 - r.load_torque_nm[i] / beta);  // [Ermolaev2020, eq. 13]
      r.motor_torque_nm.push_back(r.load_torque_nm[i]);              // the drive carries the load
    }
    r.static_error = omega0 > 0.0 ? r.mean_load_torque_nm / (omega0 * beta) : 0.0;
  } else {
    DynamicState s;
    s.speed = omega0;
    const double start_load = start_at_mean_load ? r.mean_load_torque_nm : r.load_torque_nm[0];
    const double te0 = start_load + d.viscous_nm_s_per_rad * omega0;
    s.integral = d.ki_nm_per_rad > 0.0 ? te0 / d.ki_nm_per_rad : 0.0;
    s.torque = motor_torque(d, 0.0, s.integral);
    r.speed_rad_s.push_back(s.speed);
    r.motor_torque_nm.push_back(s.torque);
    for (std::size_t i = 1; i < n; ++i) {
      advance(d, omega0, r.load_torque_nm[i - 1], r.load_torque_nm[i], t[i] - t[i - 1], s);
      r.speed_rad_s.push_back(s.speed);
      r.motor_torque_nm.push_back(s.torque);
    }
  }
  r.moving = omega0 > 0.0;
  r.static_error_ok = r.static_error <= 0.1;
  const auto [tmin, tmax] = std::minmax_element(r.load_torque_nm.begin(), r.load_torque_nm.end());
  r.torque_ripple_nm = 0.5 * (*tmax - *tmin);
  const auto [wmin, wmax] = std::minmax_element(r.speed_rad_s.begin(), r.speed_rad_s.end());
  r.speed_ripple_rad_s = 0.5 * (*wmax - *wmin);
  if (r.moving) {
    // [Ermolaev2020, eq. 1], decision: half-range over mean. Stalled or reversing: the worst.
    r.k_delta = *wmax + *wmin > 0.0 ? (*wmax - *wmin) / (*wmax + *wmin) : 1.0;
  }
  r.k_delta_verdict = nonuniformity_verdict(r.k_delta);
  // Position error about uniform motion at the mean actual speed (trapezoidal integral).
  double mean_speed = 0.0;
  for (std::size_t i = 1; i < n; ++i)
    mean_speed += 0.5 * (r.speed_rad_s[i] + r.speed_rad_s[i - 1]) * (t[i] - t[i - 1]);
  mean_speed /= t.back() - t.front();
  double angle = 0.0;
  r.position_error_m.push_back(0.0);
  for (std::size_t i = 1; i < n; ++i) {
    angle += 0.5 * (r.speed_rad_s[i] + r.speed_rad_s[i - 1] - 2.0 * mean_speed) * (t[i] - t[i - 1]);
    r.position_error_m.push_back(tr.travel_per_rad() * angle);
  }
  const auto [pmin, pmax] =
      std::minmax_element(r.position_error_m.begin(), r.position_error_m.end());
  r.position_error_pp_m = *pmax - *pmin;
  return r;
}

}  // namespace cutdyn
