#include "cutdyn/stability/detail/boundary_scan.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "cutdyn/core/detail/roots.hpp"
#include "cutdyn/stability/detail/large_eigenvalues.hpp"

namespace cutdyn {
namespace {

using cplx = std::complex<double>;

struct Sample {
  double theta = 0.0;
  bool computed = false;
  Eigen::VectorXcd values;
};

// Eigenvalues of a 2×2 matrix in closed form: the roots of λ² − tr·λ + det = 0, the larger
// by the sign of the square root that avoids cancellation, the other as det/λ1 (accurate when
// the two differ by orders of magnitude, as at a resonance of one direction). The zero-order
// method's K is 2×2 for milling, and the scan solves it at every sample: the closed form costs a
// small fraction of the general Schur iteration it replaces and agrees with it to rounding
// (tests/stability/boundary_scan_test.cpp).
void eigenvalues_2x2(const Eigen::MatrixXcd& k, Eigen::VectorXcd& out) {
  const cplx a = k(0, 0), b = k(0, 1), c = k(1, 0), d = k(1, 1);
  const cplx half = 0.5 * (a + d);
  const cplx root = std::sqrt(0.25 * (a - d) * (a - d) + b * c);
  const cplx big = std::real(std::conj(half) * root) >= 0.0 ? half + root : half - root;
  out.resize(2);
  out(0) = big;
  // det/λ1 as det·conj(λ1)/|λ1|²: the library's complex division guards against overflow
  // the entries of K cannot reach, at several times the cost.
  const double size = std::norm(big);
  out(1) = size == 0.0 ? cplx{} : (a * d - b * c) * std::conj(big) / size;
}

// An eigenvector of a 2×2 matrix for its eigenvalue λ: the larger of the two null vectors
// the rows of K − λI give, normalised.
Eigen::VectorXcd eigenvector_2x2(const Eigen::MatrixXcd& k, cplx lambda) {
  const cplx a = k(0, 0) - lambda, b = k(0, 1), c = k(1, 0), d = k(1, 1) - lambda;
  Eigen::Vector2cd from_first(b, -a), from_second(d, -c);
  Eigen::VectorXcd v = from_first.squaredNorm() >= from_second.squaredNorm() ? from_first
                                                                             : from_second;
  const double n = v.norm();
  if (n == 0.0) return Eigen::Vector2cd(1.0, 0.0);  // K = λI: every vector is one
  return v / n;
}

class Evaluator {
 public:
  // `threshold`: values() returns at least every eigenvalue of this modulus.
  Evaluator(const MatrixFunction& f, long long& count, double threshold, bool dense)
      : f_(f), count_(count), threshold_(threshold), solver_(dense) {}

  // Eigenvalues at θ, or an empty vector when the bound rules every eigenvalue out.
  Eigen::VectorXcd values(double theta) {
    ++count_;
    if (!f_(theta, k_)) return {};
    if (k_.rows() == 1) return k_.col(0);
    if (k_.rows() == 2) {
      Eigen::VectorXcd v;
      eigenvalues_2x2(k_, v);
      return v;
    }
    solver_.compute(k_, threshold_, false);
    return solver_.eigenvalues();
  }

  // Eigenvalue nearest `target` and, if asked, its eigenvector.
  std::pair<cplx, Eigen::VectorXcd> nearest(double theta, cplx target, bool vector = true) {
    ++count_;
    f_(theta, k_);
    if (k_.rows() == 1) return {k_(0, 0), Eigen::VectorXcd::Ones(1)};
    if (k_.rows() == 2) {
      Eigen::VectorXcd v;
      eigenvalues_2x2(k_, v);
      const cplx best = std::abs(v(0) - target) <= std::abs(v(1) - target) ? v(0) : v(1);
      if (!vector) return {best, {}};
      return {best, eigenvector_2x2(k_, best)};
    }
    return solver_.nearest(k_, target, vector);
  }

 private:
  const MatrixFunction& f_;
  long long& count_;
  double threshold_;
  Eigen::MatrixXcd k_;
  detail::LargeEigenvalues solver_;
};

struct Candidate {
  double theta_a, theta_b;
  cplx lambda_a, lambda_b;
  double depth_estimate;
  int level = 0;  // times the bracket has been scanned again (see scan_boundary)
};

}  // namespace

namespace {

// n equal steps from a to b: the n + 1 samples, both ends exact.
std::vector<double> uniform_grid(double a, double b, long long n) {
  std::vector<double> grid(static_cast<std::size_t>(n) + 1);
  const double h = (b - a) / static_cast<double>(n);
  for (long long s = 0; s < n; ++s)
    grid[static_cast<std::size_t>(s)] = a + static_cast<double>(s) * h;
  grid.back() = b;
  return grid;
}

// Crossings of the positive real axis by eigenvalues followed from one sample of `grid` to
// the next (`first` holds the eigenvalues at grid.front()). Where the matching of an
// eigenvalue that matters is ambiguous — its nearest successor is not clearly nearer than the
// next one, as when eigenvalues crowd — the step is split in kSplit and followed again (at
// most kMaxSplits times), so that a crossing is neither missed nor made up by a swap.
void find_candidates(Evaluator& ev, const std::vector<double>& grid, Eigen::VectorXcd first,
                     double keep, int level, std::vector<Candidate>& candidates,
                     Eigen::VectorXcd* last = nullptr, int splits = 0) {
  constexpr long long kSplit = 4;
  constexpr int kMaxSplits = 3;
  Eigen::VectorXcd prev = std::move(first);
  double prev_theta = grid.front();
  for (std::size_t s = 1; s < grid.size(); ++s) {
    const double theta = grid[s];
    Eigen::VectorXcd cur = ev.values(theta);
    if (prev.size() > 0 && cur.size() > 0) {
      std::vector<Candidate> found;
      bool ambiguous = false;
      std::vector<bool> used(static_cast<std::size_t>(cur.size()), false);
      for (Eigen::Index i = 0; i < prev.size(); ++i) {
        const cplx a = prev(i);
        if (a.real() < keep) continue;
        // Distances squared (no square root per pair): the nearest and the next nearest.
        Eigen::Index best = -1;
        double best_d = std::numeric_limits<double>::infinity();
        double second_d = std::numeric_limits<double>::infinity();
        for (Eigen::Index j = 0; j < cur.size(); ++j) {
          const double dist = std::norm(cur(j) - a);
          if (used[static_cast<std::size_t>(j)]) continue;
          if (dist < best_d) {
            second_d = best_d;
            best_d = dist;
            best = j;
          } else if (dist < second_d) {
            second_d = dist;
          }
        }
        if (best < 0) continue;
        if (best_d > 0.25 * second_d) ambiguous = true;  // nearest not clearly nearer: 0.5²
        used[static_cast<std::size_t>(best)] = true;
        const cplx b = cur(best);
        if ((a.imag() > 0.0) == (b.imag() > 0.0) || a.imag() == b.imag()) continue;
        const double frac = a.imag() / (a.imag() - b.imag());
        const double re = a.real() + frac * (b.real() - a.real());
        if (re < keep) continue;
        found.push_back({prev_theta, theta, a, b, 1.0 / re, level});
      }
      if (ambiguous && splits < kMaxSplits) {
        find_candidates(ev, uniform_grid(prev_theta, theta, kSplit), prev, keep, level, candidates,
                        nullptr, splits + 1);
      } else {
        candidates.insert(candidates.end(), found.begin(), found.end());
      }
    }
    prev = std::move(cur);
    prev_theta = theta;
  }
  if (last) *last = std::move(prev);
}

}  // namespace

BoundaryScanReport scan_boundary(const MatrixFunction& evaluate, const BoundaryScanOptions& o) {
  BoundaryScanReport report;
  // Eigenvalues that may matter at the next grid point: a margin below min_eigenvalue lets
  // an eigenvalue that crosses the real axis just above it be followed from a sample where
  // it was slightly smaller. The samples hold every eigenvalue of half that modulus, so that
  // one that matters is matched to its own successor, not to another.
  const double keep = 0.5 * o.min_eigenvalue;
  Evaluator ev(evaluate, report.evaluations, 0.5 * keep, o.dense);
  const double span = o.theta_max - o.theta_min;
  const auto n = static_cast<long long>(std::max(1.0, std::ceil(span / o.theta_step)));
  std::vector<double> grid;
  if (o.step_at) {
    // Steps of at most theta_step, shorter where step_at says K changes fast; the last one
    // ends on theta_max (no wider than the rule allows there).
    grid.push_back(o.theta_min);
    for (;;) {
      const double theta = grid.back();
      const double h = std::min(o.theta_step, o.step_at(theta));
      if (!(h > 0.0)) throw std::logic_error("scan_boundary: step_at must be positive");
      if (theta + h >= o.theta_max) break;
      grid.push_back(theta + h);
    }
    grid.push_back(o.theta_max);
  } else {
    grid = uniform_grid(o.theta_min, o.theta_max, n);
  }

  std::vector<Candidate> candidates;
  std::vector<BoundaryPoint> direct;  // real eigenvalues at the end points
  auto take_real_at = [&](double theta, const Eigen::VectorXcd& values) {
    for (Eigen::Index i = 0; i < values.size(); ++i) {
      const cplx v = values(i);
      if (v.real() >= o.min_eigenvalue && std::abs(v.imag()) <= 1e-9 * std::abs(v)) {
        auto [lambda, vec] = ev.nearest(theta, v);
        direct.push_back({theta, 1.0 / lambda.real(), lambda, vec});
      }
    }
  };
  Eigen::VectorXcd first = ev.values(o.theta_min), last;
  if (o.real_at_ends) take_real_at(o.theta_min, first);
  find_candidates(ev, grid, std::move(first), keep, 0, candidates, &last);
  if (o.real_at_ends) take_real_at(o.theta_max, last);

  // Refine in order of the interpolated depth; stop once an estimate exceeds the best
  // refined depth (or end-point depth) by more than refine_factor.
  const auto by_depth = [](const Candidate& a, const Candidate& b) {
    return a.depth_estimate < b.depth_estimate;
  };
  std::sort(candidates.begin(), candidates.end(), by_depth);
  double best = std::numeric_limits<double>::infinity();
  for (const BoundaryPoint& p : direct) best = std::min(best, p.depth);
  // A crossing is real when the followed eigenvalue is real at the refined θ. Where two
  // eigenvalues pass close to each other between samples, nearest-neighbour matching can
  // swap them and show a sign change of the imaginary part that no eigenvalue makes; such a
  // bracket is scanned again with kRescan finer steps (at most kLevels times), and what is
  // still not a root is counted as unresolved.
  constexpr long long kRescan = 16;
  constexpr int kLevels = 3;
  constexpr double kRealTolerance = 1e-6;
  for (std::size_t next = 0; next < candidates.size(); ++next) {
    const Candidate c = candidates[next];
    if (c.depth_estimate > o.refine_factor * best) break;
    // Follow the eigenvalue: at θ the one nearest the straight line from λa to λb.
    const auto follow = [&](double theta) {
      const double t = (theta - c.theta_a) / (c.theta_b - c.theta_a);
      return ev.nearest(theta, c.lambda_a + t * (c.lambda_b - c.lambda_a), false).first;
    };
    const auto root = brent_root([&](double theta) { return follow(theta).imag(); }, c.theta_a,
                                 c.theta_b, o.theta_tol * (c.theta_b - c.theta_a), 100);
    std::optional<std::pair<cplx, Eigen::VectorXcd>> found;
    if (root && root->converged) {
      const double t = (root->x - c.theta_a) / (c.theta_b - c.theta_a);
      found = ev.nearest(root->x, c.lambda_a + t * (c.lambda_b - c.lambda_a));
      if (std::abs(found->first.imag()) > kRealTolerance * std::abs(found->first))
        found.reset();  // a jump between two eigenvalues, not a root
    }
    if (!found) {
      if (c.level >= kLevels) {
        ++report.unresolved;
        continue;
      }
      std::vector<Candidate> finer;
      find_candidates(ev, uniform_grid(c.theta_a, c.theta_b, kRescan), ev.values(c.theta_a), keep,
                      c.level + 1, finer);
      candidates.insert(candidates.end(), finer.begin(), finer.end());
      std::sort(candidates.begin() + static_cast<std::ptrdiff_t>(next) + 1, candidates.end(),
                by_depth);
      continue;
    }
    const cplx lambda = found->first;
    if (!(lambda.real() >= o.min_eigenvalue)) continue;
    report.points.push_back({root->x, 1.0 / lambda.real(), lambda, std::move(found->second)});
    best = std::min(best, 1.0 / lambda.real());
  }
  for (BoundaryPoint& p : direct) {
    if (p.depth * o.min_eigenvalue <= 1.0) report.points.push_back(std::move(p));
  }
  std::sort(report.points.begin(), report.points.end(),
            [](const BoundaryPoint& a, const BoundaryPoint& b) { return a.depth < b.depth; });
  return report;
}

CriticalDepth critical_depth_from_scan(const BoundaryScanReport& report, double depth_max_m) {
  CriticalDepth result;
  result.depth_m = depth_max_m;
  result.evaluations = report.evaluations;
  result.unresolved = report.unresolved;
  if (!report.points.empty()) {
    result.found = true;
    result.depth_m = report.points.front().depth;
  }
  return result;
}

}  // namespace cutdyn
