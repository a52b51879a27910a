#include "cutdyn/stability/boundary_scan.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cutdyn/core/roots.hpp"

namespace cutdyn {
namespace {

using cplx = std::complex<double>;

struct Sample {
  double theta = 0.0;
  bool computed = false;
  Eigen::VectorXcd values;
};

class Evaluator {
 public:
  Evaluator(const MatrixFunction& f, long long& count) : f_(f), count_(count) {}

  // Eigenvalues at θ, or an empty vector when the bound rules every eigenvalue out.
  Eigen::VectorXcd values(double theta) {
    ++count_;
    if (!f_(theta, k_)) return {};
    solver_.compute(k_, false);
    return solver_.eigenvalues();
  }

  // Eigenvalue nearest `target` and its eigenvector.
  std::pair<cplx, Eigen::VectorXcd> nearest(double theta, cplx target) {
    ++count_;
    f_(theta, k_);
    solver_.compute(k_, true);
    Eigen::Index best = 0;
    solver_.eigenvalues().unaryExpr([&](cplx v) { return std::abs(v - target); }).minCoeff(&best);
    return {solver_.eigenvalues()(best), solver_.eigenvectors().col(best)};
  }

 private:
  const MatrixFunction& f_;
  long long& count_;
  Eigen::MatrixXcd k_;
  Eigen::ComplexEigenSolver<Eigen::MatrixXcd> solver_;
};

struct Candidate {
  double theta_a, theta_b;
  cplx lambda_a, lambda_b;
  double depth_estimate;
};

}  // namespace

BoundaryScanReport scan_boundary(const MatrixFunction& evaluate, const BoundaryScanOptions& o) {
  BoundaryScanReport report;
  Evaluator ev(evaluate, report.evaluations);
  const double span = o.theta_max - o.theta_min;
  const auto n = static_cast<long long>(std::max(1.0, std::ceil(span / o.theta_step)));
  const double h = span / static_cast<double>(n);
  // Eigenvalues that may matter at the next grid point: a margin below min_eigenvalue lets
  // an eigenvalue that crosses the real axis just above it be followed from a sample where
  // it was slightly smaller.
  const double keep = 0.5 * o.min_eigenvalue;

  std::vector<Candidate> candidates;
  std::vector<BoundaryPoint> direct;  // real eigenvalues at the end points
  Eigen::VectorXcd prev = ev.values(o.theta_min);
  double prev_theta = o.theta_min;
  auto take_real_at = [&](double theta, const Eigen::VectorXcd& values) {
    for (Eigen::Index i = 0; i < values.size(); ++i) {
      const cplx v = values(i);
      if (v.real() >= o.min_eigenvalue && std::abs(v.imag()) <= 1e-9 * std::abs(v)) {
        auto [lambda, vec] = ev.nearest(theta, v);
        direct.push_back({theta, 1.0 / lambda.real(), lambda, vec});
      }
    }
  };
  if (o.real_at_ends) take_real_at(o.theta_min, prev);

  for (long long s = 1; s <= n; ++s) {
    const double theta = s == n ? o.theta_max : o.theta_min + static_cast<double>(s) * h;
    Eigen::VectorXcd cur = ev.values(theta);
    if (prev.size() > 0 && cur.size() > 0) {
      std::vector<bool> used(static_cast<std::size_t>(cur.size()), false);
      for (Eigen::Index i = 0; i < prev.size(); ++i) {
        const cplx a = prev(i);
        if (a.real() < keep) continue;
        Eigen::Index best = -1;
        double best_d = std::numeric_limits<double>::infinity();
        for (Eigen::Index j = 0; j < cur.size(); ++j) {
          if (used[static_cast<std::size_t>(j)]) continue;
          const double dist = std::abs(cur(j) - a);
          if (dist < best_d) {
            best_d = dist;
            best = j;
          }
        }
        if (best < 0) continue;
        used[static_cast<std::size_t>(best)] = true;
        const cplx b = cur(best);
        if ((a.imag() > 0.0) == (b.imag() > 0.0) || a.imag() == b.imag()) continue;
        const double frac = a.imag() / (a.imag() - b.imag());
        const double re = a.real() + frac * (b.real() - a.real());
        if (re < keep) continue;
        candidates.push_back({prev_theta, theta, a, b, 1.0 / re});
      }
    }
    prev = std::move(cur);
    prev_theta = theta;
  }
  if (o.real_at_ends) take_real_at(o.theta_max, prev);

  // Refine in order of the interpolated depth; stop once an estimate exceeds the best
  // refined depth (or end-point depth) by more than refine_factor.
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return a.depth_estimate < b.depth_estimate;
  });
  double best = std::numeric_limits<double>::infinity();
  for (const BoundaryPoint& p : direct) best = std::min(best, p.depth);
  for (const Candidate& c : candidates) {
    if (c.depth_estimate > o.refine_factor * best) break;
    // Follow the eigenvalue: at θ the one nearest the straight line from λa to λb.
    const auto follow = [&](double theta) {
      const double t = (theta - c.theta_a) / (c.theta_b - c.theta_a);
      return ev.nearest(theta, c.lambda_a + t * (c.lambda_b - c.lambda_a)).first;
    };
    const auto root = brent_root([&](double theta) { return follow(theta).imag(); }, c.theta_a,
                                 c.theta_b, o.theta_tol * (c.theta_b - c.theta_a), 100);
    if (!root || !root->converged) {
      ++report.unresolved;
      continue;
    }
    const double t = (root->x - c.theta_a) / (c.theta_b - c.theta_a);
    auto [lambda, vec] = ev.nearest(root->x, c.lambda_a + t * (c.lambda_b - c.lambda_a));
    if (!(lambda.real() >= o.min_eigenvalue)) continue;
    report.points.push_back({root->x, 1.0 / lambda.real(), lambda, vec});
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
