#include "cutdyn/stability/milling.hpp"

#include <cmath>
#include <complex>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn {
namespace {

using cplx = std::complex<double>;
using units::kPi;
using units::kTwoPi;

// ∫_a^b e^(iκφ) dφ.
cplx exp_integral(double kappa, double a, double b) {
  if (kappa == 0.0) return {b - a, 0.0};
  const cplx i(0.0, 1.0);
  return (std::exp(i * kappa * b) - std::exp(i * kappa * a)) / (i * kappa);
}

// ∫_a^b A(φ) e^(−iκφ) dφ for Altintas' directional matrix, from the integrals of
// e^(−iκφ), e^(i(2−κ)φ) and e^(−i(2+κ)φ) (sin 2φ and cos 2φ as exponentials).
Eigen::Matrix2cd directional_integral(double kappa, double a, double b, double kr) {
  const cplx i(0.0, 1.0);
  const cplx one = exp_integral(-kappa, a, b);
  const cplx ep = exp_integral(2.0 - kappa, a, b);   // e^(2iφ)
  const cplx em = exp_integral(-2.0 - kappa, a, b);  // e^(−2iφ)
  const cplx s2 = (ep - em) / (2.0 * i);             // ∫ sin 2φ·e^(−iκφ)
  const cplx c2 = (ep + em) / 2.0;                   // ∫ cos 2φ·e^(−iκφ)
  Eigen::Matrix2cd m;
  m(0, 0) = -s2 - kr * (one - c2);
  m(0, 1) = -(one + c2) - kr * s2;
  m(1, 0) = (one - c2) - kr * s2;
  m(1, 1) = s2 - kr * (one + c2);
  return m;
}

// ∫ over φ in [a, b] of A(φ)·g(φ)·e^(−iκφ), with g the window [φst, φex] repeated every 2π.
Eigen::Matrix2cd windowed_integral(double kappa, double a, double b, double st, double ex,
                                   double kr) {
  Eigen::Matrix2cd sum = Eigen::Matrix2cd::Zero();
  const double k0 = std::floor((a - ex) / kTwoPi);
  for (double k = k0; st + kTwoPi * k < b; k += 1.0) {
    const double lo = std::max(a, st + kTwoPi * k);
    const double hi = std::min(b, ex + kTwoPi * k);
    if (hi > lo) sum += directional_integral(kappa, lo, hi, kr);
  }
  return sum;
}

}  // namespace

Eigen::Matrix2d milling_directional_matrix(double phi, double kr) {
  const double s2 = std::sin(2.0 * phi), c2 = std::cos(2.0 * phi);
  Eigen::Matrix2d a;
  a << -s2 - kr * (1.0 - c2), -(1.0 + c2) - kr * s2, (1.0 - c2) - kr * s2, s2 - kr * (1.0 + c2);
  return a;
}

std::vector<std::string> MillingModel::validate() const {
  Validator v;
  v.merge(modal.validate());
  for (std::size_t i = 0; i < modal.modes.size(); ++i) {
    v.require(modal.modes[i].damping_ratio > 0.0, "modes[" + std::to_string(i) + "].damping_ratio",
              modal.modes[i].damping_ratio, "", "must be positive for a stability analysis");
  }
  v.require_positive("kt_pa", kt_pa, "N/m²");
  v.require(kr_pa >= 0.0, "kr_pa", kr_pa, "N/m²", "must not be negative");
  v.require(teeth >= 1 && teeth <= 200, "teeth", teeth, "", "must be 1 to 200");
  v.require(radial_immersion > 0.0 && radial_immersion <= 1.0, "radial_immersion", radial_immersion,
            "", "must be greater than 0 and at most 1");
  return v.problems();
}

double MillingModel::entry_angle() const {
  return down_milling ? std::acos(2.0 * radial_immersion - 1.0) : 0.0;
}

double MillingModel::exit_angle() const {
  return down_milling ? kPi : std::acos(1.0 - 2.0 * radial_immersion);
}

DelayedSystem milling_system(const MillingModel& model, double rpm) {
  if (const auto problems = model.validate(); !problems.empty())
    throw InvalidInput(problems, "milling model");
  const auto ss = modal_state_space(model.modal, {Direction::kX, Direction::kY});
  DelayedSystem s;
  s.A0 = ss.A;
  s.E = ss.B;
  s.C = ss.C;
  const double spindle = units::rpm_to_rad_per_s(rpm);  // Ωs
  const int z = model.teeth;
  const double T = kTwoPi / (z * spindle);  // tooth period
  s.delay_s = T;
  const double st = model.entry_angle(), ex = model.exit_angle();
  const double kr = model.kr_pa / model.kt_pa;
  const double scale = -0.5 * model.kt_pa;  // H = −(Kt/2)·A
  const double pitch = kTwoPi / z;

  PeriodicCoefficient h;
  h.dim = 2;
  h.period_s = T;
  for (double edge : {st, ex}) {
    const double t = std::fmod(edge, pitch) / spindle;
    if (t > 0.0 && t < T) h.breakpoints_s.push_back(t);
  }
  // Mean over [t0, t1]: every tooth sweeps [Ωs·t0 + 2πj/z, Ωs·t1 + 2πj/z].
  h.mean = [=](double t0, double t1) {
    Eigen::Matrix2cd sum = Eigen::Matrix2cd::Zero();
    for (int j = 0; j < z; ++j) {
      sum += windowed_integral(0.0, spindle * t0 + pitch * j, spindle * t1 + pitch * j, st, ex, kr);
    }
    return Eigen::MatrixXd(scale * sum.real() / (spindle * (t1 - t0)));
  };
  // H_p = (z/2π)·∫ over one revolution of one tooth of h(φ)·e^(−ipzφ) dφ.
  h.fourier = [=](int p) {
    const Eigen::Matrix2cd m =
        windowed_integral(static_cast<double>(p) * z, 0.0, kTwoPi, st, ex, kr) *
        (z / kTwoPi * scale);
    return Eigen::MatrixXcd(m);
  };
  s.H = std::move(h);
  return s;
}

}  // namespace cutdyn
