#include "cutdyn/stability/full_discretization.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <optional>
#include <stdexcept>
#include <tuple>
// GCC 12 reports a false -Wuse-after-free inside Spectra's inlined Eigen code.
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ >= 12
#pragma GCC diagnostic ignored "-Wuse-after-free"
#endif
#include <Spectra/GenEigsSolver.h>
#include <Spectra/LinAlg/UpperHessenbergEigen.h>
#include <Spectra/Util/SimpleRandom.h>

#include <unsupported/Eigen/MatrixFunctions>

#include "cutdyn/core/detail/roots.hpp"
#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/stability/detail/boundary_scan.hpp"
#include "cutdyn/stability/detail/chatter_harmonic.hpp"
#include "cutdyn/stability/lobes.hpp"
#include "cutdyn/stability/multi_frequency.hpp"

namespace cutdyn {
namespace detail {

using cplx = std::complex<double>;
using units::kTwoPi;

// The harmonic (θ + 2πk)/T that carries most of a Floquet solution sampled at `times`.
// The factors e^(−i·ωk·t) are advanced from k to k + 1 by one rotation per sample; the
// samples are kept as separate real and imaginary arrays so that each harmonic's sum and the
// rotation of every factor run as plain loops over the samples (the compiler vectorizes them).
double dominant_frequency_hz(double theta, double period, const std::vector<double>& times,
                             const std::vector<cplx>& values, int steps) {
  const int kmax = std::max(0, steps / 2);
  const std::size_t m = times.size();
  std::vector<double> fr(m), fi(m), rr(m), ri(m);
  for (std::size_t i = 0; i < m; ++i) {
    const double t = times[i];
    const cplx rotation = std::polar(1.0, -kTwoPi * t / period);
    const cplx factor = values[i] * std::polar(1.0, -(theta - kTwoPi * kmax) * t / period);
    fr[i] = factor.real();
    fi[i] = factor.imag();
    rr[i] = rotation.real();
    ri[i] = rotation.imag();
  }
  std::size_t best = 0;
  double best_norm = -1.0;
  for (int k = 0; k <= 2 * kmax; ++k) {
    double sr = 0.0, si = 0.0;
    for (std::size_t i = 0; i < m; ++i) {
      sr += fr[i];
      si += fi[i];
    }
    const double norm = sr * sr + si * si;
    if (norm > best_norm) {
      best_norm = norm;
      best = static_cast<std::size_t>(k);
    }
    for (std::size_t i = 0; i < m; ++i) {
      const double a = fr[i] * rr[i] - fi[i] * ri[i];
      fi[i] = fr[i] * ri[i] + fi[i] * rr[i];
      fr[i] = a;
    }
  }
  const double w = (theta + kTwoPi * (static_cast<double>(best) - kmax)) / period;
  return std::abs(units::rad_per_s_to_hz(w));
}

// The same harmonic when the samples are uniform, t_i = −i·h with h = period/n: the factor
// of harmonic k is then e^(i·2πk·i/n), periodic in i with period n, so the samples folded
// modulo n, G_q, give every harmonic's sum S_k = Σq G_q·e^(i·2πkq/n) (k = 0 … n − 1; k = n,
// the same sum as k = 0, loses the tie to it as in the direct sum). Parseval bounds what the
// harmonics not yet summed can hold, Σk |S_k|² = n·Σq |G_q|², so the sums are taken from the
// lowest frequency up and stop once the largest so far exceeds everything left: the
// chatter frequency lies near a structural mode, far below the steps' Nyquist frequency, and
// a few harmonics settle it instead of all n.
double dominant_frequency_hz_uniform(double theta, double period, int n,
                                     const std::vector<cplx>& values) {
  const int kmax = n / 2;
  const auto un = static_cast<std::size_t>(n);
  std::vector<cplx> folded(un, cplx(0.0, 0.0)), roots(un);
  // The factors e^(i·(θ − 2π·kmax)·i/n) and the roots e^(i·2πq/n) by recurrence, each a
  // product of powers of one rotation: exact to about i·ε (a few hundred samples), where a
  // sine and cosine each cost several times as much.
  const cplx turn = std::polar(1.0, (theta - kTwoPi * kmax) / n);
  cplx factor(1.0, 0.0);
  std::size_t slot = 0;  // i mod n
  for (std::size_t i = 0; i < values.size(); ++i) {
    folded[slot] += values[i] * factor;
    factor *= turn;
    if (++slot == un) slot = 0;
  }
  double total = 0.0;
  for (const cplx& g : folded) total += std::norm(g);
  total *= n;
  const cplx root = std::polar(1.0, kTwoPi / n);
  roots[0] = cplx(1.0, 0.0);
  for (std::size_t k = 1; k < un; ++k) roots[k] = roots[k - 1] * root;
  // Harmonics k = 0 … n − 1 by their frequency |θ + 2π(k − kmax)|/T, lowest first.
  std::vector<int> order(un);
  for (int k = 0; k < n; ++k) order[static_cast<std::size_t>(k)] = k;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const double fa = std::abs(theta + kTwoPi * (a - kmax)),
                 fb = std::abs(theta + kTwoPi * (b - kmax));
    return fa < fb || (fa == fb && a < b);
  });
  int best = -1;
  double best_norm = -1.0, seen = 0.0;
  for (int k : order) {
    cplx sum(0.0, 0.0);
    std::size_t index = 0;  // k·q mod n
    for (std::size_t q = 0; q < un; ++q) {
      sum += folded[q] * roots[index];
      index += static_cast<std::size_t>(k);
      if (index >= un) index -= un;
    }
    const double norm = std::norm(sum);
    seen += norm;
    if (norm > best_norm || (norm == best_norm && k < best)) {
      best_norm = norm;
      best = k;
    }
    if (best_norm > (total - seen) + 1e-9 * total) break;
  }
  const double w = (theta + kTwoPi * (static_cast<double>(best) - kmax)) / period;
  return std::abs(units::rad_per_s_to_hz(w));
}

}  // namespace detail

namespace {

using cplx = std::complex<double>;
using units::kPi;
using units::kTwoPi;

// Exact integrals of one step [Ding2010, eqs. 8–12]: Φ0 = e^(Ah), and the weights W0, W1
// of the step's start and end values of a linearly interpolated forcing, from one matrix
// exponential of the block matrix [[A, I, 0], [0, 0, I], [0, 0, 0]]·h [VanLoan1978]. For the
// quadratic interpolation also the moments Mp = ∫0^h e^(A(h−s))·s^p ds, p = 0 … 3, times E,
// from the exponential of the longer chain [[A, I, 0, 0, 0], [0, 0, I, 0, 0], …]·h. The step
// is eq. MS-7 of docs/models/milling-stability.md, the moments its eq. MS-10.
struct StepIntegrals {
  double h = 0.0;        // the step length
  Eigen::MatrixXd phi0;  // d×d
  Eigen::MatrixXd w0E;   // W0·E, d×r
  Eigen::MatrixXd w1E;   // W1·E, d×r
  // Quadratic interpolation only: Mp·E and (Mp+1 − h/2·Mp)·E, p = 0 … 2 (d×r), the weights of
  // H̄ and of H' in a step's moment of order p.
  std::array<Eigen::MatrixXd, 3> mE, centred_mE;
};

// A diagonal D of powers of two (so exact in floating point) that balances A: the rows and
// columns of D⁻¹·A·D have comparable norms [Parlett & Reinsch]. A structure's state mixes
// displacements and velocities, so A holds both 1 and ω² (‖A‖ ~ 3e7 for a 922 Hz mode), and
// the exponential of A·h over a step of 1/32 of its period would be scaled and squared 8 times
// for a norm of ~1e3; balanced, its norm is ~ω·h ≈ 0.2 and a low-degree Padé approximant
// needs no squaring.
Eigen::VectorXd balancing_scale(const Eigen::MatrixXd& a) {
  const Eigen::Index d = a.rows();
  Eigen::MatrixXd b = a;
  Eigen::VectorXd scale = Eigen::VectorXd::Ones(d);
  for (int sweep = 0; sweep < 20; ++sweep) {
    bool changed = false;
    for (Eigen::Index i = 0; i < d; ++i) {
      const double c = b.col(i).cwiseAbs().sum() - std::abs(b(i, i));
      const double r = b.row(i).cwiseAbs().sum() - std::abs(b(i, i));
      if (!(c > 0.0 && r > 0.0) || !std::isfinite(c + r)) continue;
      const int k = static_cast<int>(std::lround(0.5 * std::log2(r / c)));
      if (k == 0) continue;
      const double f = std::ldexp(1.0, k);
      if (c * f + r / f >= 0.95 * (c + r)) continue;
      b.col(i) *= f;
      b.row(i) /= f;
      scale(i) *= f;
      changed = true;
    }
    if (!changed) break;
  }
  return scale;
}

// Φ0, W0·E and W1·E (and with `moments` M0·E … M3·E) for a step of length h (they depend on
// h only).
StepIntegrals step_integrals(const DelayedSystem& s, double h, bool moments) {
  const auto d = s.A0.rows();
  const Eigen::Index blocks = moments ? 5 : 3;
  // The exponential of the balanced chain D⁻¹·m·D (D the balancing of A0 on every block: the
  // identity blocks stay identities), each block of it brought back by D·(·)·D⁻¹.
  const Eigen::VectorXd scale = balancing_scale(s.A0);
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(blocks * d, blocks * d);
  m.topLeftCorner(d, d) = scale.cwiseInverse().asDiagonal() * s.A0 * scale.asDiagonal() * h;
  for (Eigen::Index b = 0; b + 1 < blocks; ++b)
    m.block(b * d, (b + 1) * d, d, d) = h * Eigen::MatrixXd::Identity(d, d);
  Eigen::MatrixXd f = m.exp();
  for (Eigen::Index b = 0; b < blocks; ++b) {
    auto block = f.block(0, b * d, d, d);
    block = scale.asDiagonal() * block * scale.cwiseInverse().asDiagonal();
  }
  // With the scaling above, block (1, p + 2) of f is ∫0^h e^(A(h−s))·s^p/p! ds: f12 = Φ1,
  // f13 = ∫0^h e^(A(h−s))·s ds (Mp/p!, eq. MS-10 of docs/models/milling-stability.md).
  const Eigen::MatrixXd phi1 = f.block(0, d, d, d);
  const Eigen::MatrixXd w1 = f.block(0, 2 * d, d, d) / h;
  StepIntegrals out;
  out.h = h;
  out.phi0 = f.topLeftCorner(d, d);
  out.w1E = w1 * s.E;
  out.w0E = (phi1 - w1) * s.E;
  if (moments) {
    std::array<Eigen::MatrixXd, 4> mE;  // Mp·E, p = 0 … 3
    double factorial = 1.0;
    for (int p = 0; p < 4; ++p) {
      if (p > 0) factorial *= p;
      mE[static_cast<std::size_t>(p)] = factorial * f.block(0, (p + 1) * d, d, d) * s.E;
    }
    for (std::size_t p = 0; p < 3; ++p) {
      out.mE[p] = mE[p];
      out.centred_mE[p] = mE[p + 1] - 0.5 * h * mE[p];
    }
  }
  return out;
}

// One step of the discretization: its integrals (shared by every step of the same length),
// H̄ of the first delay term, and the delay terms with H̄k ≠ 0 on it.
struct StepMatrices {
  const StepIntegrals* integrals = nullptr;
  Eigen::Index h_col = 0;            // H̄ = Discretization's h block at this column, r×r
  int first_term = 0, last_term = 0;  // its terms: [first_term, last_term)
  bool active() const { return last_term > first_term; }  // some H̄k ≠ 0
  const Eigen::MatrixXd& phi0() const { return integrals->phi0; }
  const Eigen::MatrixXd& w0E() const { return integrals->w0E; }
  const Eigen::MatrixXd& w1E() const { return integrals->w1E; }
};

// y(t_j − τ) = (1 − α)·y(g) + α·y(g + 1), g a global node index (node g + n is node g one
// period later); `weights` are those of y(g − 1), y(g), y(g + 1) in the discretization's
// interpolation: (0, 1 − α, α) for the linear one, Lagrange's on the three nodes for the
// quadratic one.
struct DelayRef {
  long long g = 0;
  double alpha = 0.0;
  std::array<double, 3> weights{0.0, 1.0, 0.0};
};

long long floor_div(long long a, long long b) {
  long long q = a / b;
  if ((a % b != 0) && ((a < 0) != (b < 0))) --q;
  return q;
}

// The coefficients (of 1, s, s²) of the Lagrange polynomials on the nodes s = a, b, c.
std::array<std::array<double, 3>, 3> lagrange_coefficients(double a, double b, double c) {
  const auto basis = [](double p, double q, double self) {  // (s − p)(s − q)/((self − p)(self − q))
    const double den = (self - p) * (self - q);
    return std::array<double, 3>{p * q / den, -(p + q) / den, 1.0 / den};
  };
  return {basis(b, c, a), basis(a, c, b), basis(a, b, c)};
}

class Discretization {
 public:
  /// `order` 1: the forcing interpolated linearly over each step and H by its mean
  /// [Ding2010]; 2: the displacement difference interpolated on the step's two nodes and
  /// the one before (Lagrange), H by its mean and slope over the step, the delayed values
  /// by Lagrange on three nodes.
  Discretization(const DelayedSystem& s, const FdGrid& grid, int order = 1)
      : terms_(s.delay_terms()), grid_(grid), order_(order) {
    const int n = grid.steps();
    const auto d = s.A0.rows(), r = s.C.rows();
    const auto kinds = static_cast<Eigen::Index>(terms_.size());
    const bool quadratic = order_ == 2;
    // Grids are uniform within each window segment: one matrix exponential per distinct
    // step length (to rounding) serves every step of that length.
    steps_.resize(static_cast<std::size_t>(n));
    // H̄k of every step and term, side by side (r × r each), and for the quadratic
    // interpolation the slopes H'k: the means' own results are the only allocations per step.
    Eigen::MatrixXd means(r, r * n * kinds), slopes(r, quadratic ? r * n * kinds : 0);
    Eigen::Index active_terms = 0;
    for (int j = 0; j < n; ++j) {
      const double t0 = grid.nodes_s[static_cast<std::size_t>(j)];
      const double t1 = grid.nodes_s[static_cast<std::size_t>(j + 1)];
      const double h = t1 - t0;
      auto it = std::find_if(integrals_.begin(), integrals_.end(), [&](const StepIntegrals& e) {
        return std::abs(e.h - h) <= 1e-12 * h;
      });
      if (it == integrals_.end()) {
        integrals_.push_back(step_integrals(s, h, quadratic));
        it = integrals_.end() - 1;
      }
      StepMatrices& st = steps_[static_cast<std::size_t>(j)];
      st.integrals = &*it;
      st.h_col = r * (static_cast<Eigen::Index>(j) * kinds);
      for (Eigen::Index k = 0; k < kinds; ++k) {
        const PeriodicCoefficient& H = terms_[static_cast<std::size_t>(k)].H;
        auto mean = means.middleCols(st.h_col + r * k, r);
        if (!quadratic) {
          mean = H.mean(t0, t1);
        } else {
          // H ≈ H̄ + H'·(s − h/2) on the step: the mean and the slope from the means of its
          // halves (the slope exact for a quadratic H, whose remainder then has neither mean
          // nor first moment). Eq. MS-8 (docs/models/milling-stability.md).
          const double mid = 0.5 * (t0 + t1);
          const Eigen::MatrixXd first = H.mean(t0, mid), second = H.mean(mid, t1);
          mean = 0.5 * (first + second);
          slopes.middleCols(st.h_col + r * k, r) = (2.0 / h) * (second - first);
        }
        if (mean.norm() != 0.0) ++active_terms;
      }
    }
    h_ = std::move(means);
    term_width_ = 3 * r + 2 * d;
    term_data_.setZero(d, term_width_ * active_terms);
    step_terms_.reserve(static_cast<std::size_t>(active_terms));
    std::array<Eigen::MatrixXd, 3> moment_terms;  // Mp·E·H̄ + (Mp+1 − h/2·Mp)·E·H' of a step
    for (int j = 0; j < n; ++j) {
      StepMatrices& st = steps_[static_cast<std::size_t>(j)];
      st.first_term = static_cast<int>(step_terms_.size());
      // Quadratic: the Lagrange polynomials on the nodes s = −h(j−1), 0, h(j) of the step.
      std::array<std::array<double, 3>, 3> lagrange{};
      if (quadratic) {
        const double h = step_length(j), back = step_length(j == 0 ? n - 1 : j - 1);
        lagrange = lagrange_coefficients(-back, 0.0, h);
      }
      for (Eigen::Index k = 0; k < kinds; ++k) {
        const auto mean = h_.middleCols(st.h_col + r * k, r);
        if (mean.norm() == 0.0) continue;
        const Eigen::Index col = term_width_ * static_cast<Eigen::Index>(step_terms_.size());
        // Products of a few rows and columns, coefficient by coefficient.
        // G(j−1) at col (left 0 by the linear interpolation), G(j) and G(j+1) after it.
        auto g0 = term_data_.middleCols(col + r, r), g1 = term_data_.middleCols(col + 2 * r, r);
        if (!quadratic) {
          g0.noalias() = st.w0E().lazyProduct(mean);
          g1.noalias() = st.w1E().lazyProduct(mean);
        } else {
          // G_i = ∫0^h e^(A(h−s))·E·(H̄ + H'·(s − h/2))·ℓi(s) ds = Σp ci,p·(Mp·E·H̄ +
          // (Mp+1 − h/2·Mp)·E·H'), ℓi(s) = Σp ci,p·s^p: eq. MS-9
          // (docs/models/milling-stability.md).
          const auto slope = slopes.middleCols(st.h_col + r * k, r);
          for (std::size_t p = 0; p < 3; ++p) {
            moment_terms[p].noalias() = st.integrals->mE[p].lazyProduct(mean);
            moment_terms[p].noalias() += st.integrals->centred_mE[p].lazyProduct(slope);
          }
          for (std::size_t i = 0; i < 3; ++i) {
            auto gi = term_data_.middleCols(col + r * static_cast<Eigen::Index>(i), r);
            for (std::size_t p = 0; p < 3; ++p) gi += lagrange[i][p] * moment_terms[p];
          }
        }
        term_data_.middleCols(col + 3 * r, d).noalias() = g0.lazyProduct(s.C);
        term_data_.middleCols(col + 3 * r + d, d).noalias() = g1.lazyProduct(s.C);
        step_terms_.push_back(static_cast<int>(k));
      }
      st.last_term = static_cast<int>(step_terms_.size());
    }
    // Node j's delayed value at refs_[k][j + 1], j = −1 … n.
    refs_.resize(terms_.size());
    for (std::size_t k = 0; k < terms_.size(); ++k) {
      for (int j = -1; j <= n; ++j) refs_[k].push_back(delay_ref(j, terms_[k].delay_s));
    }
    // The oldest node any step's delayed values need, counted back from that step's node
    // (every step, cutting or not, so that a period map's state does not depend on the
    // depth), and y(j − 1) for the quadratic interpolation.
    for (int k = 0; k < terms(); ++k)
      for (int j = 0; j < n; ++j)
        for (int e = quadratic ? j - 1 : j; e <= j + 1; ++e) {
          const DelayRef& ref = this->ref(e, k);
          history_ = std::max(history_, j - ref.g + (ref.weights[0] != 0.0 ? 1 : 0));
        }
  }

  int n() const { return grid_.steps(); }
  int order() const { return order_; }
  /// Displacement blocks a period map keeps: y(j − 1) … y(j − history()).
  long long history() const { return history_; }
  const StepMatrices& step(int j) const { return steps_[static_cast<std::size_t>(j)]; }
  /// H̄ of the first delay term over step j (r×r).
  auto H(int j) const { return h_.middleCols(step(j).h_col, h_.rows()); }
  /// The delay term k of step term i (the steps' terms with H̄k ≠ 0, in step order).
  int step_term(int i) const { return step_terms_[static_cast<std::size_t>(i)]; }
  int step_terms() const { return static_cast<int>(step_terms_.size()); }
  /// First entry of step term i's block: the weights G(j−1), G(j), G(j+1) of the step's
  /// nodes' displacement differences ŷ − y (d×r each; G(j−1) = 0 in the linear
  /// interpolation, where G(j) = W0·E·H̄k and G(j+1) = W1·E·H̄k), then G(j)·C and G(j+1)·C
  /// (d×d), side by side (so that a period map can view them as fixed-size matrices).
  const double* term_data(int i) const {
    return term_data_.data() + term_data_.rows() * term_width_ * i;
  }
  int terms() const { return static_cast<int>(terms_.size()); }
  /// Where y(t_j − τk) is, for node j (−1 … n) and delay term k.
  const DelayRef& ref(int j, int k = 0) const {
    return refs_[static_cast<std::size_t>(k)][static_cast<std::size_t>(j + 1)];
  }
  double time(long long g) const {
    const long long p = floor_div(g, n());
    return grid_.nodes_s[static_cast<std::size_t>(g - p * n())] +
           static_cast<double>(p) * grid_.period_s;
  }

 private:
  double step_length(int j) const {
    return grid_.nodes_s[static_cast<std::size_t>(j + 1)] -
           grid_.nodes_s[static_cast<std::size_t>(j)];
  }

  DelayRef delay_ref(int j, double delay) const {
    const double T = grid_.period_s;
    const double s = time(j) - delay;
    const double p = std::floor(s / T);
    double u = s - p * T;
    const auto& t = grid_.nodes_s;
    auto it = std::upper_bound(t.begin(), t.end(), u);
    auto i = static_cast<long long>(it - t.begin()) - 1;
    i = std::clamp<long long>(i, 0, n() - 1);
    const double h = t[static_cast<std::size_t>(i + 1)] - t[static_cast<std::size_t>(i)];
    double alpha = (u - t[static_cast<std::size_t>(i)]) / h;
    long long g = static_cast<long long>(p) * n() + i;
    // Snap to a node when the delayed instant falls on one.
    if (alpha < 1e-12) alpha = 0.0;
    if (alpha > 1.0 - 1e-12) {
      alpha = 0.0;
      ++g;
    }
    DelayRef out{g, alpha, {0.0, 1.0 - alpha, alpha}};
    if (order_ == 2 && alpha > 0.0) {
      // Lagrange on the nodes g − 1, g, g + 1 (all known when the step ends: g + 1 <= j).
      const double tg = time(g);
      const auto c = lagrange_coefficients(time(g - 1) - tg, 0.0, time(g + 1) - tg);
      const double x = alpha * (time(g + 1) - tg);
      for (std::size_t q = 0; q < 3; ++q) out.weights[q] = c[q][0] + x * (c[q][1] + x * c[q][2]);
    }
    return out;
  }

  std::vector<DelayTerm> terms_;
  const FdGrid& grid_;
  int order_ = 1;
  std::deque<StepIntegrals> integrals_;  // one per distinct step length (a deque: steps point
                                         // into it while it grows)
  std::vector<StepMatrices> steps_;
  Eigen::MatrixXd h_;                    // H̄k of every step and term, r × r each
  std::vector<int> step_terms_;          // the delay term of each step term
  Eigen::Index term_width_ = 0;          // 3r + 2d columns per step term
  Eigen::MatrixXd term_data_;            // the step terms' depth-independent products
  std::vector<std::vector<DelayRef>> refs_;
  long long history_ = 1;
};

// The largest |eigenvalue| of a state matrix, from its balanced form (Eigen's real Schur
// iteration can fail on the unbalanced one, whose entries span 1 to ω²), by the complex Schur
// form where the real one fails.
double largest_pole_modulus(const Eigen::MatrixXd& a) {
  const Eigen::VectorXd scale = balancing_scale(a);
  const Eigen::MatrixXd balanced = scale.cwiseInverse().asDiagonal() * a * scale.asDiagonal();
  Eigen::VectorXcd poles;
  const Eigen::EigenSolver<Eigen::MatrixXd> real(balanced, false);
  if (real.info() == Eigen::Success) {
    poles = real.eigenvalues();
  } else {
    const Eigen::ComplexEigenSolver<Eigen::MatrixXcd> complex(balanced.cast<cplx>(), false);
    if (complex.info() != Eigen::Success)
      throw std::runtime_error("full discretization: the eigenvalues of a state matrix failed");
    poles = complex.eigenvalues();
  }
  return poles.cwiseAbs().maxCoeff();
}

double shortest_structural_period(const DelayedSystem& s) {
  return kTwoPi / largest_pole_modulus(s.A0);
}

// The largest |eigenvalue| of A0 − w·E·ΣHk·C over [t0, t1] (ΣHk averaged over each quarter
// of it): the fastest motion of the structure stiffened by the cut at depth w; 0 when no
// tooth cuts there.
double cutting_frequency(const DelayedSystem& s, const std::vector<DelayTerm>& terms, double t0,
                         double t1, double w) {
  constexpr int kParts = 4;
  double omega = 0.0;
  bool cutting = false;
  for (int q = 0; q < kParts; ++q) {
    const double a = t0 + (t1 - t0) * q / kParts, b = t0 + (t1 - t0) * (q + 1) / kParts;
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(s.C.rows(), s.C.rows());
    for (const DelayTerm& t : terms) h += t.H.mean(a, b);
    if (h.norm() == 0.0) continue;
    cutting = true;
    omega = std::max(omega, largest_pole_modulus(s.A0 - w * s.E * h * s.C));
  }
  return cutting ? omega : 0.0;
}

}  // namespace

std::vector<std::string> FdOptions::validate() const {
  Validator v;
  v.require(max_step_fraction > 0.0 && max_step_fraction <= 0.5, "max_step_fraction",
            max_step_fraction, "", "must be greater than 0 and at most 0.5");
  v.require(steps_per_period >= 0 && steps_per_period <= 100000, "steps_per_period",
            steps_per_period, "", "must be 0 (automatic) to 100000");
  v.require_positive("depth_max_m", depth_max_m, "m");
  v.require(samples_per_turn >= 4.0 && samples_per_turn <= 1000.0, "samples_per_turn",
            samples_per_turn, "", "must be 4 to 1000");
  v.require(order == 1 || order == 2, "order", order, "", "must be 1 (linear) or 2 (quadratic)");
  v.require(window_steps >= 0 && window_steps <= 10000, "window_steps", window_steps, "",
            "must be 0 (no minimum) to 10000");
  v.require(cutting_depth_m >= 0.0 && std::isfinite(cutting_depth_m), "cutting_depth_m",
            cutting_depth_m, "m", "must be 0 (the structure only) or positive");
  v.require(refinements >= 0 && refinements <= 6, "refinements", refinements, "",
            "must be 0 (one grid) to 6");
  return v.problems();
}

FdGrid fd_grid(const DelayedSystem& s, const FdOptions& o) {
  require_valid(s, o.validate());
  FdGrid grid;
  grid.order = o.order;
  double h_max = o.max_step_fraction * shortest_structural_period(s);
  // The delayed value of a step's end must be known.
  for (const DelayTerm& t : s.delay_terms()) h_max = std::min(h_max, t.delay_s);
  if (s.H.constant && !s.more_delays.empty()) {
    throw InvalidInput({"more_delays: several delays need a periodic H (the grid's period)"},
                       "full discretization");
  }
  if (s.H.constant) {
    if (o.steps_per_period > 0) {
      grid.period_s = s.delay_s;
      for (int j = 0; j <= o.steps_per_period; ++j)
        grid.nodes_s.push_back(s.delay_s * j / o.steps_per_period);
    } else {
      // One step per period, and a whole number of steps per delay: no interpolation.
      const double h = s.delay_s / std::ceil(s.delay_s / h_max - 1e-9);
      grid.period_s = h;
      grid.nodes_s = {0.0, h};
    }
    return grid;
  }
  const double T = s.H.period_s;
  grid.period_s = T;
  const std::vector<DelayTerm> terms = s.delay_terms();
  std::vector<double> cuts{0.0};
  for (const DelayTerm& t : terms)
    for (double b : t.H.breakpoints_s)
      if (b > 0.0 && b < T) cuts.push_back(b);
  cuts.push_back(T);
  std::sort(cuts.begin(), cuts.end());
  grid.nodes_s.push_back(0.0);
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
    const double len = cuts[k + 1] - cuts[k];
    if (len <= 1e-9 * T) continue;  // coincident breakpoints
    int steps = o.steps_per_period > 0
                    ? std::max(1, static_cast<int>(std::lround(o.steps_per_period * len / T)))
                    : std::max(1, static_cast<int>(std::ceil(len / h_max - 1e-9)));
    if (o.steps_per_period == 0 && (o.cutting_depth_m > 0.0 || o.window_steps > 0)) {
      const double omega = cutting_frequency(s, terms, cuts[k], cuts[k + 1], o.cutting_depth_m);
      if (omega > 0.0) {
        steps = std::max(steps, o.window_steps);
        steps = std::max(
            steps,
            static_cast<int>(std::ceil(len * omega / (kTwoPi * o.max_step_fraction) - 1e-9)));
      }
    }
    for (int j = 1; j <= steps; ++j) grid.nodes_s.push_back(cuts[k] + len * j / steps);
  }
  grid.nodes_s.back() = T;
  return grid;
}

namespace {

// The transition map over one period at a fixed depth, applicable to any set of columns:
// the identity gives the dense Φ, a single vector gives the matrix-free product for Arnoldi.
// The state is z = (x(j), y(j−1), ..., y(j−L)).
class PeriodMap {
 public:
  virtual ~PeriodMap() = default;
  virtual Eigen::Index dim() const = 0;
  /// z ← Φ·z, column by column; `next` is scratch of the same size.
  virtual void apply(Eigen::MatrixXd& z, Eigen::MatrixXd& next) const = 0;
};

// The map with the state and output sizes D and R fixed at compile time (Eigen::Dynamic for
// any): the step products are 4×4 for a milling cutter with one mode per direction, and
// fixed-size kernels make them several times faster than dynamic ones.
template <int D, int R>
class PeriodMapT final : public PeriodMap {
 public:
  PeriodMapT(const Discretization& disc, const DelayedSystem& s, double depth)
      : disc_(disc), c_(s.C), d_(s.A0.rows()), r_(s.C.rows()), L_(disc.history()) {
    const int n = disc_.n();
    const bool quadratic = disc_.order() == 2;
    steps_.resize(static_cast<std::size_t>(n));
    gains_.reserve(static_cast<std::size_t>(disc_.step_terms() * (quadratic ? 4 : 2)));
    // weight·k·y(j − back) into the gains of the step that starts at gains_[first]; one gain
    // per node, those of one step on the same node merged.
    const auto add_gain = [&](int first, long long back, double weight, const MatDR& k) {
      if (weight == 0.0) return;
      for (auto g = static_cast<std::size_t>(first); g < gains_.size(); ++g) {
        if (gains_[g].back == back) {
          gains_[g].k += weight * k;
          return;
        }
      }
      Gain& g = gains_.emplace_back();
      g.k = weight == 1.0 ? k : MatDR(weight * k);
      g.back = back;
    };
    // k·ŷ (a delayed value, `ref`) seen from step j: one gain per node of its interpolation.
    const auto add_delayed = [&](int j, int first, const MatDR& k, const DelayRef& ref) {
      for (std::size_t i = 0; i < 3; ++i)
        add_gain(first, j - (ref.g + static_cast<long long>(i) - 1), ref.weights[i], k);
    };
    for (int j = 0; j < n; ++j) {
      const StepMatrices& st = disc_.step(j);
      Step& out = steps_[static_cast<std::size_t>(j)];
      out.first = static_cast<int>(gains_.size());
      out.last = out.first;
      if (!st.active() || depth <= 0.0) {
        out.mx = st.phi0();
        continue;
      }
      // x(j+1) = Φ0·x(j) + w·Σk Σi Gki·(ŷk(i) − y(i)), i = j − 1 (quadratic only), j, j + 1:
      // (I + w·Σk Gk(j+1)·C)·x(j+1) = (Φ0 − w·Σk Gk(j)·C)·x(j) − w·Σk Gk(j−1)·y(j−1)
      //   + w·Σk Σi Gki·ŷk(i)   [Ding2010, eq. 13, with one delayed term per delay]; eq. MS-11
      //   of docs/models/milling-stability.md, summed over the delay terms of eq. MS-13.
      // I + w·ΣG·C is I plus a term of the order of the step: well conditioned. G and G·C
      // are kept from the discretization: only the scaling by the depth is new.
      MatDD lhs = MatDD::Identity(d_, d_);
      MatDD rhs = st.phi0();
      MatDR prev = MatDR::Zero(d_, r_);
      for (int i = st.first_term; i < st.last_term; ++i) {
        const TermBlocks t(disc_.term_data(i), d_, r_);
        lhs += depth * t.g1C;
        rhs -= depth * t.g0C;
        if (quadratic) prev += t.g_prev;
      }
      const MatDD inv = lhs.inverse();
      out.mx.noalias() = inv * rhs;
      const MatDD scaled = depth * inv;
      if (quadratic) add_gain(out.first, 1, 1.0, -scaled * prev);  // on y(j − 1)
      for (int i = st.first_term; i < st.last_term; ++i) {
        // G(j−1), G(j), G(j+1) lie side by side: one product for the three.
        const MatD3R g = scaled * Eigen::Map<const MatD3R>(disc_.term_data(i), d_, 3 * r_);
        const int term = disc_.step_term(i);
        if (quadratic) add_delayed(j, out.first, g.leftCols(r_), disc_.ref(j - 1, term));
        add_delayed(j, out.first, g.middleCols(r_, r_), disc_.ref(j, term));
        add_delayed(j, out.first, g.rightCols(r_), disc_.ref(j + 1, term));
      }
      out.last = static_cast<int>(gains_.size());
    }
  }

  Eigen::Index dim() const override { return d_ + r_ * L_; }

  // The history is kept as a ring of L blocks during the period (no shifting), and put back
  // in order at the end.
  void apply(Eigen::MatrixXd& z, Eigen::MatrixXd& next) const override {
    if (z.cols() == 1)
      run_vector(z, next);
    else
      run<Eigen::Dynamic>(z, next);
  }

 private:
  using MatDD = Eigen::Matrix<double, D, D>;
  using MatDR = Eigen::Matrix<double, D, R>;
  using MatRD = Eigen::Matrix<double, R, D>;
  using MatD3R = Eigen::Matrix<double, D, R == Eigen::Dynamic ? Eigen::Dynamic : 3 * R>;
  // A gain on the displacements of one node: k·y(j − back) (y(j) the step's own node).
  struct Gain {
    MatDR k;
    long long back = 0;
  };
  struct Step {
    Step() {}  // user-provided: a vector of them is not zero-filled first
    MatDD mx;
    int first = 0, last = 0;  // its gains: gains_[first, last)
  };
  // A step term's products (Discretization::term_data) seen as matrices of this map's sizes.
  struct TermBlocks {
    TermBlocks(const double* p, Eigen::Index d, Eigen::Index r)
        : g_prev(p, d, r), g0C(p + 3 * d * r, d, d), g1C(p + 3 * d * r + d * d, d, d) {}
    Eigen::Map<const MatDR> g_prev;  // G(j), G(j + 1) follow it (read as one block, MatD3R)
    Eigen::Map<const MatDD> g0C, g1C;
  };

  // One column (the Arnoldi product): the same map as run<Cols>, on maps of fixed
  // size (blocks of the dynamic z keep a dynamic column count, which slows every small
  // kernel).
  void run_vector(Eigen::MatrixXd& z, Eigen::MatrixXd& next) const {
    using Xv = Eigen::Matrix<double, D, 1>;
    using Yv = Eigen::Matrix<double, R, 1>;
    double* const zp = z.data();
    // x in registers for the period (as a view of z, every store of y(j) into the history
    // could alias it, and each step would store and reload it)
    Xv x = Eigen::Map<const Xv>(zp, d_);
    Xv xo(d_);
    Yv yj(r_);
    long long head = 0;                       // ring block that holds y(j − 1)
    const auto block = [&](long long back) {  // first row of the history block y(j − back)
      long long b = head + back - 1;          // 0 <= b < 2L: no division
      if (b >= L_) b -= L_;
      return d_ + r_ * b;
    };
    const auto y_at = [&](long long back) -> Yv {  // y(j − back)
      if (back == 0) return yj;
      return Eigen::Map<const Yv>(zp + block(back), r_);
    };
    const int n = disc_.n();
    Xv delayed(d_);
    for (int j = 0; j < n; ++j) {
      const Step& st = steps_[static_cast<std::size_t>(j)];
      xo = x;
      yj.noalias() = c_ * xo;
      // The gains on past displacements first, into their own sum: they do not depend on
      // x(j), so the processor computes them while the previous step's x is still being
      // formed, and the chain from step to step is only Mx·x (several times shorter).
      delayed.setZero();
      for (int g = st.first; g < st.last; ++g) {
        const Gain& gain = gains_[static_cast<std::size_t>(g)];
        delayed.noalias() += gain.k * y_at(gain.back);
      }
      if constexpr (D != Eigen::Dynamic && D % 2 == 0) {  // two independent halves
        const Xv first = st.mx.template leftCols<D / 2>() * xo.template head<D / 2>();
        x.noalias() = st.mx.template rightCols<D / 2>() * xo.template tail<D / 2>();
        x += first + delayed;
      } else {
        x.noalias() = st.mx * xo;
        x += delayed;
      }
      head = head == 0 ? L_ - 1 : head - 1;  // push y(j) = C·x(j)
      Eigen::Map<Yv>(zp + d_ + r_ * head, r_) = yj;
    }
    next.resize(z.rows(), 1);
    next.topRows(d_) = x;
    for (long long b = 1; b <= L_; ++b)
      next.middleRows(d_ + r_ * (b - 1), r_) = z.middleRows(block(b), r_);
    z.swap(next);
  }

  template <int Cols>
  void run(Eigen::MatrixXd& z, Eigen::MatrixXd& next) const {
    using Xs = Eigen::Matrix<double, D, Cols>;
    using Ys = Eigen::Matrix<double, R, Cols>;
    const Eigen::Index cols = z.cols();
    Xs xo(d_, cols);
    Ys yj(r_, cols);
    long long head = 0;                       // ring block that holds y(j − 1)
    const auto block = [&](long long back) {  // first row of the history block y(j − back)
      long long b = head + back - 1;          // 0 <= b < 2L: no division
      if (b >= L_) b -= L_;
      return d_ + r_ * b;
    };
    const auto y_at = [&](long long back) -> Ys {  // y(j − back)
      if (back == 0) return yj;
      return z.template middleRows<R>(block(back), r_);
    };
    for (int j = 0; j < disc_.n(); ++j) {
      const Step& st = steps_[static_cast<std::size_t>(j)];
      xo = z.template topRows<D>(d_);
      yj.noalias() = c_ * xo;
      auto x = z.template topRows<D>(d_);
      x.noalias() = st.mx * xo;
      for (int g = st.first; g < st.last; ++g) {
        const Gain& gain = gains_[static_cast<std::size_t>(g)];
        x.noalias() += gain.k * y_at(gain.back);
      }
      head = head == 0 ? L_ - 1 : head - 1;  // push y(j) = C·x(j)
      z.template middleRows<R>(d_ + r_ * head, r_) = yj;
    }
    next.resize(z.rows(), cols);
    next.topRows(d_) = z.topRows(d_);
    for (long long b = 1; b <= L_; ++b)
      next.middleRows(d_ + r_ * (b - 1), r_) = z.middleRows(block(b), r_);
    z.swap(next);
  }

  const Discretization& disc_;
  MatRD c_;
  Eigen::Index d_, r_;
  long long L_;  // history blocks (Discretization::history)
  std::vector<Step> steps_;
  std::vector<Gain, Eigen::aligned_allocator<Gain>> gains_;
};

// Map<D, R>(disc, s, value) for this system's state and output sizes, with fixed-size kernels
// for the common ones (turning with one or two modes, milling with one or two modes per
// direction).
template <template <int, int> class Map>
std::unique_ptr<PeriodMap> make_sized(const Discretization& disc, const DelayedSystem& s,
                                      double value) {
  const auto d = s.A0.rows(), r = s.C.rows();
  if (r == 1 && d == 2) return std::make_unique<Map<2, 1>>(disc, s, value);
  if (r == 1 && d == 4) return std::make_unique<Map<4, 1>>(disc, s, value);
  if (r == 2 && d == 2) return std::make_unique<Map<2, 2>>(disc, s, value);
  if (r == 2 && d == 4) return std::make_unique<Map<4, 2>>(disc, s, value);
  if (r == 2 && d == 8) return std::make_unique<Map<8, 2>>(disc, s, value);
  return std::make_unique<Map<Eigen::Dynamic, Eigen::Dynamic>>(disc, s, value);
}

std::unique_ptr<PeriodMap> make_period_map(const Discretization& disc, const DelayedSystem& s,
                                           double depth) {
  return make_sized<PeriodMapT>(disc, s, depth);
}

// A product with the period map left the range of double: a unit vector grew beyond 1e308 in
// one period. The radius is reported as infinite, so the searches count the depth as
// unstable — the conservative side, and a growth no stable cut shows — and no NaN reaches
// an eigenvalue solver.
struct MapOverflow {};
constexpr double kOverflowRadius = std::numeric_limits<double>::infinity();

// The largest |eigenvalue| of a dense map; infinite if the map or its eigenvalues overflow.
double dense_radius(const Eigen::MatrixXd& phi) {
  if (!phi.allFinite()) return kOverflowRadius;
  const Eigen::VectorXd moduli = phi.eigenvalues().cwiseAbs();
  return moduli.allFinite() ? moduli.maxCoeff() : kOverflowRadius;
}

// Spectra's operator interface over the matrix-free map.
class PeriodMapOp {
 public:
  using Scalar = double;
  explicit PeriodMapOp(const PeriodMap& map) : map_(map) {}
  Eigen::Index rows() const { return map_.dim(); }
  Eigen::Index cols() const { return map_.dim(); }
  void perform_op(const double* in, double* out) const {
    z_ = Eigen::Map<const Eigen::VectorXd>(in, map_.dim());
    map_.apply(z_, next_);
    if (!z_.allFinite()) throw MapOverflow{};
    Eigen::Map<Eigen::VectorXd>(out, map_.dim()) = z_;
  }

 private:
  const PeriodMap& map_;
  mutable Eigen::MatrixXd z_, next_;
};

// The depths at which a real multiplier μ = ±1 of the discretized period map exists, as one
// linear eigenvalue problem (docs/models/milling-stability.md, "Unstable islands", eq. MS-14).
// The steps
// x(j+1) = Φ0j·x(j) + w·vj, vj = Σk Σi Gki·ek(i) (i = j − 1 … j + 1, the step's nodes), are
// driven by the displacement differences ek(i) = ŷk(i) − y(i) at the nodes the cutting steps
// use. A solution with x(j + n) = μ·x(j) is fixed by them: x(0) = (μI − Ψ)⁻¹·(the response at
// n from rest), Ψ = Πj Φ0j; then y(i) = C·x(i), and e must equal the differences of that y,
// so e = w·K·e: the eigenvalues λ of K give the depths 1/λ at which μ is a multiplier — every
// one of them at once, where a search on the spectral radius sees only the dominant one.
// Node g of another period is node g mod n times μ^floor(g/n).
// It is a PeriodMap (z ← K·z) so that the radius solvers take it as they are.
class RealMultiplierOperator : public PeriodMap {
 public:
  void apply(Eigen::MatrixXd& z, Eigen::MatrixXd& next) const override {
    next.resize(z.rows(), z.cols());
    for (Eigen::Index c = 0; c < z.cols(); ++c) product(z.col(c).data(), next.col(c).data());
    z.swap(next);
  }
  /// out ← K·in.
  virtual void product(const double* in, double* out) const = 0;
  /// The nodal displacements y(0) … y(n − 1) (r × n) of the solution with differences `e`.
  virtual Eigen::MatrixXd displacements(const double* e) const = 0;
};

// The operator with the state and output sizes fixed at compile time (as PeriodMapT).
template <int D, int R>
class RealMultiplierOperatorT final : public RealMultiplierOperator {
 public:
  RealMultiplierOperatorT(const Discretization& disc, const DelayedSystem& s, double mu)
      : c_(s.C), d_(s.A0.rows()), r_(s.C.rows()), n_(disc.n()) {
    const int kinds = disc.terms();
    const auto wrap = [&](long long g) { return static_cast<int>(g - floor_div(g, n_) * n_); };
    // μ^floor(g/n) for μ = ±1.
    const auto sign = [&](long long g) {
      return mu < 0.0 && floor_div(g, n_) % 2 != 0 ? -1.0 : 1.0;
    };
    std::vector<int> slot(static_cast<std::size_t>(kinds) * static_cast<std::size_t>(n_), -1);
    const auto slot_of = [&](int term, long long node) -> int& {
      return slot[static_cast<std::size_t>(term) * static_cast<std::size_t>(n_) +
                  static_cast<std::size_t>(wrap(node))];
    };
    struct Unknown {
      int term, node;
    };
    std::vector<Unknown> unknowns;
    MatDD psi = MatDD::Identity(d_, d_);
    steps_.resize(static_cast<std::size_t>(n_));
    for (int j = 0; j < n_; ++j) {
      const StepMatrices& st = disc.step(j);
      Step& out = steps_[static_cast<std::size_t>(j)];
      out.phi0 = st.phi0();
      psi = out.phi0 * psi;
      out.first = static_cast<int>(inputs_.size());
      for (int i = st.first_term; i < st.last_term; ++i) {
        const int term = disc.step_term(i);
        for (int q = disc.order() == 2 ? 0 : 1; q < 3; ++q) {
          const long long node = j - 1 + q;
          int& k = slot_of(term, node);
          if (k < 0) {
            k = static_cast<int>(unknowns.size()) * static_cast<int>(r_);
            unknowns.push_back({term, wrap(node)});
          }
          Input& in = inputs_.emplace_back();
          in.g = sign(node) * Eigen::Map<const Eigen::MatrixXd>(disc.term_data(i), d_, 3 * r_)
                                  .middleCols(r_ * q, r_);
          in.slot = k;
        }
      }
      out.last = static_cast<int>(inputs_.size());
    }
    rows_ = r_ * static_cast<Eigen::Index>(unknowns.size());
    // ek(i) = Σq weight_q·μ^p·y(g + q − 1 mod n) − y(i), one list of terms per unknown.
    for (const Unknown& u : unknowns) {
      const DelayRef& ref = disc.ref(u.node, u.term);
      outputs_.push_back({u.node, -1.0});
      for (int q = 0; q < 3; ++q) {
        const double w = ref.weights[static_cast<std::size_t>(q)];
        if (w != 0.0) outputs_.push_back({wrap(ref.g + q - 1), w * sign(ref.g + q - 1)});
      }
      output_end_.push_back(static_cast<int>(outputs_.size()));
    }
    MatDD shifted = -psi;
    shifted.diagonal().array() += mu;
    // d × d, well conditioned (Ψ's eigenvalues lie inside the unit circle): its inverse once,
    // so that each product's periodic start is one small fixed-size product.
    start_ = Eigen::MatrixXd(shifted).partialPivLu().inverse();
    v_.resize(d_, n_);
    y_.resize(r_, n_);
  }

  Eigen::Index dim() const override { return rows_; }

  void product(const double* in, double* out) const override {
    respond(in);
    std::size_t t = 0;
    Eigen::Index row = 0;
    for (int end : output_end_) {
      Yv e = Yv::Zero(r_);
      for (; t < static_cast<std::size_t>(end); ++t)
        e += outputs_[t].coef * y_.col(outputs_[t].node);
      Eigen::Map<Yv>(out + row, r_) = e;
      row += r_;
    }
  }

  Eigen::MatrixXd displacements(const double* e) const override {
    respond(e);
    return y_;
  }

 private:
  using MatDD = Eigen::Matrix<double, D, D>;
  using MatDR = Eigen::Matrix<double, D, R>;
  using Xv = Eigen::Matrix<double, D, 1>;
  using Yv = Eigen::Matrix<double, R, 1>;
  struct Step {
    MatDD phi0;
    int first = 0, last = 0;  // its inputs: inputs_[first, last)
  };
  struct Input {  // g·e at slot (μ's power included in g)
    MatDR g;
    int slot = 0;
  };
  struct Output {  // coef·y(node)
    int node;
    double coef;
  };

  // y_ for the differences `e`: the inputs vj, the response from rest, the periodic start.
  void respond(const double* e) const {
    Xv x = Xv::Zero(d_);
    for (int j = 0; j < n_; ++j) {
      const Step& st = steps_[static_cast<std::size_t>(j)];
      Xv v = Xv::Zero(d_);
      for (int i = st.first; i < st.last; ++i) {
        const Input& in = inputs_[static_cast<std::size_t>(i)];
        v.noalias() += in.g * Eigen::Map<const Yv>(e + in.slot, r_);
      }
      v_.col(j) = v;
      v.noalias() += st.phi0 * x;
      x = v;
    }
    x = start_ * Xv(x);
    for (int j = 0; j < n_; ++j) {
      y_.col(j).noalias() = c_ * x;
      Xv next = v_.col(j);
      next.noalias() += steps_[static_cast<std::size_t>(j)].phi0 * x;
      x = next;
    }
  }

  Eigen::Matrix<double, R, D> c_;
  Eigen::Index d_, r_;
  int n_;
  Eigen::Index rows_ = 0;
  std::vector<Step, Eigen::aligned_allocator<Step>> steps_;
  std::vector<Input, Eigen::aligned_allocator<Input>> inputs_;
  std::vector<Output> outputs_;
  std::vector<int> output_end_;  // the outputs of each unknown end here
  MatDD start_;                  // (μI − Ψ)⁻¹
  mutable Eigen::Matrix<double, D, Eigen::Dynamic> v_;
  mutable Eigen::Matrix<double, R, Eigen::Dynamic> y_;
};

std::unique_ptr<RealMultiplierOperator> make_real_multiplier_operator(const Discretization& disc,
                                                                      const DelayedSystem& s,
                                                                      double mu) {
  return std::unique_ptr<RealMultiplierOperator>(static_cast<RealMultiplierOperator*>(
      make_sized<RealMultiplierOperatorT>(disc, s, mu).release()));
}

}  // namespace

struct FdDiscretization::Impl {
  Impl(const DelayedSystem& s, FdGrid g)
      : system(s), grid(std::move(g)), disc(system, grid, grid.order) {}
  DelayedSystem system;
  FdGrid grid;
  Discretization disc;  // refers to the two members above
};

FdDiscretization::FdDiscretization(const DelayedSystem& system, const FdOptions& options)
    : impl_(std::make_unique<Impl>(system, fd_grid(system, options))) {}
FdDiscretization::FdDiscretization(const DelayedSystem& system, const FdGrid& grid)
    : impl_(std::make_unique<Impl>(system, grid)) {}
FdDiscretization::~FdDiscretization() = default;
FdDiscretization::FdDiscretization(FdDiscretization&&) noexcept = default;
FdDiscretization& FdDiscretization::operator=(FdDiscretization&&) noexcept = default;

const FdGrid& FdDiscretization::grid() const { return impl_->grid; }

Eigen::MatrixXd FdDiscretization::transition_matrix(double depth_m) const {
  const auto map_ptr = make_period_map(impl_->disc, impl_->system, depth_m);
  const PeriodMap& map = *map_ptr;
  Eigen::MatrixXd phi = Eigen::MatrixXd::Identity(map.dim(), map.dim()), scratch;
  map.apply(phi, scratch);
  return phi;
}

double FdDiscretization::spectral_radius(double depth_m) const {
  return dense_radius(transition_matrix(depth_m));
}

SpectralRadius FdDiscretization::spectral_radius_arnoldi(double depth_m) const {
  const auto map_ptr = make_period_map(impl_->disc, impl_->system, depth_m);
  const PeriodMap& map = *map_ptr;
  constexpr Eigen::Index kNev = 3, kNcv = 10;
  SpectralRadius out;
  if (map.dim() > 3 * kNcv) {
    PeriodMapOp op(map);
    Spectra::GenEigsSolver<PeriodMapOp> eigs(op, kNev, kNcv);
    eigs.init();
    try {
      const Eigen::Index converged = eigs.compute(Spectra::SortRule::LargestMagn, 200, 1e-10);
      out.operations = eigs.num_operations();
      if (converged == kNev && eigs.info() == Spectra::CompInfo::Successful) {
        out.value = eigs.eigenvalues().cwiseAbs().maxCoeff();
        out.arnoldi = true;
        return out;
      }
    } catch (const MapOverflow&) {
      out.value = kOverflowRadius;
      return out;
    } catch (const std::exception&) {  // Spectra's QR failed (values near overflow): dense
    }
  }
  // Small maps, or Arnoldi did not converge (multipliers crowding the circle): dense.
  Eigen::MatrixXd phi = Eigen::MatrixXd::Identity(map.dim(), map.dim()), scratch;
  map.apply(phi, scratch);
  out.value = dense_radius(phi);
  return out;
}

Eigen::MatrixXd fd_transition_matrix(const DelayedSystem& s, const FdGrid& grid, double depth) {
  return FdDiscretization(s, grid).transition_matrix(depth);
}

double fd_spectral_radius(const DelayedSystem& s, const FdGrid& grid, double depth) {
  return FdDiscretization(s, grid).spectral_radius(depth);
}

SpectralRadius fd_spectral_radius_arnoldi(const DelayedSystem& s, const FdGrid& grid,
                                          double depth) {
  return FdDiscretization(s, grid).spectral_radius_arnoldi(depth);
}

namespace {

// The multiplier of largest modulus and its eigenvector (dense or Arnoldi).
// An infinite multiplier (no eigenvector) when the map overflows.
std::pair<cplx, Eigen::VectorXcd> dominant_eigenpair(const PeriodMap& map, RadiusSolver solver) {
  const std::pair<cplx, Eigen::VectorXcd> overflow{cplx(kOverflowRadius, 0.0), {}};
  if (solver == RadiusSolver::kArnoldi && map.dim() > 60) {
    PeriodMapOp op(map);
    Spectra::GenEigsSolver<PeriodMapOp> eigs(op, 3, 10);
    eigs.init();
    try {
      if (eigs.compute(Spectra::SortRule::LargestMagn, 200, 1e-10) == 3)
        return {eigs.eigenvalues()(0), eigs.eigenvectors().col(0)};
    } catch (const MapOverflow&) {
      return overflow;
    } catch (const std::exception&) {  // Spectra's QR failed (values near overflow): dense
    }
  }
  Eigen::MatrixXd phi = Eigen::MatrixXd::Identity(map.dim(), map.dim()), scratch;
  map.apply(phi, scratch);
  if (!phi.allFinite()) return overflow;
  Eigen::EigenSolver<Eigen::MatrixXd> eig(phi, true);
  if (!eig.eigenvalues().allFinite() || !eig.eigenvectors().allFinite()) return overflow;
  Eigen::Index k = 0;
  eig.eigenvalues().cwiseAbs().maxCoeff(&k);
  return {eig.eigenvalues()(k), eig.eigenvectors().col(k)};
}

// The dominant multiplier by an unrestarted Arnoldi iteration: Krylov vectors from a fixed
// pseudo-random start (as Spectra's default), classical Gram–Schmidt applied twice, and from
// the kFirstTest-th product on the Ritz values of the Hessenberg matrix, tested after the
// products where the residuals' geometric fall says they may pass; accepted once the kNev of
// largest modulus pass Spectra's residual test (|h(m+1,m)·y(m)| < tol·max(|θ|, eps^(2/3)),
// y the unit eigenvector of H), so only where they do. nullopt when kMaxVectors are not
// enough or the map is small (the caller then uses Spectra or the dense matrix).
// `leading`: where to put the kNev accepted Ritz values, largest modulus first, each with its
// vector where `wants_vector` says so (empty otherwise).
using RitzPairs = std::vector<std::pair<cplx, Eigen::VectorXcd>>;
std::optional<DominantMultiplier> krylov_dominant(
    const PeriodMap& map, const ArnoldiOptions& options, RitzPairs* leading = nullptr,
    const std::function<bool(cplx)>& wants_vector = {}) {
  constexpr int kNev = 3, kMaxVectors = 30, kFirstTest = 8;
  constexpr double kScreenTol = 1e-7;
  const double full_tol = options.tolerance;
  const Eigen::Index n = map.dim();
  if (n <= 2 * kMaxVectors) return std::nullopt;
  const double eps23 = std::pow(std::numeric_limits<double>::epsilon(), 2.0 / 3.0);
  // The iteration's storage is kept per thread (a lobes search makes thousands of these
  // calls on maps of a few sizes), with the normalized start vector of the last size.
  thread_local Eigen::MatrixXd V, H, z, next;
  thread_local Eigen::VectorXd start;
  if (start.size() != n) {
    Spectra::SimpleRandom<double> rng(0);
    start = rng.random_vec(n);
    start.normalize();
  }
  V.resize(n, kMaxVectors + 1);
  H.setZero(kMaxVectors + 1, kMaxVectors);
  V.col(0) = start;
  z.resize(n, 1);
  DominantMultiplier out;
  out.krylov = true;
  const auto overflowed = [&] {  // the map overflows (MapOverflow)
    out.radius = kOverflowRadius;
    out.mu = cplx(kOverflowRadius, 0.0);
    return out;
  };
  int next_test = options.first_test > 0 ? std::clamp(options.first_test, kNev, kMaxVectors)
                                         : kFirstTest;
  int last_test = 0;
  double last_worst = 0.0;
  for (int k = 0; k < kMaxVectors; ++k) {
    z.col(0) = V.col(k);
    map.apply(z, next);
    ++out.operations;
    if (!z.allFinite()) return overflowed();
    // Modified Gram–Schmidt, one pass: the classical one needed its second pass at nine
    // products in ten (these maps contract, and z is mostly along the basis), twice the work
    // of this; the orthogonality it loses, about ε over the residual, leaves the Ritz values
    // and residuals of the tests to 1e-10 as they were (docs/models/milling-stability.md).
    for (int i = 0; i <= k; ++i) {
      const double c = V.col(i).dot(z.col(0));
      z.col(0) -= c * V.col(i);
      H(i, k) = c;
    }
    const double beta = z.col(0).norm();
    if (!std::isfinite(beta)) return overflowed();  // |z| beyond the range of double
    H(k + 1, k) = beta;
    const int m = k + 1;
    const bool invariant = beta <= std::numeric_limits<double>::epsilon() * H.col(k).norm();
    if (!invariant) V.col(k + 1) = z.col(0) / beta;
    if (m < next_test && !invariant && m < kMaxVectors) continue;
    if (m < kNev) return std::nullopt;
    Eigen::VectorXcd values;
    Eigen::MatrixXcd vectors;  // unit columns
    try {
      Spectra::UpperHessenbergEigen<double> eig(H.topLeftCorner(m, m));
      values = eig.eigenvalues();
      vectors = eig.eigenvectors();
    } catch (const std::exception&) {  // its QR iteration did not converge: Spectra, dense
      return std::nullopt;
    }
    std::vector<int> order(static_cast<std::size_t>(m));
    for (int i = 0; i < m; ++i) order[static_cast<std::size_t>(i)] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return std::abs(values(a)) > std::abs(values(b)); });
    // The worst of the kNev residuals against its bound (< 1: all pass), at the screening
    // tolerance while the largest Ritz value is below the screening bound.
    const int top = order.front();
    const bool screening = std::abs(values(top)) < options.screen_below;
    const double tol = screening ? std::max(kScreenTol, full_tol) : full_tol;
    double worst = 0.0;
    for (int q = 0; q < kNev; ++q) {
      const int i = order[static_cast<std::size_t>(q)];
      const double residual = invariant ? 0.0 : std::abs(vectors(m - 1, i)) * beta;
      worst = std::max(worst, residual / (tol * std::max(eps23, std::abs(values(i)))));
    }
    if (!(worst < 1.0)) {
      // Not yet. The residuals fall geometrically with each product (by 15–40× in milling
      // maps): from the last two tests, the products still needed; the next test comes one
      // product before that estimate (each test is a Schur decomposition of the Hessenberg
      // matrix, about as costly as a product).
      next_test = m + 1;
      if (last_worst > 0.0 && last_test == m - 1 && worst < 0.5 * last_worst) {
        const double needed = std::log(worst) / std::log(last_worst / worst);
        if (needed > 2.0) next_test = m + static_cast<int>(std::ceil(needed)) - 1;
      }
      last_worst = worst;
      last_test = m;
      continue;
    }
    // The products after which the test would likely have passed: the residuals fall by
    // the last ratio seen per product (40 if none was, the fast end of milling maps, so that
    // the schedule moves earlier only with room to spare).
    const double fall = (last_worst > 0.0 && last_test == m - 1 && worst < last_worst)
                            ? last_worst / worst
                            : 40.0;
    const int earlier = worst > 0.0 ? static_cast<int>(std::log(1.0 / worst) / std::log(fall)) : 0;
    out.passes_after = std::max(kNev, m - std::min(earlier, 1));
    out.screened = screening;
    out.mu = values(top);
    out.radius = std::abs(out.mu);
    const Eigen::VectorXd re = V.leftCols(m) * vectors.col(top).real();
    const Eigen::VectorXd im = V.leftCols(m) * vectors.col(top).imag();
    out.vector.resize(n);
    out.vector.real() = re;
    out.vector.imag() = im;
    if (leading) {
      leading->clear();
      for (int q = 0; q < kNev; ++q) {
        const int i = order[static_cast<std::size_t>(q)];
        auto& [value, vector] = leading->emplace_back(values(i), Eigen::VectorXcd());
        if (wants_vector && wants_vector(value)) {
          vector.resize(n);
          vector.real() = V.leftCols(m) * vectors.col(i).real();
          vector.imag() = V.leftCols(m) * vectors.col(i).imag();
        }
      }
    }
    return out;
  }
  return std::nullopt;
}

}  // namespace

std::pair<Bifurcation, double> FdDiscretization::dominant_mode(double depth_m,
                                                               RadiusSolver solver) const {
  const auto map_ptr = make_period_map(impl_->disc, impl_->system, depth_m);
  auto [mu, v] = dominant_eigenpair(*map_ptr, solver);
  DominantMultiplier dm;
  dm.mu = mu;
  dm.radius = std::abs(mu);
  dm.vector = std::move(v);
  return mode_of(dm);
}

DominantMultiplier FdDiscretization::dominant_multiplier(double depth_m,
                                                         RadiusSolver solver) const {
  return dominant_multiplier(depth_m, solver, ArnoldiOptions{});
}

DominantMultiplier FdDiscretization::dominant_multiplier(double depth_m, RadiusSolver solver,
                                                         const ArnoldiOptions& options) const {
  const auto map_ptr = make_period_map(impl_->disc, impl_->system, depth_m);
  const PeriodMap& map = *map_ptr;
  if (solver == RadiusSolver::kArnoldi) {
    if (auto d = krylov_dominant(map, options)) return std::move(*d);
  }
  // Spectra (maps of more than 60 rows), else the dense matrix: as dominant_mode.
  auto [mu, v] = dominant_eigenpair(map, solver);
  DominantMultiplier out;
  out.mu = mu;
  out.radius = std::abs(mu);
  out.vector = std::move(v);
  return out;
}

std::pair<Bifurcation, double> FdDiscretization::mode_of(const DominantMultiplier& dm) const {
  if (!std::isfinite(dm.radius) || dm.vector.size() == 0) {
    throw InvalidInput({"the period map overflows at the boundary (a growth beyond 1e308 in one "
                        "period): the structure is far too flexible for the cutting "
                        "coefficients; check the modes' stiffness and the depth limit"},
                       "full discretization");
  }
  const DelayedSystem& s = impl_->system;
  const double theta = std::arg(dm.mu);
  const Eigen::VectorXcd& v = dm.vector;
  const auto d = s.A0.rows();
  const auto r = s.C.rows();
  std::vector<double> times{0.0};
  std::vector<cplx> values{(s.C.cast<cplx>() * v.head(d))(0)};
  for (Eigen::Index b = 0; d + r * (b + 1) <= v.size(); ++b) {
    times.push_back(impl_->disc.time(-(b + 1)));
    values.push_back(v(d + r * b));
  }
  const int n = impl_->grid.steps();
  const std::vector<double>& nodes = impl_->grid.nodes_s;
  const double h = impl_->grid.period_s / n;
  bool uniform = true;
  for (int j = 0; j < n && uniform; ++j) {
    const double step = nodes[static_cast<std::size_t>(j + 1)] - nodes[static_cast<std::size_t>(j)];
    uniform = std::abs(step - h) <= 1e-9 * h;
  }
  return {classify_multiplier(theta),
          uniform ? detail::dominant_frequency_hz_uniform(theta, impl_->grid.period_s, n, values)
                  : detail::dominant_frequency_hz(theta, impl_->grid.period_s, times, values, n)};
}

CriticalDepth FdDiscretization::first_real_crossing(double below_m, Bifurcation kind) const {
  if (kind != Bifurcation::kFlip && kind != Bifurcation::kFold) {
    throw InvalidInput(
        {std::string("first_real_crossing: the kind must be flip or fold, not ") + to_string(kind)},
        "full discretization");
  }
  CriticalDepth out;
  out.depth_m = below_m;
  if (!(below_m > 0.0)) return out;
  const double mu = kind == Bifurcation::kFlip ? -1.0 : 1.0;
  const auto k_ptr = make_real_multiplier_operator(impl_->disc, impl_->system, mu);
  const RealMultiplierOperator& k_op = *k_ptr;
  const Eigen::Index m = k_op.dim();
  if (m == 0) return out;  // never in contact
  ++out.evaluations;
  const double lambda_min = 1.0 / below_m;
  // The Krylov iteration of the radius searches gives the three eigenvalues of largest
  // modulus; mostly the third (often the first) is already below 1/below_m, and then they
  // hold every depth below below_m. Its residual tolerance, 1e-6 of the eigenvalue, leaves a
  // well-conditioned modulus within about that; within 1e-4 of the bound, or with more than
  // two eigenvalues above it, Krylov–Schur (Spectra) finds more, or the dense matrix (small
  // operators, or Spectra failing) all of them.
  Eigen::VectorXcd values;
  Eigen::MatrixXcd vectors;
  constexpr double kMargin = 1e-4, kRealTolerance = 1e-9;
  ArnoldiOptions loose;
  loose.tolerance = 1e-6;
  RitzPairs leading;
  bool settled = false;
  const auto candidate = [&](cplx l) {  // real, and a depth below below_m
    return l.real() >= lambda_min && std::abs(l.imag()) <= kRealTolerance * std::abs(l);
  };
  if (const auto top = krylov_dominant(k_op, loose, &leading, candidate); top && !leading.empty()) {
    const double last = std::abs(leading.back().first);
    settled = last < lambda_min * (1.0 - kMargin);
    for (const auto& [value, vector] : leading)
      if (std::abs(std::abs(value) - lambda_min) <= kMargin * lambda_min) settled = false;
    if (settled) {
      values.resize(static_cast<Eigen::Index>(leading.size()));
      vectors.resize(m, values.size());
      for (std::size_t q = 0; q < leading.size(); ++q) {
        values(static_cast<Eigen::Index>(q)) = leading[q].first;
        if (leading[q].second.size() == m)  // the candidates' (the others are not needed)
          vectors.col(static_cast<Eigen::Index>(q)) = leading[q].second;
        else
          vectors.col(static_cast<Eigen::Index>(q)).setZero();
      }
    }
  }
  constexpr Eigen::Index kDenseRows = 60, kFirstNev = 6;
  bool dense = !settled && m <= kDenseRows;
  for (Eigen::Index nev = kFirstNev; !settled && !dense;) {
    const Eigen::Index ncv = std::min(m, std::max<Eigen::Index>(2 * nev + 1, 20));
    PeriodMapOp op(k_op);
    Spectra::GenEigsSolver<PeriodMapOp> eigs(op, nev, ncv);
    eigs.init();
    try {
      eigs.compute(Spectra::SortRule::LargestMagn, 1000, 1e-10);
    } catch (const std::exception&) {
      dense = true;
      break;
    } catch (const MapOverflow&) {
      dense = true;
      break;
    }
    if (eigs.info() != Spectra::CompInfo::Successful) {
      dense = true;
      break;
    }
    values = eigs.eigenvalues();
    vectors = eigs.eigenvectors();
    if (values.size() == 0 || values.cwiseAbs().minCoeff() < lambda_min) break;
    if (2 * nev + 2 > m) {  // nearly every eigenvalue is above the bound: all of them
      dense = true;
      break;
    }
    nev *= 2;
  }
  if (dense) {
    Eigen::MatrixXd k = Eigen::MatrixXd::Identity(m, m), scratch;
    k_op.apply(k, scratch);
    if (!k.allFinite()) return out;
    Eigen::EigenSolver<Eigen::MatrixXd> eig(k, true);
    if (eig.info() != Eigen::Success) return out;
    values = eig.eigenvalues();
    vectors = eig.eigenvectors();
  }
  // The largest real positive λ ≥ 1/below_m: the smallest depth.
  Eigen::Index best = -1;
  for (Eigen::Index i = 0; i < values.size(); ++i)
    if (candidate(values(i)) && (best < 0 || values(i).real() > values(best).real())) best = i;
  if (best < 0) return out;
  out.found = true;
  out.depth_m = 1.0 / values(best).real();
  out.bifurcation = kind;
  // The chatter frequency: the harmonic (θ + 2πk)/T, θ = π (flip) or 0 (fold), that carries
  // the solution's displacement (its larger component) over the period.
  const Eigen::VectorXd e = vectors.col(best).real();
  const Eigen::MatrixXd y = k_op.displacements(e.data());
  Eigen::Index row = 0;
  y.rowwise().squaredNorm().maxCoeff(&row);
  const int n = impl_->grid.steps();
  std::vector<double> times(impl_->grid.nodes_s.begin(), impl_->grid.nodes_s.begin() + n);
  std::vector<cplx> samples(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j) samples[static_cast<std::size_t>(j)] = y(row, j);
  out.chatter_hz =
      detail::dominant_frequency_hz(mu < 0.0 ? kPi : 0.0, impl_->grid.period_s, times, samples, n);
  return out;
}

namespace {

double radius_at_zero(const DelayedSystem& s, double period_s) {
  const Eigen::VectorXcd poles = s.A0.eigenvalues();
  double growth = -std::numeric_limits<double>::infinity();
  for (Eigen::Index i = 0; i < poles.size(); ++i) growth = std::max(growth, poles(i).real());
  return std::exp(growth * period_s);
}

}  // namespace

double FdDiscretization::radius_without_cutting() const {
  return radius_at_zero(impl_->system, impl_->grid.period_s);
}

namespace {

// The dominant multipliers of one speed's depth search, depth after depth, each Arnoldi
// iteration first tested where the previous one would have passed (ArnoldiOptions::
// first_test, DominantMultiplier::passes_after), those that only screen ρ < 1 where the
// previous screening would have (at first, two products before the full tolerance's).
class ScheduledRadii {
 public:
  using Evaluate = std::function<DominantMultiplier(double, const ArnoldiOptions&)>;
  explicit ScheduledRadii(Evaluate evaluate) : evaluate_(std::move(evaluate)) {}
  /// `tolerance`: the residual test's (ArnoldiOptions::tolerance); `screen_below` > 0: only
  /// whether ρ < screen_below is asked (ArnoldiOptions::screen_below).
  DominantMultiplier operator()(double depth, double tolerance = ArnoldiOptions{}.tolerance,
                                double screen_below = 0.0) {
    ArnoldiOptions options;
    options.tolerance = tolerance;
    options.screen_below = screen_below;
    options.first_test = full_;
    if (screen_below > 0.0) options.first_test = screened_ > 0 ? screened_ : std::max(0, full_ - 2);
    DominantMultiplier d = evaluate_(depth, options);
    if (d.krylov) (d.screened ? screened_ : full_) = d.passes_after;
    return d;
  }

 private:
  Evaluate evaluate_;
  int full_ = 0, screened_ = 0;  // products of the last radius at each tolerance (0: none yet)
};

ScheduledRadii radii_of(const FdDiscretization& fd, RadiusSolver solver) {
  return ScheduledRadii([&fd, solver](double w, const ArnoldiOptions& options) {
    return fd.dominant_multiplier(w, solver, options);
  });
}

// The depth-dependent system (helical cutter): the step coefficients rebuilt at each depth.
ScheduledRadii radii_of(const std::function<DelayedSystem(double)>& system_at, const FdGrid& grid,
                        RadiusSolver solver) {
  return ScheduledRadii([&system_at, &grid, solver](double w, const ArnoldiOptions& options) {
    return FdDiscretization(system_at(w), grid).dominant_multiplier(w, solver, options);
  });
}

// An island between two grid points that no real multiplier bounds (a complex pair leaving
// and re-entering the unit circle): where the radii on the depth grid below the boundary have
// a local maximum of at least kIslandWatch, the maximum between its two neighbours is sought
// by golden sections (docs/models/milling-stability.md, "Unstable islands and the depth
// search"). `rho[k]`: ρ at k·cell, k = 0 … (rho[0] = ρ(0)), all below 1; NaN where not known.
// Returns a bracket [a stable grid point, an unstable depth], or nullopt.
constexpr double kIslandWatch = 0.9;

std::optional<std::pair<double, double>> island_between_grid_points(const std::vector<double>& rho,
                                                                    double cell, ScheduledRadii& at,
                                                                    double rel_tol,
                                                                    long long& evaluations) {
  constexpr double kGolden = 0.3819660112501051;  // (3 − √5)/2
  constexpr int kMaxProbes = 40;
  for (std::size_t k = 1; k + 1 < rho.size(); ++k) {
    if (!(rho[k] >= kIslandWatch && rho[k] >= rho[k - 1] && rho[k] > rho[k + 1])) continue;
    double a = cell * static_cast<double>(k - 1), b = cell * static_cast<double>(k + 1);
    double c = cell * static_cast<double>(k), fc = rho[k];
    for (int probe = 0; probe < kMaxProbes && b - a > rel_tol * b; ++probe) {
      const bool right = b - c > c - a;
      const double x = right ? c + kGolden * (b - c) : c - kGolden * (c - a);
      const double fx = at(x).radius;
      ++evaluations;
      if (fx >= 1.0) return std::pair{cell * static_cast<double>(k - 1), x};
      if (fx > fc) {
        (right ? a : b) = c;
        c = x;
        fc = fx;
      } else {
        (right ? b : a) = x;
      }
    }
  }
  return std::nullopt;
}

// The coarse scan and Brent's method on ρ − 1, ρ the dominant multiplier's modulus (the
// unrestarted Arnoldi for kArnoldi, with its fallbacks), and the island probe below the
// boundary (island_between_grid_points; ρ(0) = rho0). The mode is left to the caller.
// `at` evaluates the radii (a warm search's, when it falls back here, keeps its schedule).
CriticalDepth scan_grid(ScheduledRadii& at, double rho0, double depth_max, double rel_tol,
                        int coarse_steps) {
  const double cell = depth_max / coarse_steps;
  std::vector<double> rho(static_cast<std::size_t>(coarse_steps) + 1,
                          std::numeric_limits<double>::quiet_NaN());
  rho[0] = rho0;
  const auto margin = [&](double w) {
    const double r = at(w).radius;
    const double k = std::round(w / cell);
    if (k >= 1.0 && k <= coarse_steps && std::abs(w - k * cell) <= 1e-12 * depth_max)
      rho[static_cast<std::size_t>(k)] = r;
    return r - 1.0;
  };
  CriticalDepth result = critical_depth_by_bracketing(margin, depth_max, coarse_steps, rel_tol);
  if (result.found && result.depth_m <= 0.0) return result;
  for (double& r : rho)
    if (!(r < 1.0)) r = std::numeric_limits<double>::quiet_NaN();  // only the stable points
  long long evaluations = 0;
  const auto island = island_between_grid_points(rho, cell, at, rel_tol, evaluations);
  result.evaluations += evaluations;
  if (!island) return result;
  const auto [lo, hi] = *island;
  const auto g = [&](double w) { return at(w).radius - 1.0; };
  const auto root =
      brent_root(g, lo, rho0 < 1.0 && lo == 0.0 ? rho0 - 1.0 : g(lo), hi, g(hi), rel_tol * hi);
  result.found = true;
  result.depth_m = root ? root->x : hi;
  if (root) result.evaluations += root->evaluations;
  return result;
}

CriticalDepth exhaustive_search(const FdDiscretization& fd, ScheduledRadii& at, double depth_max,
                                double rel_tol, int coarse_steps) {
  CriticalDepth result =
      scan_grid(at, fd.radius_without_cutting(), depth_max, rel_tol, coarse_steps);
  if (result.found)
    std::tie(result.bifurcation, result.chatter_hz) =
        fd.mode_of(at(result.depth_m * (1.0 + 0.5 * rel_tol)));
  return result;
}

// A search's answer replaced by the first real-multiplier crossing below it when there is
// one: an unstable island that the search's depth grid stepped over (or the boundary itself,
// found exactly). Flip (μ = −1) always; fold (μ = +1) with several delays (uneven pitch: the
// period is a revolution, and a pitch pattern that repeats within it turns a flip of the
// repeated part into μ = +1 per revolution). The search's other findings (unresolved,
// truncated) are kept.
std::vector<Bifurcation> real_crossings(const DelayedSystem& s) {
  if (s.more_delays.empty()) return {Bifurcation::kFlip};
  return {Bifurcation::kFlip, Bifurcation::kFold};
}

void take_crossing(CriticalDepth crossing, CriticalDepth& result) {
  result.evaluations += crossing.evaluations;
  if (!crossing.found || !(crossing.depth_m < result.depth_m)) return;
  crossing.evaluations = result.evaluations;
  crossing.unresolved = result.unresolved;
  crossing.truncated = result.truncated;
  result = crossing;
}

// The depth below which a search's answer is checked for such crossings: the answer, or the
// limit when stable up to it; none (0) when unstable without cutting.
double crossing_limit(const CriticalDepth& result, double depth_max) {
  if (!result.found) return depth_max;
  return result.depth_m > 0.0 ? result.depth_m : 0.0;
}

void take_real_crossings(const FdDiscretization& fd, const DelayedSystem& s, const FdOptions& o,
                         CriticalDepth& result) {
  if (!o.flip_crossings) return;
  for (Bifurcation kind : real_crossings(s))
    if (const double below = crossing_limit(result, o.depth_max_m); below > 0.0)
      take_crossing(fd.first_real_crossing(below, kind), result);
}

// The same for a depth-dependent system: the crossing depth w of the system at depth w, by the
// fixed-point iteration w ← (first crossing depth of system_at(w)) (the coefficient changes
// slowly with the depth: two or three iterations to 1e-6), started from the search's answer
// and, where the system there has no crossing below it, from 0.9 of it (a narrow island can
// exist for the coefficient of its own depths and not for that of a deeper one).
void take_real_crossings(const std::function<DelayedSystem(double)>& system_at, const FdGrid& grid,
                         const FdOptions& o, CriticalDepth& result) {
  if (!o.flip_crossings) return;
  constexpr int kMaxIterations = 12;
  constexpr double kSettled = 1e-6, kSecondStart = 0.9;
  for (Bifurcation kind : real_crossings(system_at(o.depth_max_m))) {
    const double below = crossing_limit(result, o.depth_max_m);
    if (!(below > 0.0)) return;
    double w = below;
    CriticalDepth crossing;
    for (int k = 0; k < kMaxIterations; ++k) {
      if (k == 1 && !crossing.found) w = kSecondStart * below;
      CriticalDepth next = FdDiscretization(system_at(w), grid).first_real_crossing(below, kind);
      next.evaluations += crossing.evaluations;
      crossing = next;
      if (!crossing.found) {
        if (k > 0) break;
        continue;
      }
      const bool settled = std::abs(crossing.depth_m - w) <= kSettled * w;
      w = crossing.depth_m;
      if (settled) break;
    }
    take_crossing(crossing, result);
  }
}

}  // namespace

namespace {

// The searches on the one grid of `o` (fd_grid); the public functions below add the
// convergence check (FdOptions::refinements).
CriticalDepth search_by_radius(const DelayedSystem& s, const FdOptions& o, RadiusSolver solver,
                               double rel_tol, int coarse_steps) {
  const FdDiscretization fd(s, o);
  ScheduledRadii at = radii_of(fd, solver);
  CriticalDepth result = exhaustive_search(fd, at, o.depth_max_m, rel_tol, coarse_steps);
  take_real_crossings(fd, s, o, result);
  return result;
}

CriticalDepth search_by_radius(const std::function<DelayedSystem(double)>& system_at,
                               const FdOptions& o, RadiusSolver solver, double rel_tol,
                               int coarse_steps) {
  const DelayedSystem at_limit = system_at(o.depth_max_m);
  const FdGrid grid = fd_grid(at_limit, o);
  ScheduledRadii at = radii_of(system_at, grid, solver);
  CriticalDepth result =
      scan_grid(at, radius_at_zero(at_limit, grid.period_s), o.depth_max_m, rel_tol, coarse_steps);
  if (result.found) {
    const double above = result.depth_m * (1.0 + 0.5 * rel_tol);
    std::tie(result.bifurcation, result.chatter_hz) =
        FdDiscretization(system_at(above), grid).mode_of(at(above));
  }
  take_real_crossings(system_at, grid, o, result);
  return result;
}

// The warm-started search (fd_critical_depth_from_hint) on g(w) = ρ(w) − 1, with `at(w)` the
// dominant multiplier at depth w and ρ(0) = rho0 known. nullopt: the exhaustive search must
// decide (no bracket near the hint, or the guard found an unstable grid point below it).
struct WarmFound {
  CriticalDepth result;
  DominantMultiplier at_hi;
  double hi = 0.0;
  double slope = 0.0;  // dρ/dw across the last bracket
};

std::optional<WarmFound> warm_search(ScheduledRadii& at, double rho0, double depth_max,
                                     int coarse_steps, double rel_tol, double hint, bool close,
                                     long long& evaluations, bool guard = true) {
  if (!(hint > 0.0 && hint <= depth_max) || !(rho0 < 1.0)) return std::nullopt;
  // The bracket's depths need only the sign of ρ − 1 and a secant through it: a residual
  // tolerance of 1e-8 (ArnoldiOptions::tolerance) leaves ρ within about 3e-6 of the 1e-10
  // one, a depth error near 1e-5 of the boundary's, against the search's 1e-3.
  constexpr double kBracketTol = 1e-8;
  const auto evaluate = [&](double w, double screen_below = 0.0) {
    ++evaluations;
    return at(w, kBracketTol, screen_below);
  };
  const auto secant = [](double xa, double ga, double xb, double gb) {
    return gb == ga ? std::numeric_limits<double>::quiet_NaN() : xb - gb * (xb - xa) / (gb - ga);
  };
  double lo = 0.0, g_lo = rho0 - 1.0;  // stable
  double hi = -1.0, g_hi = 0.0;        // unstable, once found
  DominantMultiplier at_hi;
  double xa = 0.0, ga = g_lo;  // the point evaluated before the last (for the secant)
  double x = hint, g = 0.0;
  // Evaluates x, and makes it the bracket's stable or unstable end.
  const auto take = [&](double depth) {
    DominantMultiplier d = evaluate(depth);
    g = d.radius - 1.0;
    if (g >= 0.0) {
      hi = depth;
      g_hi = g;
      at_hi = std::move(d);
    } else {
      lo = depth;
      g_lo = g;
    }
  };
  // The exhaustive search's absolute tolerance (rel_tol times the grid point at or above the
  // boundary, eq. MS-15 of docs/models/milling-stability.md; in the first cell's lowest eighth,
  // relative to the boundary).
  const auto tolerance_at = [&](double depth) {
    return boundary_tolerance(depth, depth_max, coarse_steps, rel_tol);
  };
  // A close hint (extrapolated along a smooth lobe, usually within a fraction of the
  // tolerance): the first two depths straddle it, 0.45 tolerance below and above, and when
  // the boundary lies between them the bracket is already narrow enough.
  const double straddle = 0.45 * tolerance_at(hint);
  if (close && hint - straddle > 0.0 && hint + straddle <= depth_max) x = hint - straddle;
  else close = false;
  // 1. Bracket: from the hint, secant steps (the first through (0, ρ(0) − 1)) pushed half a
  //    tolerance past the estimated root, so that the next point tends to land on its far side.
  constexpr int kMaxBracketSteps = 40;
  for (int step = 0;; ++step) {
    if (step == kMaxBracketSteps) return std::nullopt;
    take(x);
    if (hi > 0.0 && lo > 0.0) break;
    if (hi > 0.0 && lo == 0.0 && x <= depth_max / 1e6) return std::nullopt;  // unstable near 0
    double next = secant(xa, ga, x, g);
    if (step == 0 && close && g < 0.0) {  // stable below the close hint: just above it
      xa = x;
      ga = g;
      x = hint + straddle;
      continue;
    }
    if (g < 0.0) {                              // stable so far: go up
      if (x >= depth_max) return std::nullopt;  // stable to the limit above the hint
      next = std::isfinite(next) && next > x ? next * (1.0 + 0.5 * rel_tol) : 2.0 * x;
      next = std::min(std::max(next, x * (1.0 + rel_tol)), std::min(depth_max, 2.0 * x));
    } else {  // unstable: go down (towards the stable anchor lo)
      next = std::isfinite(next) && next < x ? next * (1.0 - 0.5 * rel_tol) : 0.5 * (lo + x);
      next = std::clamp(next, 0.5 * x, x * (1.0 - rel_tol));
    }
    xa = x;
    ga = g;
    x = next;
  }
  // 2. Shrink [lo, hi] to rel_tol·hi: the secant (or regula falsi) estimate r, and a probe a
  //    little past it on the side away from the nearer end, so that when r is good the next
  //    bracket is already narrow enough; a bisection whenever a probe did not halve it.
  double prev_width = hi - lo;
  bool bisect = false;
  const auto tolerance = [&] { return tolerance_at(hi); };
  for (int step = 0; hi - lo > tolerance(); ++step) {
    if (step == 200) return std::nullopt;
    double r = secant(xa, ga, x, g);
    if (!(r > lo && r < hi)) r = lo - g_lo * (hi - lo) / (g_hi - g_lo);
    const double width = hi - lo;
    const double offset = 0.3 * tolerance();
    double probe = (hi - r <= r - lo) ? r - offset : r + offset;
    if (bisect) probe = 0.5 * (lo + hi);
    probe = std::clamp(probe, lo + 0.02 * width, hi - 0.02 * width);
    xa = x;
    ga = g;
    x = probe;
    take(x);
    bisect = !bisect && (hi - lo) > 0.5 * prev_width;
    prev_width = hi - lo;
  }
  // 3. The guard (unless the caller has already searched below on a coarser grid): every point
  //    of the exhaustive scan's grid below the bracket is stable. Only
  //    ρ < 1 is asked: a radius below 0.99 may stop at the screening tolerance (its error
  //    is below 1e-4; ArnoldiOptions::screen_below), one closer to 1 goes to the full one.
  constexpr double kScreenBelow = 0.99;
  std::vector<double> rho(static_cast<std::size_t>(coarse_steps) + 1,
                          std::numeric_limits<double>::quiet_NaN());
  rho[0] = rho0;
  for (int k = guard ? coarse_steps : 0; k >= 1; --k) {
    const double w = depth_max * k / coarse_steps;
    if (!(w < lo)) continue;
    rho[static_cast<std::size_t>(k)] = evaluate(w, kScreenBelow).radius;
    if (rho[static_cast<std::size_t>(k)] >= 1.0) return std::nullopt;
  }
  //    And the exhaustive search's island probe between those points: an island there is
  //    left to it.
  if (guard && island_between_grid_points(rho, depth_max / coarse_steps, at, rel_tol, evaluations))
    return std::nullopt;
  WarmFound out;
  out.result.found = true;
  out.result.depth_m = lo - g_lo * (hi - lo) / (g_hi - g_lo);
  out.at_hi = std::move(at_hi);
  out.hi = hi;
  out.slope = (g_hi - g_lo) / (hi - lo);
  return out;
}

// A search's answer, and dρ/dw there when the search ended on a bracket of ρ − 1 (NaN
// otherwise): the convergence check's Newton step on a finer grid.
struct Searched {
  CriticalDepth result;
  double slope = std::numeric_limits<double>::quiet_NaN();
};

// take_real_crossings on a search's answer: a crossing taken below it has no slope.
template <class... Args>
void take_crossings_into(Searched& found, Args&&... args) {
  const double before = found.result.depth_m;
  take_real_crossings(std::forward<Args>(args)..., found.result);
  if (found.result.depth_m != before) found.slope = std::numeric_limits<double>::quiet_NaN();
}

Searched search_from_hint(const DelayedSystem& s, const FdOptions& o, RadiusSolver solver,
                          double rel_tol, int coarse_steps, double hint, bool close,
                          bool guard = true) {
  const FdDiscretization fd(s, o);
  long long evaluations = 0;
  ScheduledRadii at = radii_of(fd, solver);
  auto found = warm_search(at, fd.radius_without_cutting(), o.depth_max_m, coarse_steps, rel_tol,
                           hint, close, evaluations, guard);
  Searched out;
  if (!found) {
    out.result = exhaustive_search(fd, at, o.depth_max_m, rel_tol, coarse_steps);
    out.result.evaluations += evaluations;
  } else {
    out.result = found->result;
    out.result.evaluations = evaluations;
    out.slope = found->slope;
    std::tie(out.result.bifurcation, out.result.chatter_hz) = fd.mode_of(found->at_hi);
    if (!guard) return out;
  }
  take_crossings_into(out, fd, s, o);
  return out;
}

Searched search_from_hint(const std::function<DelayedSystem(double)>& system_at, const FdOptions& o,
                          RadiusSolver solver, double rel_tol, int coarse_steps, double hint,
                          bool close, bool guard = true) {
  const DelayedSystem at_limit = system_at(o.depth_max_m);
  const FdGrid grid = fd_grid(at_limit, o);
  long long evaluations = 0;
  ScheduledRadii at = radii_of(system_at, grid, solver);
  auto found = warm_search(at, radius_at_zero(at_limit, grid.period_s), o.depth_max_m, coarse_steps,
                           rel_tol, hint, close, evaluations, guard);
  Searched out;
  if (!found) {
    out.result = search_by_radius(system_at, o, solver, rel_tol, coarse_steps);
    out.result.evaluations += evaluations;
    return out;
  }
  out.result = found->result;
  out.result.evaluations = evaluations;
  out.slope = found->slope;
  std::tie(out.result.bifurcation, out.result.chatter_hz) =
      FdDiscretization(system_at(found->hi), grid).mode_of(found->at_hi);
  if (guard) take_crossings_into(out, system_at, grid, o);
  return out;
}

// The convergence check (FdOptions::refinements; docs/models/milling-stability.md, "The step
// and its convergence check"). The grid is first sized by the cut at the boundary found
// (FdOptions::cutting_depth_m; re-searched only when the boundary lies more than a quarter
// deeper than the depth the grid was sized at), then the step is halved: when the search
// ended on a bracket, one radius on the finer grid at the boundary w gives its boundary by a
// Newton step, w + (1 − ρ(w))/ρ' (ρ' from the bracket); otherwise, or when that step is
// longer than the search's tolerance, the finer grid is searched from w (warm, without the
// guard below: that was done on the first grid, whose depth grid and islands do not depend on
// the step). Converged when the boundary moves by less than the tolerance; the answer is the
// finest grid's. `steps(o)` counts the steps of o's grid, `near(o, w)` searches o's grid from
// w, `radius(o, w)` is ρ(w) on it.
Searched converged(Searched found, FdOptions o, double rel_tol, int coarse_steps,
                   const std::function<int(const FdOptions&)>& steps,
                   const std::function<Searched(const FdOptions&, double)>& near,
                   const std::function<double(const FdOptions&, double)>& radius) {
  if (o.refinements == 0 || o.steps_per_period > 0 || !found.result.found ||
      !(found.result.depth_m > 0.0))
    return found;
  const auto tolerance = [&](double depth) {
    return std::max(rel_tol * depth,
                    boundary_tolerance(depth, o.depth_max_m, coarse_steps, rel_tol));
  };
  const auto continue_from = [](Searched next, const CriticalDepth& before) {
    next.result.evaluations += before.evaluations;
    next.result.unresolved = std::max(next.result.unresolved, before.unresolved);
    return next;
  };
  constexpr double kSizingSlack = 1.25;
  constexpr int kMaxResizings = 3;
  for (int k = 0; k < kMaxResizings && found.result.found &&
                  found.result.depth_m > kSizingSlack * o.cutting_depth_m;
       ++k) {
    FdOptions sized = o;
    sized.cutting_depth_m = found.result.depth_m;
    const bool same = steps(sized) == steps(o);
    o = sized;
    if (same) break;
    found = continue_from(near(o, found.result.depth_m), found.result);
  }
  for (int halving = 0; halving < o.refinements && found.result.found; ++halving) {
    o.max_step_fraction *= 0.5;
    o.window_steps *= 2;
    const double w = found.result.depth_m;
    if (std::isfinite(found.slope) && found.slope > 0.0) {
      const double step = (1.0 - radius(o, w)) / found.slope;
      ++found.result.evaluations;
      if (std::abs(step) <= tolerance(w)) {
        found.result.depth_m = w + step;
        return found;
      }
      found = continue_from(near(o, w + step), found.result);
    } else {
      found = continue_from(near(o, w), found.result);
      if (std::abs(found.result.depth_m - w) <= tolerance(w)) return found;
    }
  }
  found.result.unconverged = found.result.found;
  return found;
}

int grid_steps(const DelayedSystem& s, const FdOptions& o) { return fd_grid(s, o).steps(); }

// The radius of the convergence check's Newton step to the residual tolerance of a bracket's
// radii (warm_search): ρ within about 3e-6, the step within 1e-4 of the tolerance.
const ArnoldiOptions newton_radius{.tolerance = 1e-8};

// The callables of `converged` for one system, and for a depth-dependent one.
CriticalDepth converged_search(const DelayedSystem& s, Searched found, const FdOptions& o,
                               RadiusSolver solver, double rel_tol, int coarse_steps) {
  return converged(
             std::move(found), o, rel_tol, coarse_steps,
             [&](const FdOptions& g) { return grid_steps(s, g); },
             [&](const FdOptions& g, double w) {
               return search_from_hint(s, g, solver, rel_tol, coarse_steps, w, true, false);
             },
             [&](const FdOptions& g, double w) {
               return FdDiscretization(s, g).dominant_multiplier(w, solver, newton_radius).radius;
             })
      .result;
}

CriticalDepth converged_search(const std::function<DelayedSystem(double)>& system_at,
                               Searched found, const FdOptions& o, RadiusSolver solver,
                               double rel_tol, int coarse_steps) {
  const DelayedSystem at_limit = system_at(o.depth_max_m);
  return converged(
             std::move(found), o, rel_tol, coarse_steps,
             [&](const FdOptions& g) { return grid_steps(at_limit, g); },
             [&](const FdOptions& g, double w) {
               return search_from_hint(system_at, g, solver, rel_tol, coarse_steps, w, true, false);
             },
             [&](const FdOptions& g, double w) {
               return FdDiscretization(system_at(w), fd_grid(at_limit, g))
                   .dominant_multiplier(w, solver, newton_radius)
                   .radius;
             })
      .result;
}

}  // namespace

CriticalDepth fd_critical_depth_by_radius(const DelayedSystem& s, const FdOptions& o,
                                          RadiusSolver solver, double rel_tol, int coarse_steps) {
  return converged_search(s, {search_by_radius(s, o, solver, rel_tol, coarse_steps)}, o, solver,
                          rel_tol, coarse_steps);
}

CriticalDepth fd_critical_depth_by_radius(const std::function<DelayedSystem(double)>& system_at,
                                          const FdOptions& o, RadiusSolver solver, double rel_tol,
                                          int coarse_steps) {
  return converged_search(system_at,
                          {search_by_radius(system_at, o, solver, rel_tol, coarse_steps)}, o,
                          solver, rel_tol, coarse_steps);
}

CriticalDepth fd_critical_depth_from_hint(const DelayedSystem& s, const FdOptions& o,
                                          RadiusSolver solver, double rel_tol, int coarse_steps,
                                          double hint_depth_m, bool hint_is_close) {
  FdOptions sized = o;
  if (o.refinements > 0) sized.cutting_depth_m = std::max(o.cutting_depth_m, hint_depth_m);
  return converged_search(
      s, search_from_hint(s, sized, solver, rel_tol, coarse_steps, hint_depth_m, hint_is_close),
      sized, solver, rel_tol, coarse_steps);
}

CriticalDepth fd_critical_depth_from_hint(const std::function<DelayedSystem(double)>& system_at,
                                          const FdOptions& o, RadiusSolver solver, double rel_tol,
                                          int coarse_steps, double hint_depth_m,
                                          bool hint_is_close) {
  FdOptions sized = o;
  if (o.refinements > 0) sized.cutting_depth_m = std::max(o.cutting_depth_m, hint_depth_m);
  return converged_search(system_at,
                          search_from_hint(system_at, sized, solver, rel_tol, coarse_steps,
                                           hint_depth_m, hint_is_close),
                          sized, solver, rel_tol, coarse_steps);
}

CriticalDepth fd_critical_depth_dense(const DelayedSystem& s, const FdOptions& o, double rel_tol,
                                      int coarse_steps) {
  return fd_critical_depth_by_radius(s, o, RadiusSolver::kDense, rel_tol, coarse_steps);
}

CriticalDepth fd_critical_depth(const DelayedSystem& s, const FdOptions& o) {
  if (!s.more_delays.empty()) {
    throw InvalidInput({"more_delays: the reduced full discretization takes one delay (use "
                        "fd_critical_depth_by_radius)"},
                       "full discretization");
  }
  if (o.order != 1) {
    throw InvalidInput({"order = " + std::to_string(o.order) +
                        ": the reduced full discretization takes the linear interpolation "
                        "(order 1); the spectral-radius methods take order 2"},
                       "full discretization");
  }
  const FdGrid grid = fd_grid(s, o);
  const Discretization disc(s, grid);
  const int n = disc.n();
  const auto d = s.A0.rows();
  const auto r = s.C.rows();

  std::vector<int> active;
  for (int j = 0; j < n; ++j)
    if (disc.step(j).active()) active.push_back(j);
  if (active.empty()) return CriticalDepth{o.depth_max_m};  // never in contact: never unstable
  const auto m = static_cast<Eigen::Index>(2 * r * static_cast<Eigen::Index>(active.size()));

  // Response of the nodal displacements to the step inputs z = (a_j, b_j) over one period of
  // a solution with multiplier μ: Y = (Tc + Cp·(μI − Ψ)⁻¹·V)·z.
  Eigen::MatrixXd Tc = Eigen::MatrixXd::Zero(r * n, m);
  Eigen::MatrixXd V(d, m);
  Eigen::MatrixXd Cp(r * n, d);
  Eigen::MatrixXd prefix = Eigen::MatrixXd::Identity(d, d);
  for (int i = 0; i < n; ++i) {
    Cp.middleRows(r * i, r) = s.C * prefix;
    prefix = disc.step(i).phi0() * prefix;
  }
  const Eigen::MatrixXd psi = prefix;  // e^(A0·T)
  for (std::size_t jj = 0; jj < active.size(); ++jj) {
    const int j = active[jj];
    for (int which = 0; which < 2; ++which) {
      const Eigen::Index col = (2 * static_cast<Eigen::Index>(jj) + which) * r;
      Eigen::MatrixXd v = which == 0 ? disc.step(j).w0E() : disc.step(j).w1E();  // into x(j+1)
      for (int i = j + 1; i < n; ++i) {
        Tc.block(r * i, col, r, r) = s.C * v;
        v = disc.step(i).phi0() * v;
      }
      V.middleCols(col, r) = v;
    }
  }

  // The closure z = w·Q(μ)·Y as terms (row block, node, coefficient, power of μ):
  // a_j = H̄j·(ŷ(j) − y(j)), b_j = H̄j·(ŷ(j+1) − y(j+1)), with y(g) = μ^floor(g/n)·Y(g mod n).
  struct Term {
    Eigen::Index row_block;
    Eigen::Index node;
    double coef;
    long long power;
  };
  std::vector<Term> terms;
  const auto add_y = [&](Eigen::Index rb, long long g, double coef) {
    if (coef == 0.0) return;
    const long long p = floor_div(g, n);
    terms.push_back({rb, static_cast<Eigen::Index>(g - p * n), coef, p});
  };
  long long delay_periods = 0;
  for (std::size_t jj = 0; jj < active.size(); ++jj) {
    const int j = active[jj];
    for (int which = 0; which < 2; ++which) {
      const auto rb = static_cast<Eigen::Index>(2 * jj + which);
      const int node = j + which;
      const DelayRef& ref = disc.ref(node);
      add_y(rb, ref.g, 1.0 - ref.alpha);
      add_y(rb, ref.g + 1, ref.alpha);
      add_y(rb, node, -1.0);
      delay_periods = std::max(delay_periods, -floor_div(ref.g, n));
    }
  }

  const double min_eigenvalue = 1.0 / o.depth_max_m;
  Eigen::MatrixXcd T(r * n, m), trow(r, m), rhs(d, m);
  const Eigen::MatrixXcd Tc_c = Tc.cast<cplx>(), Cp_c = Cp.cast<cplx>(), V_c = V.cast<cplx>();
  const auto response = [&](double theta) {
    const cplx mu = std::polar(1.0, theta);
    Eigen::MatrixXcd shifted = -psi.cast<cplx>();
    shifted.diagonal().array() += mu;
    rhs.noalias() = shifted.partialPivLu().solve(V_c);
    T.noalias() = Cp_c * rhs;
    T += Tc_c;
  };
  const MatrixFunction evaluate = [&](double theta, Eigen::MatrixXcd& K) {
    response(theta);
    K.setZero(m, m);
    for (Eigen::Index rb = 0; rb < m / r; ++rb) {
      trow.setZero();
      for (const Term& t : terms) {
        if (t.row_block != rb) continue;
        trow += (t.coef * std::polar(1.0, theta * static_cast<double>(t.power))) *
                T.middleRows(r * t.node, r);
      }
      const int j = active[static_cast<std::size_t>(rb / 2)];
      K.middleRows(r * rb, r) = disc.H(j).cast<cplx>() * trow;
    }
    return K.norm() >= 0.5 * min_eigenvalue;  // as the scan's own margin
  };

  BoundaryScanOptions scan;
  scan.theta_min = 0.0;
  scan.theta_max = kPi;
  // A multiplier e^(iθ) stands for the frequencies (±θ + 2πk)/T. When the period is short
  // against the structure (Ω = 2π/T well above every frequency at which the structure can
  // respond enough to reach depth_max), only θ/T itself can matter: stop the scan there
  // instead of sampling the whole half circle.
  double h_norm = 0.0;
  for (int j : active) h_norm = std::max(h_norm, disc.H(j).norm());
  const double w_limit = 1.5 * response_limit_rad_s(s, h_norm, o.depth_max_m);
  const double omega = kTwoPi / grid.period_s;
  bool partial = false;
  if (omega > 2.0 * w_limit && w_limit * grid.period_s < kPi) {
    scan.theta_max = w_limit * grid.period_s;
    partial = true;
  }
  const double resonance = 0.25 * sharpest_half_bandwidth(s) * grid.period_s;
  scan.theta_step =
      std::min(kTwoPi / (o.samples_per_turn * static_cast<double>(delay_periods + 1)), resonance);
  scan.min_eigenvalue = min_eigenvalue;
  scan.real_at_ends = !partial;  // θ = π (multiplier −1) only when the scan reaches it
  const BoundaryScanReport report = scan_boundary(evaluate, scan);
  CriticalDepth result = critical_depth_from_scan(report, o.depth_max_m);
  if (!result.found) return result;

  const BoundaryPoint& best = report.points.front();
  result.bifurcation = classify_multiplier(best.theta);
  response(best.theta);
  const Eigen::VectorXcd y = T * best.eigenvector;
  std::vector<double> times;
  std::vector<cplx> values;
  for (int i = 0; i < n; ++i) {
    times.push_back(grid.nodes_s[static_cast<std::size_t>(i)]);
    values.push_back(y(r * i));
  }
  result.chatter_hz = detail::dominant_frequency_hz(best.theta, grid.period_s, times, values, n);
  return result;
}

}  // namespace cutdyn
