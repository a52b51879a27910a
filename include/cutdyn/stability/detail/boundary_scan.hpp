// Stability boundaries as real positive eigenvalues of a matrix function.
//
// Every frequency-domain and Floquet-boundary method in cutdyn reduces, at one spindle
// speed, to the same question: for which values of a scan variable θ (a chatter frequency,
// or the argument of a Floquet multiplier on the unit circle) does the matrix K(θ) have a
// real positive eigenvalue λ? Each such point is a depth w = 1/λ at which the process is on
// its stability boundary; the smallest is the critical depth. This scans θ on a grid, follows
// each eigenvalue from one grid point to the next (nearest-neighbour matching), detects its
// crossings of the positive real axis, and refines each candidate by Brent's method on the
// imaginary part of the followed eigenvalue. K must be continuous in θ and the step fine
// enough that eigenvalues move little between grid points (each method chooses it).
#pragma once

#include <Eigen/Dense>
#include <complex>
#include <functional>
#include <vector>

#include "cutdyn/stability/critical_depth.hpp"

namespace cutdyn {

struct BoundaryScanOptions {
  double theta_min = 0.0;
  double theta_max = 0.0;
  double theta_step = 0.0;  // grid spacing, > 0 (the largest one when step_at is set)
  /// The largest step the scan may take from θ, where K changes faster in some places than
  /// in others (near a resonance): the grid then follows it, never wider than theta_step.
  /// Empty: equal steps of theta_step.
  std::function<double(double theta)> step_at;
  double min_eigenvalue = 0.0;  // ignore λ below this (depths above 1/min_eigenvalue)
  /// Refine only candidates whose interpolated depth is within this factor of the smallest
  /// refined one (the others cannot be the critical depth). Near a sharp resonance the
  /// eigenvalue moves on a curved path and the straight-line estimate can be off by several
  /// per cent, hence the generous default. Use +inf to refine every crossing.
  double refine_factor = 1.5;
  double theta_tol = 1e-13;  // relative to the bracket size after Brent
  /// Also take real eigenvalues at the end points θ_min and θ_max (where K is real for the
  /// Floquet methods: multipliers +1 and −1).
  bool real_at_ends = false;
  /// Every eigenvalue at every sample by the dense Schur decomposition, instead of those that
  /// can matter by Arnoldi's method and inverse iteration (detail/large_eigenvalues.hpp): the
  /// reference for tests and benchmarks.
  bool dense = false;
};

struct BoundaryPoint {
  double theta = 0.0;
  double depth = 0.0;               // 1/λ
  std::complex<double> eigenvalue;  // λ at the refined θ (imaginary part ~ 0)
  Eigen::VectorXcd eigenvector;     // of K(θ) for λ
};

struct BoundaryScanReport {
  std::vector<BoundaryPoint> points;  // refined crossings, by increasing depth
  long long evaluations = 0;          // number of K evaluations
  /// Candidates that could have been the smallest depth but whose crossing Brent's method
  /// could not pin down (the followed eigenvalue did not change sign on the bracket); the
  /// result may then be too deep. Zero in every case the tests know.
  int unresolved = 0;
};

/// `evaluate(θ, K)` fills K (it may reuse K's storage). Returning false means "no
/// eigenvalue of K(θ) can reach min_eigenvalue" (a cheap bound said so); the scan then
/// skips the eigenvalue problem at that θ.
using MatrixFunction = std::function<bool(double theta, Eigen::MatrixXcd& k)>;

BoundaryScanReport scan_boundary(const MatrixFunction& evaluate,
                                 const BoundaryScanOptions& options);

/// The critical depth a scan found: its smallest boundary point, or the search limit
/// `depth_max_m` with found = false; work and unresolved counts carried over. The chatter
/// frequency is left to the method, which knows what θ stands for.
CriticalDepth critical_depth_from_scan(const BoundaryScanReport& report, double depth_max_m);

}  // namespace cutdyn
