// Poles of the least-squares complex-frequency (LSCF) estimator [Guillaume2003; Peeters2004]:
// G(ω) ≈ B(Ω)/A(Ω) with real polynomials in Ω = exp(i·ω·Δt), Δt = π/ω_hi, fitted by the
// linearised weighted error w·(B − G·A), the numerator eliminated through the reduced normal
// equations and the denominator's leading coefficient fixed to 1. docs/models/modal-fitting.md
// §2.
#include <Eigen/Dense>
#include <cmath>
#include <numbers>

#include "frf_fit_internal.hpp"

namespace cutdyn::fit_detail {
namespace {

// Normal-equation blocks of the highest order: R = Re(XᴴX), S = Re(XᴴY), T = Re(YᴴY) with
// X_kj = w_k·Ω_k^j and Y_kj = −w_k·G_k·Ω_k^j [Peeters2004]. A lower order's blocks
// are their leading principal parts (the basis functions nest). Ω_k of eq. FIT-6, w_k the
// band's weights: eq. FIT-9, (4.2) or (4.4) (docs/models/modal-fitting.md).
struct NormalBlocks {
  Eigen::MatrixXd r, s, t;
};

NormalBlocks normal_blocks(const BandData& band, int max_order, double dt) {
  const auto p = static_cast<Eigen::Index>(band.size());
  const Eigen::Index m = max_order + 1;
  Eigen::MatrixXcd x(p, m), y(p, m);
  for (Eigen::Index k = 0; k < p; ++k) {
    const cd step = std::polar(1.0, band.omega[k] * dt);
    cd basis = band.w[k];
    for (Eigen::Index j = 0; j < m; ++j) {
      x(k, j) = basis;
      y(k, j) = -band.g[k] * basis;
      basis *= step;
    }
  }
  // Coefficient-wise products: small results, and no worker threads that a busy machine's
  // other work would slow down (Eigen's blocked product uses OpenMP where it is enabled).
  const auto xh = x.adjoint();
  return {xh.lazyProduct(x).real(), xh.lazyProduct(y).real(), y.adjoint().lazyProduct(y).real()};
}

// Roots of z^n + a[n−1]·z^(n−1) + … + a[0] from the companion matrix.
Eigen::VectorXcd monic_roots(const Eigen::VectorXd& a) {
  const Eigen::Index n = a.size();
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index i = 1; i < n; ++i) c(i, i - 1) = 1.0;
  c.col(n - 1) = -a;
  return Eigen::EigenSolver<Eigen::MatrixXd>(c, false).eigenvalues();
}

}  // namespace

std::vector<std::vector<cd>> lscf_poles(const BandData& band, int max_order) {
  // Δt of eq. FIT-6 (docs/models/modal-fitting.md): the band's top at Ω = −1.
  const double dt = std::numbers::pi / band.hi_rad_s;
  const NormalBlocks nb = normal_blocks(band, max_order, dt);
  std::vector<std::vector<cd>> out(static_cast<std::size_t>(max_order));
  for (int n = 1; n <= max_order; ++n) {
    const Eigen::Index m = n + 1;
    const Eigen::MatrixXd r = nb.r.topLeftCorner(m, m);
    const Eigen::MatrixXd s = nb.s.topLeftCorner(m, m);
    // Reduced normal equations M·a = 0 with a_n = 1 [Peeters2004]: eq. FIT-7
    // (docs/models/modal-fitting.md), M = T − Sᵀ·R⁻¹·S.
    const Eigen::MatrixXd rs = r.ldlt().solve(s);
    const Eigen::MatrixXd mm = nb.t.topLeftCorner(m, m) - s.transpose().lazyProduct(rs);
    const Eigen::VectorXd a = mm.topLeftCorner(n, n).ldlt().solve(-mm.col(n).head(n));
    if (!a.allFinite()) continue;
    const Eigen::VectorXcd z = monic_roots(a);
    for (Eigen::Index i = 0; i < z.size(); ++i) {
      if (std::abs(z(i)) == 0.0) continue;
      const cd lambda = std::log(z(i)) / dt;  // z = exp(λ·Δt)
      const double wn = std::abs(lambda);
      const double zeta = -lambda.real() / wn;
      if (lambda.imag() > 0.0 && zeta > 0.0 && zeta < 0.5 && wn >= band.lo_rad_s &&
          wn <= band.hi_rad_s)
        out[static_cast<std::size_t>(n - 1)].push_back(lambda);
    }
  }
  return out;
}

}  // namespace cutdyn::fit_detail
