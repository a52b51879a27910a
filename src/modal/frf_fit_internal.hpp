// Internals of the modal fit (include/cutdyn/modal/frf_fit.hpp), shared by its source files:
// the band's data, the pole-residue model, the LSCF pole estimates [Guillaume2003;
// Peeters2004] and the Levenberg–Marquardt refinement [Marquardt1963].
#pragma once

#include <Eigen/Dense>

#include <complex>
#include <vector>

namespace cutdyn::fit_detail {

using cd = std::complex<double>;

/// The table's points inside the band, with the relative weights of the error.
struct BandData {
  std::vector<double> omega;  // rad/s
  std::vector<cd> g;          // measured receptance, m/N
  std::vector<double> w;      // the fit's weights, N/m: w_rel, or those of the noise (§4)
  std::vector<double> w_rel;  // 1/max(|g|, g0, 1e-6·max|g|), g0 the noise floor (0: none)
  /// sqrt((1 − γ²)/γ²) of each point where the table has a coherence (§4.3), else empty.
  std::vector<double> coherence_noise;
  double lo_rad_s = 0.0, hi_rad_s = 0.0;
  std::size_t size() const { return omega.size(); }
};

/// A residual term: a real coefficient times a basis function of ω.
enum class ResidualKind {
  kLower,         // −1/ω²
  kLowerDamping,  // i/ω³
  kUpper,         // 1
  kUpperDamping,  // iω
  kUpperMass,     // −ω²
};
struct ResidualTerm {
  ResidualKind kind;
  double value = 0.0;
};
cd residual_basis(ResidualKind kind, double omega);

/// G(ω) = Σ A/(s − λ) + A*/(s − λ*) + Σ residual terms, s = iω (one entry per pole with
/// Im λ > 0).
struct PoleResidueModel {
  std::vector<cd> poles;     // rad/s
  std::vector<cd> residues;  // m/(N·s)
  std::vector<ResidualTerm> residuals;
};

/// The pair of terms of pole r at ω.
cd mode_term(cd pole, cd residue, double omega);
/// The whole model at ω; `with_residuals` false leaves out −L/ω² and U.
cd evaluate(const PoleResidueModel& model, double omega, bool with_residuals = true);
/// sqrt(mean over the band of w_rel²·|G_model − G|²).
double rms_relative_error(const BandData& band, const PoleResidueModel& model);
/// sqrt(mean over the band of w²·|G_model − G|²): what the refinement minimises.
double rms_fit_error(const BandData& band, const PoleResidueModel& model);

/// The physical poles (Im λ > 0, 0 < ζ < 0.5, ωn inside the band) of the LSCF estimate of
/// each order 1…max_order; entry [n − 1] holds order n.
std::vector<std::vector<cd>> lscf_poles(const BandData& band, int max_order);

/// Residues and residual terms of least weighted error for fixed poles (linear least squares).
void fit_residues(const BandData& band, PoleResidueModel& model);

/// The covariance of pack()'s parameters at `model` (σ, ωd, Re A, Im A per pole, then the
/// residual terms): c²·(JᵀJ)⁻¹, J the weighted residual's Jacobian and c² = cost/(2N − p)
/// (docs/models/modal-fitting.md §4.2).
Eigen::MatrixXd parameter_covariance(const BandData& band, const PoleResidueModel& model);

struct RefineStats {
  int iterations = 0;
  bool converged = false;
};
/// Levenberg–Marquardt over every pole, residue and residual term, from `model`.
RefineStats refine(const BandData& band, PoleResidueModel& model, int max_iterations = 200);

}  // namespace cutdyn::fit_detail
