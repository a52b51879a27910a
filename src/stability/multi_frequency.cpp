#include "cutdyn/stability/multi_frequency.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/stability/boundary_scan.hpp"

namespace cutdyn {

using cplx = std::complex<double>;
using units::kTwoPi;

double sharpest_half_bandwidth(const DelayedSystem& system) {
  const Eigen::VectorXcd poles = system.A0.eigenvalues();
  double b = std::numeric_limits<double>::infinity();
  for (Eigen::Index i = 0; i < poles.size(); ++i) b = std::min(b, -poles(i).real());
  return b;
}

double response_limit_rad_s(const DelayedSystem& system, double coefficient_norm,
                            double depth_max_m) {
  const Eigen::VectorXcd poles = system.A0.eigenvalues();
  double w_top = 0.0;
  for (Eigen::Index i = 0; i < poles.size(); ++i) w_top = std::max(w_top, std::abs(poles(i)));
  // |λ| <= ‖G‖·‖H‖·2; beyond the highest pole ‖G‖ falls off, so step up until it is too small
  // and stays so over the next doubling.
  const double need = 1.0 / depth_max_m;
  double w = std::max(1.5 * w_top, 1.0);
  for (int i = 0; i < 400; ++i, w *= 1.1) {
    const double g = system.frequency_response(w).norm();
    const double g2 = system.frequency_response(2.0 * w).norm();
    if (2.0 * coefficient_norm * std::max(g, g2) < 0.5 * need) return w;
  }
  return w;
}

std::vector<std::string> MultiFrequencyOptions::validate() const {
  Validator v;
  v.require(harmonics >= 0 && harmonics <= 50, "harmonics", harmonics, "", "must be 0 to 50");
  v.require_positive("depth_max_m", depth_max_m, "m");
  v.require(samples_per_turn >= 4.0 && samples_per_turn <= 1000.0, "samples_per_turn",
            samples_per_turn, "", "must be 4 to 1000");
  return v.problems();
}

void require_valid(const DelayedSystem& system, const std::vector<std::string>& option_problems) {
  Validator v;
  v.merge(system.validate());
  v.merge(option_problems);
  v.throw_if_any("stability analysis");
}

CriticalDepth multi_frequency_critical_depth(const DelayedSystem& system,
                                             const MultiFrequencyOptions& o) {
  require_valid(system, o.validate());
  const int r = system.outputs();
  const bool periodic = !system.H.constant && o.harmonics > 0;
  const int P = periodic ? o.harmonics : 0;
  const int size = r * (2 * P + 1);
  const double Omega = periodic ? kTwoPi / system.H.period_s : 0.0;
  // One or more regenerative terms Σk Hk(t)·(x(t − τk) − x(t)).
  const std::vector<DelayTerm> terms = system.delay_terms();
  const auto n_terms = terms.size();
  double tau = 0.0;  // the longest delay sets the sampling
  for (const DelayTerm& t : terms) tau = std::max(tau, t.delay_s);

  // Fourier coefficients Hk(m), m = −2P..2P, of every term.
  std::vector<std::vector<Eigen::MatrixXcd>> Hk(n_terms);
  double h_norm = 0.0;
  for (std::size_t k = 0; k < n_terms; ++k) {
    for (int m = -2 * P; m <= 2 * P; ++m) {
      Hk[k].push_back(terms[k].H.fourier(m));
      if (periodic) h_norm += Hk[k].back().norm();
    }
    if (!periodic) h_norm += Hk[k][0].norm();
  }

  const double w_limit = response_limit_rad_s(system, h_norm, o.depth_max_m);
  const double w_max = periodic ? std::min(0.5 * Omega, w_limit) : w_limit;
  const double step =
      std::min(kTwoPi / (o.samples_per_turn * tau), 0.25 * sharpest_half_bandwidth(system));

  std::vector<Eigen::MatrixXcd> G(static_cast<std::size_t>(2 * P + 1));
  std::vector<std::vector<cplx>> regen(n_terms, std::vector<cplx>(2 * P + 1));
  Eigen::MatrixXcd sum(r, r);
  const double min_eigenvalue = 1.0 / o.depth_max_m;
  const MatrixFunction evaluate = [&](double w, Eigen::MatrixXcd& K) {
    for (int p = -P; p <= P; ++p) {
      const double wp = w + p * Omega;
      G[static_cast<std::size_t>(p + P)] = system.frequency_response(wp);
      for (std::size_t k = 0; k < n_terms; ++k)
        regen[k][static_cast<std::size_t>(p + P)] =
            std::exp(cplx(0.0, -wp * terms[k].delay_s)) - 1.0;
    }
    K.resize(size, size);
    for (int p = -P; p <= P; ++p) {
      for (int q = -P; q <= P; ++q) {
        sum.setZero();
        for (std::size_t k = 0; k < n_terms; ++k)
          sum += Hk[k][static_cast<std::size_t>(p - q + 2 * P)] *
                 regen[k][static_cast<std::size_t>(q + P)];
        K.block((p + P) * r, (q + P) * r, r, r) = G[static_cast<std::size_t>(p + P)] * sum;
      }
    }
    return K.norm() >= 0.5 * min_eigenvalue;  // as the scan's own margin
  };

  BoundaryScanOptions scan;
  scan.theta_min = 0.0;
  scan.theta_max = w_max;
  scan.theta_step = step;
  scan.min_eigenvalue = min_eigenvalue;
  const BoundaryScanReport report = scan_boundary(evaluate, scan);
  CriticalDepth result = critical_depth_from_scan(report, o.depth_max_m);
  if (!result.found) return result;
  result.bifurcation = Bifurcation::kHopf;
  const BoundaryPoint& best = report.points.front();
  // The chatter frequency is the harmonic that carries most of the vibration.
  // The eigenvector holds the displacement harmonics Yp: take the largest.
  Eigen::Index dominant = P;
  if (P > 0) {
    Eigen::VectorXd weight(2 * P + 1);
    for (int p = 0; p < 2 * P + 1; ++p) weight(p) = best.eigenvector.segment(p * r, r).norm();
    weight.maxCoeff(&dominant);
  }
  result.chatter_hz =
      std::abs(units::rad_per_s_to_hz(best.theta + static_cast<double>(dominant - P) * Omega));
  return result;
}

}  // namespace cutdyn
