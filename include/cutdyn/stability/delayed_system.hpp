// The neutral description every stability method and the time-domain integrators take:
// a linear delayed system with periodic coefficients, in the regenerative form
//
//     ẋ(t) = A0·x(t) + w·E·H(t)·C·( x(t − τ) − x(t) ),      H(t + T) = H(t),
//
// i.e. ẋ = A(t)x + B(t)x(t − τ) with A(t) = A0 − w·E·H(t)·C and B(t) = w·E·H(t)·C.
// x (d states) is the structure's state, y = C·x (r displacements) the displacements the
// chip thickness sees, E (d×r) maps forces to state derivatives, H(t) (r×r, N/m² per unit
// width) is the periodic cutting-coefficient matrix, w the width of cut (depth, m) and τ the
// regenerative delay. The structure and the force model build it (turning.hpp, and the
// milling models); the methods never need to know which process it came from.
#pragma once

#include <Eigen/Dense>
#include <complex>
#include <functional>
#include <string>
#include <vector>

namespace cutdyn {

/// H(t), periodic with period T, described by what the methods need of it.
struct PeriodicCoefficient {
  int dim = 1;            // r
  double period_s = 0;    // T; ignored when `constant`
  bool constant = false;  // H(t) = H0 for all t: any period may be used
  /// Instants in [0, T) where H jumps (contact windows); time grids put nodes on them.
  std::vector<double> breakpoints_s;
  /// Mean of H over [t0, t1], 0 <= t0 < t1 <= T (r×r).
  std::function<Eigen::MatrixXd(double t0, double t1)> mean;
  /// Fourier coefficient H_p = (1/T)∫0^T H(t)·exp(−i·p·2πt/T) dt (r×r).
  std::function<Eigen::MatrixXcd(int p)> fourier;
};

/// A constant coefficient H(t) = H0.
PeriodicCoefficient constant_coefficient(const Eigen::MatrixXd& h0);

/// H(t) = H0·g(t) with g the contact window that is 1 on [start, start + r·T) modulo T and
/// 0 elsewhere (vibration-assisted cutting). Means and Fourier coefficients are exact.
PeriodicCoefficient windowed_coefficient(const Eigen::MatrixXd& h0, double period_s,
                                         double duty_cycle, double start_s);

/// A further regenerative term w·E·H_k(t)·C·(x(t − τ_k) − x(t)), with H_k of the same period
/// as the system's H: a milling cutter with uneven tooth pitch has one per tooth.
struct DelayTerm {
  PeriodicCoefficient H;
  double delay_s = 0;
};

struct DelayedSystem {
  Eigen::MatrixXd A0;  // d×d, the structure alone (asymptotically stable)
  Eigen::MatrixXd E;   // d×r
  Eigen::MatrixXd C;   // r×d
  PeriodicCoefficient H;
  double delay_s = 0;  // τ
  /// Further delays, added to the term above (usually empty). The full discretization by
  /// spectral radius and the multi-frequency method take them; the others reject them.
  std::vector<DelayTerm> more_delays;

  int states() const { return static_cast<int>(A0.rows()); }
  int outputs() const { return static_cast<int>(C.rows()); }
  /// The regenerative terms, the first being (H, delay_s).
  std::vector<DelayTerm> delay_terms() const;
  /// Problems as "field = value: rule"; empty when valid.
  std::vector<std::string> validate() const;
  /// A measured structure's receptance at ω, written into g (resized to r×r): when set, the
  /// frequency-domain methods take it instead of the state space's, which then holds modes
  /// fitted to it (for the time-domain methods, and for the frequency grids). Written in place
  /// because a scan asks for it hundreds of times per speed.
  std::function<void(double omega_rad_s, Eigen::MatrixXcd& g)> measured_response;

  /// Frequency response of the structure alone: measured_response when set, else
  /// C·(iωI − A0)⁻¹·E (r×r).
  Eigen::MatrixXcd frequency_response(double omega_rad_s) const;
  /// The same, written into g (its storage reused).
  void frequency_response(double omega_rad_s, Eigen::MatrixXcd& g) const;
};

}  // namespace cutdyn
