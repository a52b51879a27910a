#include "cutdyn/forces/oxley.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <string>

#include "cutdyn/core/detail/roots.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kSqrt3 = std::numbers::sqrt3;
constexpr double kPi = std::numbers::pi;
constexpr const char* kWhere = "Oxley machining theory";

// Boothroyd's fraction of the shear-zone heat conducted into the work [Oxley1989, eq. 3.9],
// clamped to [0, 1] outside its range (the solution is checked against the range): β of
// eq. OX-7 (docs/models/oxley.md).
double heat_into_work(double thermal_number, double tan_phi) {
  const double x = thermal_number * tan_phi;
  const double beta = x <= 10.0 ? 0.5 - 0.35 * std::log10(x) : 0.3 - 0.15 * std::log10(x);
  return std::clamp(beta, 0.0, 1.0);
}

// The largest root of f on [lo, hi]: f at n equal steps from hi down, stopping at the first
// sign change between two points where f is defined (not NaN), refined by Brent's method
// (a NaN inside that cell counts as the lower end's sign). NaN when there is none.
template <typename F>
double largest_root(F f, double lo, double hi, int n, double tol) {
  double upper = kNaN, f_upper = kNaN;
  for (int i = n - 1; i >= 0; --i) {
    const double x = lo + (hi - lo) * i / (n - 1);
    const double fx = f(x);
    if (std::isnan(fx)) {
      upper = kNaN;
      continue;
    }
    if (fx == 0.0) return x;
    if (!std::isnan(upper) && (fx > 0.0) != (f_upper > 0.0)) {
      const auto root = brent_root(
          [&](double t) {
            const double y = f(t);
            return std::isnan(y) ? fx : y;
          },
          x, fx, upper, f_upper, tol);
      return root ? root->x : kNaN;
    }
    upper = x;
    f_upper = fx;
  }
  return kNaN;
}

}  // namespace

void OxleyOptions::validate(Validator& v) const {
  v.require(std::isfinite(eta) && eta > 0.0 && eta <= 1.0, "oxley.eta", eta, "",
            "must be in (0, 1]");
  v.require(std::isfinite(psi) && psi > 0.0 && psi <= 1.0, "oxley.psi", psi, "",
            "must be in (0, 1]");
  v.require(std::isfinite(c0_min) && c0_min > 0.0, "oxley.c0_min", c0_min, "", "must be > 0");
  v.require(std::isfinite(c0_max) && c0_max > c0_min, "oxley.c0_max", c0_max, "",
            "must be > c0_min");
  v.require(std::isfinite(delta_min) && delta_min > 0.0, "oxley.delta_min", delta_min, "",
            "must be > 0");
  v.require(std::isfinite(delta_max) && delta_max > delta_min && delta_max < 1.0, "oxley.delta_max",
            delta_max, "", "must be > delta_min and < 1");
  v.require(std::isfinite(phi_min_rad) && phi_min_rad > 0.0, "oxley.phi_min_rad", phi_min_rad,
            "rad", "must be > 0");
  v.require(std::isfinite(phi_max_rad) && phi_max_rad > phi_min_rad && phi_max_rad < kPi / 2,
            "oxley.phi_max_rad", phi_max_rad, "rad", "must be > phi_min_rad and < π/2");
  v.require(phi_scan_points >= 8 && phi_scan_points <= 10000, "oxley.phi_scan_points",
            phi_scan_points, "", "must be in [8, 10000]");
  v.require(c0_scan_points >= 3 && c0_scan_points <= 10000, "oxley.c0_scan_points", c0_scan_points,
            "", "must be in [3, 10000]");
  v.require(delta_scan_points >= 3 && delta_scan_points <= 10000, "oxley.delta_scan_points",
            delta_scan_points, "", "must be in [3, 10000]");
  for (const auto& [name, tol] : {std::pair{"oxley.phi_tolerance_rad", phi_tolerance_rad},
                                  std::pair{"oxley.c0_tolerance", c0_tolerance},
                                  std::pair{"oxley.delta_tolerance", delta_tolerance}})
    v.require(std::isfinite(tol) && tol > 0.0, name, tol, "", "must be > 0");
}

void validate(const OrthogonalCut& cut, const WorkMaterial& material, Validator& v) {
  v.require_positive("cut.speed_m_per_s", cut.speed_m_per_s, "m/s");
  v.require_positive("cut.uncut_chip_thickness_m", cut.uncut_chip_thickness_m, "m");
  v.require_positive("cut.width_m", cut.width_m, "m");
  v.require(std::isfinite(cut.rake_rad) && std::abs(cut.rake_rad) < kPi / 4, "cut.rake_rad",
            cut.rake_rad, "rad", "must be between −45° and 45°");
  const JohnsonCook& jc = material.flow;
  v.require(std::isfinite(cut.workpiece_temperature_c) &&
                cut.workpiece_temperature_c < jc.melting_temperature_c,
            "cut.workpiece_temperature_c", cut.workpiece_temperature_c, "°C",
            "must be below the material's melting temperature");
}

OxleyState oxley_state(const WorkMaterial& material, const OrthogonalCut& cut, double phi,
                       double c0, double delta, const OxleyOptions& options) {
  const JohnsonCook& jc = material.flow;
  const ThermalProperties& th = material.thermal;
  const double V = cut.speed_m_per_s, t1 = cut.uncut_chip_thickness_m, w = cut.width_m;
  const double alpha = cut.rake_rad, Tw = cut.workpiece_temperature_c, rho = th.density_kg_per_m3;
  OxleyState s;
  s.phi_rad = phi;
  s.c0 = c0;
  s.delta = delta;
  const double sin_phi = std::sin(phi), cos_pa = std::cos(phi - alpha);
  const double tan_phi = std::tan(phi);
  // Shear-plane geometry and kinematics [Oxley1989, eqs. 7.1–7.4]; eqs. OX-3 and OX-4
  // (docs/models/oxley.md).
  const double l = t1 / sin_phi;
  s.shear_plane_length_m = l;
  s.shear_velocity_m_per_s = V * std::cos(alpha) / cos_pa;
  s.chip_velocity_m_per_s = V * sin_phi / cos_pa;
  s.chip_thickness_m = t1 * cos_pa / sin_phi;
  const double gamma_ab = std::cos(alpha) / (2.0 * sin_phi * cos_pa);
  s.strain_ab = gamma_ab / kSqrt3;
  s.strain_rate_ab_per_s = c0 * s.shear_velocity_m_per_s / l / kSqrt3;

  // Angle of the resultant and the friction angle [Oxley1989, eq. 7.9; Lalwani2009, eq. 8];
  // eq. OX-5 (docs/models/oxley.md), n_eq of eq. OX-2 at ε_AB.
  s.hardening_index = jc.hardening_index(s.strain_ab);
  const double tan_theta = 1.0 + 2.0 * (kPi / 4.0 - phi) - c0 * s.hardening_index;
  s.theta_rad = std::atan(tan_theta);
  s.friction_angle_rad = s.theta_rad - phi + alpha;
  const double lambda = s.friction_angle_rad;
  s.admissible = tan_theta > 0.0 && lambda > 0.0 && lambda < kPi / 2;
  if (!s.admissible) return s;  // before the temperature: most of a φ scan ends here

  // Shear-plane temperature T_AB = Tw + η·ΔT_SZ(T_AB): properties and flow stress at T_AB
  // [Oxley1989, eqs. 3.9–3.11; Lalwani2009, eqs. 9–12]. g(T) = Tw + η·ΔT_SZ − T is ≥ 0 at Tw
  // and Tw − Tm < 0 at Tm (no flow stress), so Brent's method has a bracket. R_T and β of
  // eq. OX-7, ΔT_SZ and T_AB of eq. OX-8, k_AB = σ/√3 of eqs. OX-1 and OX-2
  // (docs/models/oxley.md).
  const double k_unsoftened =
      jc.hardening_pa(s.strain_ab) * jc.rate_factor(s.strain_rate_ab_per_s) / kSqrt3;
  const auto softening = [&](double T) { return jc.softening(T); };
  const auto shear_zone_rise = [&](double T, double& beta, double& rt) {
    const double S = th.specific_heat(T);
    rt = rho * S * V * t1 / th.conductivity(T);
    beta = heat_into_work(rt, tan_phi);
    const double Fs = k_unsoftened * softening(T) * l * w;
    return (1.0 - beta) * Fs * s.shear_velocity_m_per_s / (rho * S * t1 * w * V);
  };
  double beta = 0.0, rt = 0.0;
  const auto g = [&](double T) { return Tw + options.eta * shear_zone_rise(T, beta, rt) - T; };
  const double g_cold = g(Tw);
  double T_ab = Tw;
  if (g_cold > 0.0) {
    const double Tm = jc.melting_temperature_c;
    const auto root = brent_root(g, Tw, g_cold, Tm, Tw - Tm, 1e-9);
    T_ab = root ? root->x : Tm;
  }
  s.temperature_rise_shear_c = shear_zone_rise(T_ab, beta, rt);
  s.temperature_ab_c = T_ab;
  s.thermal_number = rt;
  s.heat_into_work = beta;
  s.shear_flow_stress_pa = k_unsoftened * softening(T_ab);

  // Forces [Oxley1989, eqs. 7.10–7.14]; eq. OX-6 (docs/models/oxley.md).
  s.shear_force_n = s.shear_flow_stress_pa * l * w;
  s.resultant_n = s.shear_force_n / std::cos(s.theta_rad);
  s.cutting_force_n = s.resultant_n * std::cos(lambda - alpha);
  s.thrust_force_n = s.resultant_n * std::sin(lambda - alpha);
  s.friction_force_n = s.resultant_n * std::sin(lambda);
  s.normal_force_n = s.resultant_n * std::cos(lambda);

  // Tool–chip contact length and the stresses on it [Oxley1989, eqs. 7.15–7.17]; eqs. OX-9
  // and OX-10 (docs/models/oxley.md).
  s.contact_length_m = t1 * std::sin(s.theta_rad) / (std::cos(lambda) * sin_phi) *
                       (1.0 + c0 * s.hardening_index / (3.0 * tan_theta));
  s.interface_shear_stress_pa = s.friction_force_n / (s.contact_length_m * w);
  s.interface_normal_stress_pa = s.normal_force_n / (s.contact_length_m * w);
  s.normal_stress_b_pa =
      s.shear_flow_stress_pa * (1.0 + kPi / 2.0 - 2.0 * alpha - 2.0 * c0 * s.hardening_index);

  // Interface temperature [Oxley1989, eqs. 3.12–3.13]: the mean chip temperature
  // T_c = Tw + ΔT_SZ + ΔT_C with S at T_c (a contracting fixed point: ΔT_C depends on T_c
  // only through S), then ΔT_M from the thermal number at T_c, T_int = Tw + ΔT_SZ + ψ·ΔT_M:
  // eqs. OX-11, OX-12 and OX-13 (docs/models/oxley.md).
  const double t2 = s.chip_thickness_m, h = s.contact_length_m;
  const double heat_rate = s.friction_force_n * s.chip_velocity_m_per_s;
  const double T_sz = Tw + s.temperature_rise_shear_c;
  double T_c = T_sz, dT_c = 0.0;
  for (int it = 0; it < 100; ++it) {
    dT_c = heat_rate / (rho * th.specific_heat(T_c) * V * t1 * w);
    // The properties' fits end at melting, and so does the chip's strength.
    const double next = std::min(T_sz + dT_c, jc.melting_temperature_c);
    const bool done = std::abs(next - T_c) <= 1e-9 * (1.0 + std::abs(next));
    T_c = next;
    if (done) break;
  }
  const double rt_chip = rho * th.specific_heat(T_c) * V * t1 / th.conductivity(T_c);
  const double x = rt_chip * t2 / h;
  const double dT_m =
      dT_c * std::pow(10.0, 0.06 - 0.195 * delta * std::sqrt(x) + 0.5 * std::log10(x));
  s.temperature_rise_chip_c = dT_c;
  s.temperature_chip_c = T_c;
  s.temperature_rise_max_c = dT_m;
  s.temperature_interface_c = std::min(T_sz + options.psi * dT_m, jc.melting_temperature_c);

  // Flow stress of the chip at the interface [Oxley1989, eqs. 7.18–7.19]; eqs. OX-14 and
  // OX-15 (docs/models/oxley.md).
  const double T_int = s.temperature_interface_c;
  const double gamma_int = 2.0 * gamma_ab + 0.5 * h / (delta * t2);
  s.strain_interface = gamma_int / kSqrt3;
  s.strain_rate_interface_per_s = s.chip_velocity_m_per_s / (delta * t2) / kSqrt3;
  s.chip_flow_stress_pa =
      jc.flow_stress_pa(s.strain_interface, s.strain_rate_interface_per_s, T_int) / kSqrt3;
  return s;
}

namespace {

// The nested solution (docs/models/oxley.md §3).
class Solver {
 public:
  Solver(const WorkMaterial& material, const OrthogonalCut& cut, const OxleyOptions& options)
      : material_(material), cut_(cut), o_(options) {}

  int evaluations() const { return evaluations_; }

  OxleyState state(double phi, double c0, double delta) {
    ++evaluations_;
    return oxley_state(material_, cut_, phi, c0, delta, o_);
  }

  // τ_int − k_chip, relative to k_AB; NaN where the geometry does not exist. Condition 1 of
  // docs/models/oxley.md §3: τ_int of eq. OX-10 against k_chip of eq. OX-15.
  double interface_mismatch(double phi, double c0, double delta) {
    const OxleyState s = state(phi, c0, delta);
    if (!s.admissible) return kNaN;
    return (s.interface_shear_stress_pa - s.chip_flow_stress_pa) / s.shear_flow_stress_pa;
  }

  // The largest shear angle that satisfies the interface condition, or NaN.
  double shear_angle(double c0, double delta) {
    return largest_root([&](double phi) { return interface_mismatch(phi, c0, delta); },
                        o_.phi_min_rad, o_.phi_max_rad, o_.phi_scan_points, o_.phi_tolerance_rad);
  }

  struct Equilibrium {
    double phi = kNaN;
    double c0 = kNaN;
  };

  // σ_N − σ'_N (relative to k_AB) at the shear angle of (C0, δ); NaN without one. Condition 2
  // of docs/models/oxley.md §3, both stresses of eq. OX-10.
  double normal_mismatch(double c0, double delta) {
    const double phi = shear_angle(c0, delta);
    if (std::isnan(phi)) return kNaN;
    const OxleyState s = state(phi, c0, delta);
    const double g = (s.interface_normal_stress_pa - s.normal_stress_b_pa) / s.shear_flow_stress_pa;
    normal_min_ = std::min(normal_min_, g);
    normal_max_ = std::max(normal_max_, g);
    return g;
  }

  // Why there is no equilibrium, from what the scans saw.
  std::string failure_reason() const {
    if (normal_min_ > normal_max_)
      return "the interface condition (tool–chip shear stress = the chip's flow shear stress) "
             "has no solution at any shear angle";
    if (normal_min_ > 0.0)
      return "the interface normal stress exceeds the normal stress at the tool tip for every "
             "C0 in the range (the equilibrium would need C0 below c0_min = " +
             format_value(o_.c0_min) + ")";
    if (normal_max_ < 0.0)
      return "the normal stress at the tool tip exceeds the interface normal stress for every C0 "
             "in the range (the equilibrium would need C0 above c0_max = " +
             format_value(o_.c0_max) + ")";
    return "the normal-stress condition changes sign only across C0 values with no physical "
           "shear angle";
  }

  // (φ, C0) for one δ: a C0 root of the normal-stress condition; with several, the one of
  // largest C0 (the thinnest primary zone). NaN if none in [c0_min, c0_max].
  Equilibrium equilibrium(double delta) {
    Equilibrium e;
    e.c0 = largest_root([&](double c0) { return normal_mismatch(c0, delta); }, o_.c0_min, o_.c0_max,
                        o_.c0_scan_points, o_.c0_tolerance);
    if (!std::isnan(e.c0)) e.phi = shear_angle(e.c0, delta);
    return e;
  }

  // Fc at the equilibrium of δ; +inf without one. Keeps the state of least Fc seen.
  double cutting_force(double delta) {
    const Equilibrium e = equilibrium(delta);
    if (std::isnan(e.phi) || std::isnan(e.c0)) return std::numeric_limits<double>::infinity();
    OxleyState s = state(e.phi, e.c0, delta);
    const double fc = s.cutting_force_n;
    if (!best_ || fc < best_->cutting_force_n) best_ = std::move(s);
    return fc;
  }

  // The equilibrium of least Fc among those evaluated (none before any succeeded).
  const std::optional<OxleyState>& best() const { return best_; }

 private:
  const WorkMaterial& material_;
  const OrthogonalCut& cut_;
  const OxleyOptions& o_;
  int evaluations_ = 0;
  std::optional<OxleyState> best_;
  double normal_min_ = std::numeric_limits<double>::infinity();
  double normal_max_ = -std::numeric_limits<double>::infinity();
};

}  // namespace

double oxley_shear_angle(const WorkMaterial& material, const OrthogonalCut& cut, double c0,
                         double delta, const OxleyOptions& options) {
  return Solver(material, cut, options).shear_angle(c0, delta);
}

OxleyResult oxley_orthogonal(const WorkMaterial& material, const OrthogonalCut& cut,
                             const OxleyOptions& options) {
  {
    Validator v;
    validate(material, v);
    validate(cut, material, v);
    options.validate(v);
    v.throw_if_any(kWhere);
  }
  Solver solver(material, cut, options);

  // δ: scan, then Brent's minimiser between the neighbours of the best sample; the answer is
  // the equilibrium of least Fc the solver met.
  const int n = options.delta_scan_points;
  const double d_lo = options.delta_min, d_hi = options.delta_max;
  // Geometric spacing: the force changes fastest at small δ.
  const auto delta_at = [&](int i) {
    return d_lo * std::pow(d_hi / d_lo, static_cast<double>(std::clamp(i, 0, n - 1)) / (n - 1));
  };
  int best = -1;
  double least = std::numeric_limits<double>::infinity();
  for (int i = 0; i < n; ++i) {
    const double fc = solver.cutting_force(delta_at(i));
    if (fc < least) {
      least = fc;
      best = i;
    }
  }
  if (best < 0) {
    throw InvalidInput(
        {"no equilibrium of Oxley's theory in the physical branch at V = " +
         format_value(units::m_per_s_to_m_per_min(cut.speed_m_per_s)) +
         " m/min, t1 = " + format_value(units::m_to_mm(cut.uncut_chip_thickness_m)) + " mm, rake " +
         format_value(std::round(units::rad_to_deg(cut.rake_rad) * 1e6) / 1e6) + "° for C0 in [" +
         format_value(options.c0_min) + ", " + format_value(options.c0_max) + "] and δ in [" +
         format_value(d_lo) + ", " + format_value(d_hi) + "]: " + solver.failure_reason() +
         "; the cut is outside the theory's validity (it describes continuous chips at "
         "moderate to high speeds)"},
        kWhere);
  }
  const double a = delta_at(best - 1), b = delta_at(best + 1);
  if (b > a)
    brent_minimum([&](double d) { return solver.cutting_force(d); }, a, b, options.delta_tolerance);

  OxleyResult r;
  r.state = *solver.best();
  const double delta = r.state.delta;
  const OxleyState& s = r.state;
  const double t1w = cut.uncut_chip_thickness_m * cut.width_m;
  r.kc_pa = s.cutting_force_n / t1w;
  r.kt_pa = s.thrust_force_n / t1w;
  r.chip_ratio = cut.uncut_chip_thickness_m / s.chip_thickness_m;
  r.evaluations = solver.evaluations();

  // Validity of the solution.
  std::vector<std::string> problems;
  const double x = s.thermal_number * std::tan(s.phi_rad);
  if (x < 0.04)
    problems.push_back(
        "thermal number × tan φ = " + format_value(x) +
        " is below 0.04, outside Boothroyd's heat-partition correlation (the cutting speed or "
        "the uncut chip thickness is too small for the theory)");
  if (s.temperature_interface_c >= material.flow.melting_temperature_c)
    problems.push_back(
        "tool–chip interface temperature " + format_value(s.temperature_interface_c) +
        " °C reaches the melting temperature " + format_value(material.flow.melting_temperature_c) +
        " °C (the cutting speed is too high for the theory)");
  if (!problems.empty()) throw InvalidInput(problems, kWhere);

  const double c0_margin = 1e-6 * (options.c0_max - options.c0_min);
  if (s.c0 <= options.c0_min + c0_margin || s.c0 >= options.c0_max - c0_margin)
    r.warnings.push_back("the strain-rate constant C0 = " + format_value(s.c0) +
                         " is on its search bound");
  if (delta <= d_lo * (1.0 + 1e-3) || delta >= d_hi * (1.0 - 1e-3))
    r.warnings.push_back("the least cutting force is at the bound δ = " + format_value(delta) +
                         " of the search range");
  return r;
}

}  // namespace cutdyn
