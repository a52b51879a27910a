#include "cutdyn/stability/delayed_system.hpp"

#include <cmath>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn {

PeriodicCoefficient constant_coefficient(const Eigen::MatrixXd& h0) {
  PeriodicCoefficient h;
  h.dim = static_cast<int>(h0.rows());
  h.constant = true;
  h.period_s = 1.0;
  h.mean = [h0](double, double) { return h0; };
  h.fourier = [h0](int p) {
    return p == 0 ? Eigen::MatrixXcd(h0.cast<std::complex<double>>())
                  : Eigen::MatrixXcd::Zero(h0.rows(), h0.cols()).eval();
  };
  return h;
}

PeriodicCoefficient windowed_coefficient(const Eigen::MatrixXd& h0, double period_s,
                                         double duty_cycle, double start_s) {
  if (duty_cycle >= 1.0) return constant_coefficient(h0);
  PeriodicCoefficient h;
  h.dim = static_cast<int>(h0.rows());
  h.period_s = period_s;
  const double T = period_s;
  const double a = std::fmod(std::fmod(start_s, T) + T, T);  // contact start in [0, T)
  const double b = a + duty_cycle * T;                       // contact end, may pass T
  h.breakpoints_s = {a};
  if (b < T) {
    h.breakpoints_s.push_back(b);
  } else if (b > T) {
    h.breakpoints_s.insert(h.breakpoints_s.begin(), b - T);
  }
  // Contact measure of [t0, t1] within one period, contact = [a, b) ∪ [a − T, b − T).
  const auto overlap = [](double lo, double hi, double c0, double c1) {
    return std::max(0.0, std::min(hi, c1) - std::max(lo, c0));
  };
  h.mean = [h0, a, b, T, overlap](double t0, double t1) {
    const double c = overlap(t0, t1, a, b) + overlap(t0, t1, a - T, b - T);
    return Eigen::MatrixXd(h0 * (c / (t1 - t0)));
  };
  h.fourier = [h0, a, b, T, duty_cycle](int p) {
    if (p == 0) return Eigen::MatrixXcd(h0.cast<std::complex<double>>() * duty_cycle);
    // (1/T)∫_a^b e^{−ipΩt} dt = (e^{−ipΩa} − e^{−ipΩb}) / (i p Ω T), Ω = 2π/T.
    const double w = units::kTwoPi * p / T;
    const std::complex<double> i(0.0, 1.0);
    const std::complex<double> g = (std::exp(-i * w * a) - std::exp(-i * w * b)) / (i * w * T);
    return Eigen::MatrixXcd(h0.cast<std::complex<double>>() * g);
  };
  return h;
}

std::vector<std::string> DelayedSystem::validate() const {
  Validator v;
  const auto d = A0.rows();
  const auto r = C.rows();
  if (A0.cols() != d || d == 0) v.add("A0: must be square and non-empty");
  if (E.rows() != d || E.cols() != r) v.add("E: must be states × outputs");
  if (C.cols() != d || r == 0) v.add("C: must be outputs × states");
  if (H.dim != r) v.add("H.dim: must equal the number of outputs");
  if (!H.mean || !H.fourier) v.add("H: mean and fourier must be set");
  v.require_positive("delay_s", delay_s, "s");
  if (!H.constant) v.require_positive("H.period_s", H.period_s, "s");
  for (std::size_t k = 0; k < more_delays.size(); ++k) {
    const DelayTerm& t = more_delays[k];
    const std::string name = "more_delays[" + std::to_string(k) + "]";
    if (t.H.dim != r) v.add(name + ".H.dim: must equal the number of outputs");
    if (!t.H.mean || !t.H.fourier) v.add(name + ".H: mean and fourier must be set");
    v.require_positive(name + ".delay_s", t.delay_s, "s");
    if (t.H.constant != H.constant || (!H.constant && t.H.period_s != H.period_s))
      v.add(name + ".H: must have the period of H");
  }
  if (v.ok()) {
    const Eigen::VectorXcd eig = A0.eigenvalues();
    for (Eigen::Index i = 0; i < eig.size(); ++i) {
      if (!(eig(i).real() < 0.0)) {
        v.add("A0: the structure alone must be asymptotically stable (every mode damped)");
        break;
      }
    }
  }
  return v.problems();
}

std::vector<DelayTerm> DelayedSystem::delay_terms() const {
  std::vector<DelayTerm> terms{DelayTerm{H, delay_s}};
  terms.insert(terms.end(), more_delays.begin(), more_delays.end());
  return terms;
}

Eigen::MatrixXcd DelayedSystem::frequency_response(double omega_rad_s) const {
  Eigen::MatrixXcd g;
  frequency_response(omega_rad_s, g);
  return g;
}

void DelayedSystem::frequency_response(double omega_rad_s, Eigen::MatrixXcd& g) const {
  if (measured_response) {
    measured_response(omega_rad_s, g);
    return;
  }
  Eigen::MatrixXcd m = -A0.cast<std::complex<double>>();
  m.diagonal().array() += std::complex<double>(0.0, omega_rad_s);
  g = C.cast<std::complex<double>>() * m.partialPivLu().solve(E.cast<std::complex<double>>());
}

}  // namespace cutdyn
