// Structural modes of the tool (or workpiece) and their frequency response.
//
// Each mode is a single-degree-of-freedom oscillator acting in one direction with unit
// mode shape: m·q̈ + c·q̇ + k·q = F_dir, and the displacement in that direction is the sum
// of its modes' q. Several modes per direction are allowed.
#pragma once

#include <Eigen/Dense>
#include <complex>
#include <string>
#include <vector>

namespace cutdyn {

enum class Direction { kX, kY };

const char* to_string(Direction direction);

struct Mode {
  Direction direction = Direction::kX;
  double natural_rad_s = 0.0;      // ωn
  double damping_ratio = 0.0;      // ζ, 0 <= ζ < 1
  double stiffness_n_per_m = 0.0;  // k

  double mass_kg() const { return stiffness_n_per_m / (natural_rad_s * natural_rad_s); }
  double damping_n_s_per_m() const { return 2.0 * damping_ratio * natural_rad_s * mass_kg(); }
};

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
/// G(ω) = Σ 1 / (k (1 − r² + 2iζr)), r = ω/ωn, over the modes in that direction.
std::complex<double> frf(const ModalModel& model, Direction direction, double omega_rad_s);

/// First-order form of the modes acting in `directions`: ẋ = A x + B f, y = C x, where
/// f holds one force per listed direction (N), y one displacement per listed direction (m),
/// and x = (q1, q̇1, q2, q̇2, ...) over the modes in those directions, in model order.
struct ModalStateSpace {
  Eigen::MatrixXd A;  // d×d
  Eigen::MatrixXd B;  // d×r
  Eigen::MatrixXd C;  // r×d
};
ModalStateSpace modal_state_space(const ModalModel& model,
                                  const std::vector<Direction>& directions);

}  // namespace cutdyn
