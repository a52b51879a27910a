// The pole-residue model with residual terms [Ewins2000, ch. 2 and 4], its residues for fixed
// poles (linear least squares) and the Levenberg–Marquardt refinement of all its parameters
// [Marquardt1963] on the relatively weighted complex error. docs/models/modal-fitting.md §4.
#include <Eigen/Dense>
#include <cmath>

#include "frf_fit_internal.hpp"

namespace cutdyn::fit_detail {

// One pair of terms of eq. FIT-1 (docs/models/modal-fitting.md).
cd mode_term(cd pole, cd residue, double omega) {
  const cd s{0.0, omega};
  return residue / (s - pole) + std::conj(residue) / (s - std::conj(pole));
}

// Eq. FIT-1 (docs/models/modal-fitting.md); without its residual terms when asked.
cd evaluate(const PoleResidueModel& model, double omega, bool with_residuals) {
  cd g{0.0, 0.0};
  for (std::size_t r = 0; r < model.poles.size(); ++r)
    g += mode_term(model.poles[r], model.residues[r], omega);
  if (with_residuals)
    for (const ResidualTerm& t : model.residuals) g += t.value * residual_basis(t.kind, omega);
  return g;
}

// The basis functions of lower(ω) and upper(ω), eqs. FIT-3 and FIT-4
// (docs/models/modal-fitting.md).
cd residual_basis(ResidualKind kind, double omega) {
  switch (kind) {
    case ResidualKind::kLower:
      return -1.0 / (omega * omega);
    case ResidualKind::kLowerDamping:
      return cd(0.0, 1.0 / (omega * omega * omega));
    case ResidualKind::kUpper:
      return 1.0;
    case ResidualKind::kUpperDamping:
      return cd(0.0, omega);
    case ResidualKind::kUpperMass:
      return -omega * omega;
  }
  return 0.0;
}

namespace {

double weighted_rms(const BandData& band, const PoleResidueModel& model,
                    const std::vector<double>& w) {
  double sum = 0.0;
  for (std::size_t k = 0; k < band.size(); ++k)
    sum += std::norm(w[k] * (evaluate(model, band.omega[k]) - band.g[k]));
  return std::sqrt(sum / static_cast<double>(band.size()));
}

}  // namespace

double rms_relative_error(const BandData& band, const PoleResidueModel& model) {
  return weighted_rms(band, model, band.w_rel);
}

double rms_fit_error(const BandData& band, const PoleResidueModel& model) {
  return weighted_rms(band, model, band.w);
}

namespace {

int parameter_count(const PoleResidueModel& m) {
  return static_cast<int>(4 * m.poles.size() + m.residuals.size());
}

// Parameters (σ, ωd, Re A, Im A) per pole, λ = −σ + i·ωd (eq. FIT-2 with σ = ζ·ωn,
// docs/models/modal-fitting.md), then L and U when used.
Eigen::VectorXd pack(const PoleResidueModel& m) {
  Eigen::VectorXd p(parameter_count(m));
  Eigen::Index i = 0;
  for (std::size_t r = 0; r < m.poles.size(); ++r) {
    p.segment<4>(i) << -m.poles[r].real(), m.poles[r].imag(), m.residues[r].real(),
        m.residues[r].imag();
    i += 4;
  }
  for (const ResidualTerm& t : m.residuals) p(i++) = t.value;
  return p;
}

void unpack(const Eigen::VectorXd& p, PoleResidueModel& m) {
  Eigen::Index i = 0;
  for (std::size_t r = 0; r < m.poles.size(); ++r) {
    m.poles[r] = cd(-p(i), p(i + 1));
    m.residues[r] = cd(p(i + 2), p(i + 3));
    i += 4;
  }
  for (ResidualTerm& t : m.residuals) t.value = p(i++);
}

// Weighted residual (Re and Im of w·(G_model − G) at every point) and, when `jac` is given,
// its Jacobian with respect to pack()'s parameters: its squared norm is the cost of eq. FIT-9
// (docs/models/modal-fitting.md; the weights (4.2) or (4.4) after a reweighting), the
// derivatives those listed after it in §4.
Eigen::VectorXd residual(const BandData& band, const PoleResidueModel& m, Eigen::MatrixXd* jac) {
  const auto p = static_cast<Eigen::Index>(band.size());
  Eigen::VectorXd e(2 * p);
  if (jac) jac->resize(2 * p, parameter_count(m));
  for (Eigen::Index k = 0; k < p; ++k) {
    const double om = band.omega[k], w = band.w[k];
    const cd ek = w * (evaluate(m, om) - band.g[k]);
    e(k) = ek.real();
    e(p + k) = ek.imag();
    if (!jac) continue;
    const cd s{0.0, om}, i1{0.0, 1.0};
    const auto put = [&](Eigen::Index col, cd d) {
      (*jac)(k, col) = w * d.real();
      (*jac)(p + k, col) = w * d.imag();
    };
    Eigen::Index col = 0;
    for (std::size_t r = 0; r < m.poles.size(); ++r) {
      const cd q = 1.0 / (s - m.poles[r]), qc = 1.0 / (s - std::conj(m.poles[r]));
      const cd a = m.residues[r], ac = std::conj(a);
      put(col++, -(a * q * q + ac * qc * qc));      // ∂/∂σ
      put(col++, i1 * (a * q * q - ac * qc * qc));  // ∂/∂ωd
      put(col++, q + qc);                           // ∂/∂Re A
      put(col++, i1 * (q - qc));                    // ∂/∂Im A
    }
    for (const ResidualTerm& t : m.residuals) put(col++, residual_basis(t.kind, om));
  }
  return e;
}

// Column norms of `j`, 1 where a column is zero: the scaling that makes the normal equations
// of a Levenberg–Marquardt step independent of the parameters' units.
Eigen::VectorXd column_scale(const Eigen::MatrixXd& j) {
  Eigen::VectorXd d = j.colwise().norm().transpose();
  for (Eigen::Index i = 0; i < d.size(); ++i)
    if (!(d(i) > 0.0) || !std::isfinite(d(i))) d(i) = 1.0;
  return d;
}

bool physical(const PoleResidueModel& m) {
  for (const cd& pole : m.poles)
    if (!(pole.real() < 0.0 && pole.imag() > 0.0)) return false;
  return true;
}

}  // namespace

void fit_residues(const BandData& band, PoleResidueModel& model) {
  model.residues.assign(model.poles.size(), cd{0.0, 0.0});
  for (ResidualTerm& t : model.residuals) t.value = 0.0;
  Eigen::MatrixXd jac;
  const Eigen::VectorXd e0 = residual(band, model, &jac);  // the model is linear in these
  // Keep the residue and residual-term columns (every fourth pair after the pole's two).
  const int n = parameter_count(model);
  std::vector<Eigen::Index> cols;
  for (int c = 0; c < n; ++c)
    if (c >= 4 * static_cast<int>(model.poles.size()) || c % 4 >= 2) cols.push_back(c);
  Eigen::MatrixXd a(jac.rows(), static_cast<Eigen::Index>(cols.size()));
  for (std::size_t c = 0; c < cols.size(); ++c) a.col(c) = jac.col(cols[c]);
  const Eigen::VectorXd d = column_scale(a);
  const Eigen::VectorXd x =
      (a * d.cwiseInverse().asDiagonal()).colPivHouseholderQr().solve(-e0).cwiseQuotient(d);
  Eigen::VectorXd p = pack(model);
  for (std::size_t c = 0; c < cols.size(); ++c) p(cols[c]) = x(c);
  if (p.allFinite()) unpack(p, model);
}

Eigen::MatrixXd parameter_covariance(const BandData& band, const PoleResidueModel& model) {
  Eigen::MatrixXd jac;
  const Eigen::VectorXd e = residual(band, model, &jac);
  const auto p = jac.cols();
  const double dof = static_cast<double>(jac.rows() - p);
  const double c2 = dof > 0.0 ? e.squaredNorm() / dof : 0.0;
  // Scaled to unit columns for the conditioning, (JᵀJ)⁻¹ = D⁻¹·(JsᵀJs)⁻¹·D⁻¹.
  const Eigen::VectorXd d = column_scale(jac);
  const Eigen::MatrixXd js = jac * d.cwiseInverse().asDiagonal();
  const Eigen::MatrixXd h = js.transpose().lazyProduct(js);
  const Eigen::MatrixXd inv =
      h.completeOrthogonalDecomposition().pseudoInverse();  // singular: the null space is 0
  return c2 * d.cwiseInverse().asDiagonal() * inv * d.cwiseInverse().asDiagonal();
}

RefineStats refine(const BandData& band, PoleResidueModel& model, int max_iterations) {
  RefineStats stats;
  Eigen::VectorXd p = pack(model);
  Eigen::MatrixXd jac;
  Eigen::VectorXd e = residual(band, model, &jac);
  double cost = e.squaredNorm();
  double mu = 1e-3;
  while (stats.iterations < max_iterations) {
    ++stats.iterations;
    const Eigen::VectorXd d = column_scale(jac);
    const Eigen::MatrixXd js = jac * d.cwiseInverse().asDiagonal();
    const Eigen::MatrixXd h = js.transpose().lazyProduct(js);  // no OpenMP threads (lscf)
    const Eigen::VectorXd grad = js.transpose() * e;
    bool accepted = false;
    while (!accepted && mu < 1e12) {
      Eigen::MatrixXd hm = h;
      hm.diagonal().array() += mu;
      const Eigen::VectorXd step = hm.ldlt().solve(-grad).cwiseQuotient(d);
      PoleResidueModel trial = model;
      unpack(p + step, trial);
      const Eigen::VectorXd et = residual(band, trial, nullptr);
      const double ct = et.squaredNorm();
      if (step.allFinite() && physical(trial) && std::isfinite(ct) && ct < cost) {
        accepted = true;
        const bool small = cost - ct <= 1e-12 * cost ||
                           step.cwiseProduct(d).norm() <= 1e-12 * p.cwiseProduct(d).norm();
        p += step;
        model = trial;
        e = residual(band, model, &jac);
        cost = ct;
        mu = std::max(mu / 3.0, 1e-15);
        if (small) {
          stats.converged = true;
          return stats;
        }
      } else {
        mu *= 4.0;
      }
    }
    // No step lowers the cost: a minimum to working precision.
    if (!accepted) {
      stats.converged = true;
      return stats;
    }
  }
  return stats;
}

}  // namespace cutdyn::fit_detail
