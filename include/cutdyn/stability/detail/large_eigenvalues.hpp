// The eigenvalues of a dense complex matrix that a boundary scan needs: every one of at least
// a given modulus, and the one nearest a target.
//
// The matrices of the frequency-domain methods (K(ω) = G·H·D of the multi-frequency method,
// docs/models/milling-stability.md) have a few large eigenvalues and a long tail that decays
// with the structure's response and the spectrum of the contact pulse; only the large ones can
// be boundaries below the depth limit. Arnoldi's method finds the outer part of a spectrum
// first: a basis of a few tens of vectors holds every eigenvalue above the threshold, at a
// small fraction of the dense Schur decomposition's cost (O(m·N²) against O(N³)). The one
// eigenvalue nearest a target (the eigenvalue a scan follows) is found by inverse iteration:
// one LU factorisation and a few solves. Both fall back to the dense solver where they cannot
// vouch for their answer.
#pragma once

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <complex>
#include <utility>

namespace cutdyn::detail {

class LargeEigenvalues {
 public:
  /// `dense`: always the dense Schur decomposition (all eigenvalues; the reference that tests
  /// and benchmarks compare with).
  explicit LargeEigenvalues(bool dense = false) : always_dense_(dense) {}

  /// Every eigenvalue of K (square) with |λ| >= threshold, possibly with some smaller ones, in
  /// no particular order; with unit eigenvectors (columns) if `vectors`. Arnoldi's method on a
  /// basis grown from a fixed start vector until every Ritz value above the threshold has a
  /// residual below 1e-10 of its modulus and two below the threshold have converged too; the
  /// dense solver when K is small (N <= 32) or the basis would need more than N/2 vectors.
  void compute(const Eigen::MatrixXcd& K, double threshold, bool vectors);
  const Eigen::VectorXcd& eigenvalues() const { return values_; }
  const Eigen::MatrixXcd& eigenvectors() const { return vectors_; }
  /// Whether the last compute() took the dense solver.
  bool dense() const { return dense_; }

  /// The eigenvalue of K nearest `target` and (if `vector`) its unit eigenvector, by inverse
  /// iteration with the shift `target` until the residual is below 1e-12 of the eigenvalue;
  /// the dense solver where it does not converge (two eigenvalues almost as near).
  std::pair<std::complex<double>, Eigen::VectorXcd> nearest(const Eigen::MatrixXcd& K,
                                                            std::complex<double> target,
                                                            bool vector);

 private:
  void compute_dense(const Eigen::MatrixXcd& K, bool vectors);
  std::pair<std::complex<double>, Eigen::VectorXcd> nearest_dense(const Eigen::MatrixXcd& K,
                                                                  std::complex<double> target,
                                                                  bool vector);

  Eigen::VectorXcd values_;
  Eigen::MatrixXcd vectors_;
  bool always_dense_ = false;
  bool dense_ = false;
  Eigen::Index last_basis_ = 0;                  // the basis the last Arnoldi solution needed
  Eigen::MatrixXcd basis_;                       // Arnoldi vectors V (N × (m + 1))
  Eigen::MatrixXcd hessenberg_;                  // H ((m + 1) × m), K·V_m = V_(m+1)·H
  Eigen::ComplexSchur<Eigen::MatrixXcd> schur_;  // of H
  Eigen::MatrixXcd ritz_;                        // eigenvectors of its triangular factor
  Eigen::ComplexEigenSolver<Eigen::MatrixXcd> full_;
  Eigen::PartialPivLU<Eigen::MatrixXcd> lu_;
};

}  // namespace cutdyn::detail
