// Structural modes of the tool (or workpiece) and their frequency response.
//
// Each mode is a single-degree-of-freedom oscillator acting in one direction with unit
// mode shape: m·q̈ + c·q̇ + k·q = F_dir, and the displacement in that direction is the sum
// of its modes' q. Several modes per direction are allowed.
//
// A mode fitted to a measured receptance may have a complex residue (a non-proportionally
// damped structure, docs/models/modal-fitting.md §10): its pole pair is that of the
// oscillator, its residue A = −i·|A|·e^(iφ) is turned by φ from the real mode's. Its
// receptance is then
//   G(s) = (b0 + b1·s) / (s² + 2ζωn·s + ωn²),   s = iω,
//   b0 = (ωn²/k)·(cos φ + (ζωn/ωd)·sin φ),   b1 = (ωn²/k)·sin φ / ωd,   ωd = ωn·sqrt(1 − ζ²),
// and the displacement it adds is b0/(ωn²/k)·q + b1/(ωn²/k)·q̇ (φ = 0: q).
#pragma once

#include <Eigen/Dense>
#include <complex>
#include <string>
#include <utility>
#include <vector>

namespace cutdyn {

enum class Direction { kX, kY };

const char* to_string(Direction direction);

struct Mode {
  Direction direction = Direction::kX;
  double natural_rad_s = 0.0;      // ωn
  double damping_ratio = 0.0;      // ζ, 0 <= ζ < 1
  double stiffness_n_per_m = 0.0;  // k = ωn²/(2·ωd·|A|)
  /// φ, the residue's phase from a real mode's, |φ| < π/2; 0 for a real (proportionally
  /// damped) mode.
  double residue_phase_rad = 0.0;

  double mass_kg() const { return stiffness_n_per_m / (natural_rad_s * natural_rad_s); }
  double damping_n_s_per_m() const { return 2.0 * damping_ratio * natural_rad_s * mass_kg(); }
};

/// The numerator b0 + b1·s of the mode's receptance (header): {b0 in m/(N·s²), b1 in m/(N·s)}.
/// A real mode has {ωn²/k, 0}.
std::pair<double, double> receptance_numerator(const Mode& mode);

/// Builds a mode from its modal mass instead of its stiffness: k = m·ωn².
Mode mode_from_mass(Direction direction, double natural_rad_s, double damping_ratio,
                    double mass_kg);

struct ModalModel {
  std::vector<Mode> modes;

  /// Problems as "modes[i].field = value unit: rule"; empty when valid.
  std::vector<std::string> validate() const;
  /// Number of modes acting in `direction`.
  int count(Direction direction) const;
  /// Highest natural frequency (rad/s) among all modes; 0 when there are none.
  double max_natural_rad_s() const;
};

/// Direct receptance in `direction` at angular frequency ω (rad/s), in m/N:
/// G(ω) = Σ 1 / (k (1 − r² + 2iζr)), r = ω/ωn, over the modes in that direction (for a mode
/// with a complex residue, the form of the header).
std::complex<double> frf(const ModalModel& model, Direction direction, double omega_rad_s);

/// First-order form of the modes acting in `directions`: ẋ = A x + B f, y = C x, where
/// f holds one force per listed direction (N), y one displacement per listed direction (m),
/// and x = (q1, q̇1, q2, q̇2, ...) over the modes in those directions, in model order; C picks
/// each q (and, for a mode with a complex residue, a share of q̇ as in the header).
struct ModalStateSpace {
  Eigen::MatrixXd A;  // d×d
  Eigen::MatrixXd B;  // d×r
  Eigen::MatrixXd C;  // r×d
};
ModalStateSpace modal_state_space(const ModalModel& model,
                                  const std::vector<Direction>& directions);

}  // namespace cutdyn
