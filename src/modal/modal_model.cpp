#include "cutdyn/modal/modal_model.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "cutdyn/core/error.hpp"

namespace cutdyn {

const char* to_string(Direction direction) { return direction == Direction::kX ? "x" : "y"; }

std::pair<double, double> receptance_numerator(const Mode& m) {
  const double wn = m.natural_rad_s, phi = m.residue_phase_rad;
  const double gain = wn / m.stiffness_n_per_m * wn;  // ωn²/k
  if (phi == 0.0) return {gain, 0.0};
  const double wd = wn * std::sqrt(1.0 - m.damping_ratio * m.damping_ratio);
  // [modal_model.hpp]: b0 = (ωn²/k)·(cos φ + (ζωn/ωd)·sin φ), b1 = (ωn²/k)·sin φ/ωd; eq. (10.2)
  // of docs/models/modal-fitting.md.
  return {gain * (std::cos(phi) + m.damping_ratio * wn / wd * std::sin(phi)),
          gain * std::sin(phi) / wd};
}

Mode mode_from_mass(Direction direction, double natural_rad_s, double damping_ratio,
                    double mass_kg) {
  return Mode{direction, natural_rad_s, damping_ratio, mass_kg * natural_rad_s * natural_rad_s};
}

std::vector<std::string> ModalModel::validate() const {
  Validator v;
  if (modes.empty()) v.add("modes: at least one mode is required");
  for (std::size_t i = 0; i < modes.size(); ++i) {
    const std::string at = "modes[" + std::to_string(i) + "].";
    const Mode& m = modes[i];
    v.require_positive(at + "natural_rad_s", m.natural_rad_s, "rad/s");
    v.require(m.damping_ratio >= 0.0 && m.damping_ratio < 1.0, at + "damping_ratio",
              m.damping_ratio, "", "must be at least 0 and less than 1");
    v.require_positive(at + "stiffness_n_per_m", m.stiffness_n_per_m, "N/m");
    v.require(std::abs(m.residue_phase_rad) < std::numbers::pi / 2, at + "residue_phase_rad",
              m.residue_phase_rad, "rad",
              "must lie between -pi/2 and pi/2 (beyond, the mode has a negative stiffness)");
  }
  return v.problems();
}

int ModalModel::count(Direction direction) const {
  return static_cast<int>(std::count_if(modes.begin(), modes.end(),
                                        [&](const Mode& m) { return m.direction == direction; }));
}

double ModalModel::max_natural_rad_s() const {
  double w = 0.0;
  for (const Mode& m : modes) w = std::max(w, m.natural_rad_s);
  return w;
}

std::complex<double> frf(const ModalModel& model, Direction direction, double omega_rad_s) {
  std::complex<double> g{0.0, 0.0};
  for (const Mode& m : model.modes) {
    if (m.direction != direction) continue;
    const double r = omega_rad_s / m.natural_rad_s;
    if (m.residue_phase_rad == 0.0) {
      g += 1.0 / (m.stiffness_n_per_m * std::complex<double>(1.0 - r * r, 2.0 * m.damping_ratio * r));
      continue;
    }
    // A complex residue: eq. (10.2) of docs/models/modal-fitting.md at s = iω.
    const auto [b0, b1] = receptance_numerator(m);
    const double wn = m.natural_rad_s;
    g += std::complex<double>(b0, b1 * omega_rad_s) /
         std::complex<double>(wn * wn - omega_rad_s * omega_rad_s,
                              2.0 * m.damping_ratio * wn * omega_rad_s);
  }
  return g;
}

ModalStateSpace modal_state_space(const ModalModel& model,
                                  const std::vector<Direction>& directions) {
  std::vector<std::pair<const Mode*, int>> used;  // mode, output index
  for (const Mode& m : model.modes) {
    for (std::size_t j = 0; j < directions.size(); ++j) {
      if (m.direction == directions[j]) used.emplace_back(&m, static_cast<int>(j));
    }
  }
  const auto d = static_cast<Eigen::Index>(2 * used.size());
  const auto r = static_cast<Eigen::Index>(directions.size());
  ModalStateSpace ss{Eigen::MatrixXd::Zero(d, d), Eigen::MatrixXd::Zero(d, r),
                     Eigen::MatrixXd::Zero(r, d)};
  for (std::size_t i = 0; i < used.size(); ++i) {
    const Mode& m = *used[i].first;
    const auto row = static_cast<Eigen::Index>(2 * i);
    const double wn = m.natural_rad_s;
    ss.A(row, row + 1) = 1.0;
    ss.A(row + 1, row) = -wn * wn;
    ss.A(row + 1, row + 1) = -2.0 * m.damping_ratio * wn;
    ss.B(row + 1, used[i].second) = 1.0 / m.mass_kg();
    // y = (b0·q + b1·q̇)·m with q̈ + 2ζωn·q̇ + ωn²·q = f/m (modal_model.hpp): C = (1, 0) for a
    // real mode. Its transfer function is eq. (10.2) of docs/models/modal-fitting.md.
    const auto [b0, b1] = receptance_numerator(m);
    ss.C(used[i].second, row) = m.residue_phase_rad == 0.0 ? 1.0 : b0 * m.mass_kg();
    ss.C(used[i].second, row + 1) = b1 * m.mass_kg();
  }
  return ss;
}

}  // namespace cutdyn
