#include "cutdyn/stability/detail/large_eigenvalues.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace cutdyn::detail {
namespace {

using cplx = std::complex<double>;

constexpr Eigen::Index kDenseUpTo = 32;   // below this the dense solver is as cheap
constexpr Eigen::Index kFirstBasis = 12;  // Arnoldi vectors before the first test
constexpr double kRitzTolerance = 1e-10;
constexpr double kNearestTolerance = 1e-12;
// The rounding floor of a residual, relative to the matrix's Frobenius norm (a product with an
// N×N matrix is exact to about N·ε of it).
constexpr double kRoundingFloor = 1e-13;
constexpr int kMaxInverseIterations = 30;

// A fixed start vector without structure, so that every eigenvector has a component in it:
// mt19937's raw numbers, which the standard fixes (the same on every platform).
void start_vector(Eigen::Ref<Eigen::VectorXcd> v) {
  std::mt19937 generator(20261202u);
  constexpr double kScale = 1.0 / 4294967296.0;
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    const double re = static_cast<double>(generator()) * kScale - 0.5;
    const double im = static_cast<double>(generator()) * kScale - 0.5;
    v(i) = cplx(re, im);
  }
  v.normalize();
}

// Unit eigenvectors of an upper triangular T, column k for T(k, k), by back substitution
// (T − T(k,k)·I)·x = 0 with x_k = 1 and x_j = 0 below; a vanishing divisor (a repeated
// eigenvalue) is replaced by a tiny one, as LAPACK's ztrevc does.
void triangular_eigenvectors(const Eigen::MatrixXcd& T, Eigen::MatrixXcd& x) {
  const Eigen::Index m = T.rows();
  x.setZero(m, m);
  const double small = std::max(T.norm(), std::numeric_limits<double>::min()) * 1e-16;
  for (Eigen::Index k = 0; k < m; ++k) {
    const cplx lambda = T(k, k);
    x(k, k) = 1.0;
    for (Eigen::Index j = k - 1; j >= 0; --j) {
      cplx sum = 0.0;
      for (Eigen::Index l = j + 1; l <= k; ++l) sum += T(j, l) * x(l, k);
      cplx divisor = T(j, j) - lambda;
      if (std::abs(divisor) < small) divisor = small;
      x(j, k) = -sum / divisor;
    }
    x.col(k).normalize();
  }
}

}  // namespace

void LargeEigenvalues::compute_dense(const Eigen::MatrixXcd& K, bool vectors) {
  dense_ = true;
  full_.compute(K, vectors);
  values_ = full_.eigenvalues();
  if (vectors) vectors_ = full_.eigenvectors();  // unit columns
}

void LargeEigenvalues::compute(const Eigen::MatrixXcd& K, double threshold, bool vectors) {
  const Eigen::Index n = K.rows();
  if (always_dense_ || n <= kDenseUpTo) return compute_dense(K, vectors);
  dense_ = false;
  const Eigen::Index max_basis = n / 2;
  basis_.resize(n, max_basis + 1);
  hessenberg_.setZero(max_basis + 1, max_basis);
  start_vector(basis_.col(0));
  Eigen::VectorXcd w(n), h;
  // A scan asks for the eigenvalues of nearby matrices: start with the basis the last one
  // needed, so that it is usually tested once.
  Eigen::Index m = 0, target = std::min(max_basis, std::max(kFirstBasis, last_basis_));
  for (;;) {
    bool invariant = false;  // the basis spans an invariant subspace: its values are exact
    for (; m < target; ++m) {
      w.noalias() = K * basis_.col(m);
      const double size = w.norm();
      for (int pass = 0; pass < 2; ++pass) {  // classical Gram–Schmidt, twice
        h.noalias() = basis_.leftCols(m + 1).adjoint() * w;
        w.noalias() -= basis_.leftCols(m + 1) * h;
        hessenberg_.col(m).head(m + 1) += h;
      }
      const double beta = w.norm();
      hessenberg_(m + 1, m) = beta;
      if (beta <= 1e-14 * size || beta == 0.0) {
        ++m;
        invariant = true;
        break;
      }
      basis_.col(m + 1) = w / beta;
    }
    // Ritz pairs: H_m = U·T·Uᴴ (H_m is already upper Hessenberg, so the Schur iteration
    // starts from it), and T's eigenvectors x by back substitution; y = U·x.
    schur_.computeFromHessenberg(hessenberg_.topLeftCorner(m, m), Eigen::MatrixXcd::Identity(m, m),
                                 true);
    if (schur_.info() != Eigen::Success) return compute_dense(K, vectors);
    const Eigen::MatrixXcd& T = schur_.matrixT();
    triangular_eigenvectors(T, ritz_);
    // The residual of the Ritz pair (θ, V·y), |y| = 1, is β·|y_m|.
    const double beta = invariant ? 0.0 : std::abs(hessenberg_(m, m - 1));
    const double floor = kRoundingFloor * T.norm();
    const auto last = schur_.matrixU().row(m - 1);
    bool converged = true;
    int below = 0;
    std::vector<Eigen::Index> found;
    for (Eigen::Index i = 0; i < m; ++i) {
      const double size = std::abs(T(i, i));
      const double residual = beta * std::abs((last * ritz_.col(i)).value());
      const bool done = residual <= kRitzTolerance * std::max(size, threshold) + floor;
      if (size >= threshold && !done) converged = false;
      if (size < threshold && done) ++below;
      if (done) found.push_back(i);
    }
    if (invariant || (converged && below >= 2)) {
      last_basis_ = m;
      // In increasing real part, as the dense solver gives them: a scan matches them to the
      // next sample's in this order.
      std::sort(found.begin(), found.end(),
                [&](Eigen::Index a, Eigen::Index b) { return T(a, a).real() < T(b, b).real(); });
      const auto count = static_cast<Eigen::Index>(found.size());
      values_.resize(count);
      if (vectors) vectors_.resize(n, count);
      for (Eigen::Index j = 0; j < count; ++j) {
        const Eigen::Index i = found[static_cast<std::size_t>(j)];
        values_(j) = T(i, i);
        if (vectors)
          vectors_.col(j) = (basis_.leftCols(m) * (schur_.matrixU() * ritz_.col(i))).normalized();
      }
      return;
    }
    if (m >= max_basis) return compute_dense(K, vectors);
    target = std::min(max_basis, m + std::max<Eigen::Index>(4, m / 2));
  }
}

std::pair<cplx, Eigen::VectorXcd> LargeEigenvalues::nearest(const Eigen::MatrixXcd& K, cplx target,
                                                            bool vector) {
  const Eigen::Index n = K.rows();
  if (always_dense_) return nearest_dense(K, target, vector);
  Eigen::MatrixXcd shifted = K;
  shifted.diagonal().array() -= target;
  lu_.compute(shifted);
  const double floor = kRoundingFloor * K.norm();
  Eigen::VectorXcd x(n), y(n), kx(n);
  start_vector(x);
  for (int i = 0; i < kMaxInverseIterations; ++i) {
    y.noalias() = lu_.solve(x);
    const double size = y.norm();
    if (!(size > 0.0) || !std::isfinite(size)) break;  // target exactly an eigenvalue
    x = y / size;
    kx.noalias() = K * x;
    const cplx mu = x.dot(kx);  // Rayleigh quotient (x is a unit vector)
    if ((kx - mu * x).norm() <= kNearestTolerance * std::abs(mu) + floor)
      return {mu, vector ? x : Eigen::VectorXcd()};
  }
  return nearest_dense(K, target, vector);
}

std::pair<cplx, Eigen::VectorXcd> LargeEigenvalues::nearest_dense(const Eigen::MatrixXcd& K,
                                                                  cplx target, bool vector) {
  full_.compute(K, vector);
  Eigen::Index best = 0;
  full_.eigenvalues().unaryExpr([&](cplx v) { return std::abs(v - target); }).minCoeff(&best);
  return {full_.eigenvalues()(best),
          vector ? Eigen::VectorXcd(full_.eigenvectors().col(best)) : Eigen::VectorXcd()};
}

}  // namespace cutdyn::detail
