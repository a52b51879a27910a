#include "cutdyn/stability/multi_frequency.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/stability/detail/boundary_scan.hpp"
#include "cutdyn/stability/detail/large_eigenvalues.hpp"

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

double response_band_rad_s(const DelayedSystem& system) {
  // A mode's response |1/(1 − ρ² + 2iζρ)| (ρ = ω/ωn) falls to kFraction of its resonance
  // peak 1/(2ζ) at ρ² ≈ 1 + 2ζ/kFraction; a window that reaches there for every mode
  // truncates the response by at most that fraction (the critical depth by about 0.1 %:
  // docs/models/milling-stability.md).
  constexpr double kFraction = 0.05;
  const Eigen::VectorXcd poles = system.A0.eigenvalues();
  double band = 0.0;
  for (Eigen::Index i = 0; i < poles.size(); ++i) {
    const double wn = std::abs(poles(i));
    const double zeta = wn > 0.0 ? -poles(i).real() / wn : 1.0;
    band = std::max(band, wn * std::sqrt(1.0 + 2.0 * zeta / kFraction));
  }
  return band;
}

namespace {

// The shortest contact pulse or gap of any term's coefficient: the shortest stretch between
// two of its jumps, taken around the period (the last jump to the first one of the next
// period), as a fraction of the period; 1 when a term has at most one jump. Each term by
// itself: the harmonics of K couple through each term's own coefficients (the header), so the
// short stretches between one tooth's jump and another's (uneven pitch) do not spread them.
double shortest_segment_fraction(const DelayedSystem& system) {
  const double T = system.H.period_s;
  double shortest = 1.0;
  for (const DelayTerm& term : system.delay_terms()) {
    std::vector<double> b;
    for (double t : term.H.breakpoints_s) b.push_back(std::fmod(std::fmod(t, T) + T, T));
    if (b.size() < 2) continue;
    std::sort(b.begin(), b.end());
    b.push_back(b.front() + T);
    for (std::size_t i = 0; i + 1 < b.size(); ++i) {
      const double length = (b[i + 1] - b[i]) / T;
      if (length > 1e-9) shortest = std::min(shortest, length);  // coinciding jumps: one
    }
  }
  return shortest;
}

}  // namespace

int multi_frequency_harmonics(const DelayedSystem& system, const MultiFrequencyOptions& o,
                              bool* truncated) {
  if (truncated) *truncated = false;
  if (system.H.constant || o.harmonics == 0) return 0;
  if (o.exact_harmonics) return o.harmonics;
  const double Omega = kTwoPi / system.H.period_s;
  // Reach the response band, plus the spread of a narrow contact pulse's spectrum: the
  // coefficients H_(p−q) of a pulse of a fraction δ of the period couple a harmonic at a mode
  // to about 1/δ harmonics either side, which must be in the window too (a/D = 0.05 with
  // the band alone gave depths 10–27 % off). 1.5 harmonics per pulse length keep the depth
  // within about 0.5 % of the full discretization (docs/models/milling-stability.md).
  constexpr double kHarmonicsPerPulse = 1.5;
  const double needed = std::ceil(response_band_rad_s(system) / Omega) +
                        std::ceil(kHarmonicsPerPulse / shortest_segment_fraction(system) - 1e-9);
  if (needed > o.max_harmonics) {
    if (truncated) *truncated = true;
    return std::max(o.harmonics, o.max_harmonics);
  }
  return std::max(o.harmonics, static_cast<int>(needed));
}

std::vector<std::string> MultiFrequencyOptions::validate() const {
  Validator v;
  const FieldSpec& h = stability_fields::kHarmonics;  // one range for the key everywhere
  if (!h.range.contains(harmonics)) v.require(false, h.key, harmonics, "", h.range.rule());
  v.require(max_harmonics >= 1 && max_harmonics <= 500, "max_harmonics", max_harmonics, "",
            "must be 1 to 500");
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

namespace {

// K(ω) over the harmonic window p = lo..hi (see the header), built in place. With no harmonics
// (lo = hi = 0) it is G(ω)·H0·(e^(−iωτ) − 1), the zero-order matrix of eq. MS-6
// (docs/models/milling-stability.md).
class HillMatrix {
 public:
  HillMatrix(const DelayedSystem& system, int max_index, bool periodic)
      : system_(system),
        terms_(system.delay_terms()),
        omega_(periodic ? kTwoPi / system.H.period_s : 0.0),
        r_(system.outputs()),
        max_index_(max_index) {
    // Fourier coefficients H_k(m), m = −max_index..max_index, of every term.
    for (const DelayTerm& t : terms_) {
      std::vector<Eigen::MatrixXcd> hk;
      for (int m = -max_index; m <= max_index; ++m) {
        hk.push_back(t.H.fourier(m));
        if (periodic || m == 0) norm_ += hk.back().norm();
      }
      if (r_ == 1) h1_.emplace_back(hk.begin(), hk.end());
      if (r_ == 2) h2_.emplace_back(hk.begin(), hk.end());
      h_.push_back(std::move(hk));
    }
  }

  double coefficient_norm() const { return norm_; }

  void build(double w, int lo, int hi, Eigen::MatrixXcd& K) {
    const int n = hi - lo + 1;
    G_.resize(static_cast<std::size_t>(n));
    regen_.resize(terms_.size());
    for (std::vector<cplx>& r : regen_) r.resize(static_cast<std::size_t>(n));
    for (int p = lo; p <= hi; ++p) {
      const double wp = w + p * omega_;
      const auto i = static_cast<std::size_t>(p - lo);
      system_.frequency_response(wp, G_[i]);
      for (std::size_t k = 0; k < terms_.size(); ++k)
        regen_[k][i] = std::polar(1.0, -wp * terms_[k].delay_s) - 1.0;
    }
    K.resize(r_ * n, r_ * n);
    // One or two directions (turning, milling): fixed-size arithmetic, several times faster
    // than dynamic blocks; with many harmonics, building K costs as much as the eigenvalues
    // the scan needs of it.
    if (r_ == 1) return build_fixed(lo, hi, h1_, G1_, K);
    if (r_ == 2) return build_fixed(lo, hi, h2_, G2_, K);
    sum_.resize(r_, r_);
    for (int p = lo; p <= hi; ++p) {
      for (int q = lo; q <= hi; ++q) {
        sum_.setZero();
        for (std::size_t k = 0; k < terms_.size(); ++k)
          sum_ += h_[k][static_cast<std::size_t>(p - q + max_index_)] *
                  regen_[k][static_cast<std::size_t>(q - lo)];
        K.block((p - lo) * r_, (q - lo) * r_, r_, r_).noalias() =
            G_[static_cast<std::size_t>(p - lo)] * sum_;
      }
    }
  }

 private:
  const DelayedSystem& system_;
  std::vector<DelayTerm> terms_;
  double omega_;
  int r_;
  int max_index_;
  double norm_ = 0.0;
  std::vector<std::vector<Eigen::MatrixXcd>> h_;
  std::vector<Eigen::MatrixXcd> G_;
  std::vector<std::vector<cplx>> regen_;
  Eigen::MatrixXcd sum_;  // Σ_k H_k(p − q)·(e^(−iω_q τ_k) − 1), reused
  // The same in fixed size, for one and two directions.
  std::vector<std::vector<Eigen::Matrix<cplx, 1, 1>>> h1_;
  std::vector<Eigen::Matrix<cplx, 1, 1>> G1_;
  std::vector<std::vector<Eigen::Matrix2cd>> h2_;
  std::vector<Eigen::Matrix2cd> G2_;

  template <int R>
  void build_fixed(int lo, int hi, const std::vector<std::vector<Eigen::Matrix<cplx, R, R>>>& h,
                   std::vector<Eigen::Matrix<cplx, R, R>>& G, Eigen::MatrixXcd& K) const {
    using Block = Eigen::Matrix<cplx, R, R>;
    G.assign(G_.begin(), G_.end());
    for (int q = lo; q <= hi; ++q) {
      const auto j = static_cast<std::size_t>(q - lo);
      for (int p = lo; p <= hi; ++p) {
        Block sum = Block::Zero();
        for (std::size_t k = 0; k < terms_.size(); ++k)
          sum += h[k][static_cast<std::size_t>(p - q + max_index_)] * regen_[k][j];
        K.template block<R, R>(R * (p - lo), R * (q - lo)).noalias() =
            G[static_cast<std::size_t>(p - lo)] * sum;
      }
    }
  }
};

// Real eigenvalues λ >= min_eigenvalue of K: boundary points at the scan's ends, where K is
// similar to its complex conjugate (real eigenvalues are real up to rounding). Each is a depth
// w = 1/λ, as in eq. MS-6 (docs/models/milling-stability.md).
void real_boundary_points(const Eigen::MatrixXcd& K, double theta, double min_eigenvalue,
                          bool dense, std::vector<BoundaryPoint>& points, long long& evaluations) {
  ++evaluations;
  detail::LargeEigenvalues solver(dense);
  solver.compute(K, min_eigenvalue, true);
  const Eigen::VectorXcd& values = solver.eigenvalues();
  for (Eigen::Index i = 0; i < values.size(); ++i) {
    const cplx v = values(i);
    if (v.real() >= min_eigenvalue && std::abs(v.imag()) <= 1e-7 * std::abs(v))
      points.push_back({theta, 1.0 / v.real(), v, solver.eigenvectors().col(i)});
  }
}

}  // namespace

CriticalDepth multi_frequency_critical_depth(const DelayedSystem& system,
                                             const MultiFrequencyOptions& o) {
  require_valid(system, o.validate());
  const int r = system.outputs();
  bool truncated = false;
  const int P = multi_frequency_harmonics(system, o, &truncated);
  const bool periodic = P > 0;
  const double Omega = periodic ? kTwoPi / system.H.period_s : 0.0;
  double tau = 0.0;  // the longest delay sets the sampling
  for (const DelayTerm& t : system.delay_terms()) tau = std::max(tau, t.delay_s);

  // The scan's window is p = −P−1..P (symmetric about zero frequency at ω = Ω/2); the end
  // point ω = 0 is symmetric with p = −P..P.
  const int lo = periodic ? -P - 1 : 0, hi = P;
  HillMatrix hill(system, periodic ? 2 * P + 1 : 0, periodic);
  const double w_limit = response_limit_rad_s(system, hill.coefficient_norm(), o.depth_max_m);
  // Beyond w_limit every harmonic ω + pΩ of a base ω in [w_limit, Ω/2] is too, so no
  // eigenvalue can reach the depth limit there.
  const double w_max = periodic ? std::min(0.5 * Omega, w_limit) : w_limit;
  // Steps of at most 1/samples_per_turn of the delay's phase turn, and, near a resonance, a
  // quarter of the distance from the nearest harmonic iω' = i(ω + pΩ) of the window to the
  // nearest pole s_r of the structure: G(ω') changes by a fraction of about h/|iω' − s_r| over
  // a step h, so a quarter of that distance moves the eigenvalues as little as a quarter of the
  // half-bandwidth does at the peak (docs/models/milling-stability.md, "Frequency samples",
  // MF-1 and MF-2).
  const double delay_step = kTwoPi / (o.samples_per_turn * tau);
  const Eigen::VectorXcd poles = system.A0.eigenvalues();
  const auto pole_distance = [&](double w) {
    double d = std::numeric_limits<double>::infinity();
    for (Eigen::Index i = 0; i < poles.size(); ++i) {
      const cplx s = poles(i);
      // The harmonic of the window nearest the pole's frequency, and its neighbours.
      double p_near = periodic ? std::round((s.imag() - w) / Omega) : 0.0;
      p_near = std::clamp(p_near, static_cast<double>(lo), static_cast<double>(hi));
      for (double p = std::max<double>(lo, p_near - 1); p <= std::min<double>(hi, p_near + 1);
           p += 1.0)
        d = std::min(d, std::abs(cplx(0.0, w + p * Omega) - s));
    }
    return d;
  };

  const double min_eigenvalue = 1.0 / o.depth_max_m;
  const MatrixFunction evaluate = [&](double w, Eigen::MatrixXcd& K) {
    hill.build(w, lo, hi, K);
    return K.norm() >= 0.5 * min_eigenvalue;  // as the scan's own margin
  };
  BoundaryScanOptions scan;
  scan.theta_min = 0.0;
  scan.theta_max = w_max;
  if (o.uniform_step) {
    scan.theta_step = std::min(delay_step, 0.25 * sharpest_half_bandwidth(system));
  } else {
    scan.theta_step = delay_step;
    scan.step_at = [&](double w) { return 0.25 * pole_distance(w); };
  }
  scan.min_eigenvalue = min_eigenvalue;
  scan.dense = o.dense_eigenvalues;
  BoundaryScanReport report = scan_boundary(evaluate, scan);
  if (periodic) {
    // Flip (ω = Ω/2) and fold (ω = 0) boundaries: real eigenvalues at the ends.
    Eigen::MatrixXcd K;
    if (0.5 * Omega <= w_limit) {
      hill.build(0.5 * Omega, lo, hi, K);
      real_boundary_points(K, 0.5 * Omega, min_eigenvalue, o.dense_eigenvalues, report.points,
                           report.evaluations);
    }
    hill.build(0.0, -P, P, K);
    if (K.norm() >= min_eigenvalue)
      real_boundary_points(K, 0.0, min_eigenvalue, o.dense_eigenvalues, report.points,
                           report.evaluations);
    std::sort(report.points.begin(), report.points.end(),
              [](const BoundaryPoint& a, const BoundaryPoint& b) { return a.depth < b.depth; });
  }
  CriticalDepth result = critical_depth_from_scan(report, o.depth_max_m);
  result.truncated = truncated;
  if (!result.found) return result;
  const BoundaryPoint& best = report.points.front();
  result.bifurcation =
      periodic ? classify_multiplier(best.theta * system.H.period_s) : Bifurcation::kHopf;
  // The chatter frequency is the harmonic that carries most of the vibration: the
  // eigenvector holds the displacement harmonics Yp.
  int dominant = 0;
  if (periodic) {
    const int first = best.theta == 0.0 ? -P : lo;
    const auto count = best.eigenvector.size() / r;
    double largest = -1.0;
    for (Eigen::Index i = 0; i < count; ++i) {
      const double weight = best.eigenvector.segment(i * r, r).norm();
      if (weight > largest) {
        largest = weight;
        dominant = first + static_cast<int>(i);
      }
    }
  }
  result.chatter_hz = std::abs(units::rad_per_s_to_hz(best.theta + dominant * Omega));
  return result;
}

}  // namespace cutdyn
