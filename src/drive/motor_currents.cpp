#include "cutdyn/drive/motor_currents.hpp"

#include <cmath>
#include <random>
#include <string>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn {

std::vector<std::string> PmsmMotor::validate() const {
  Validator v;
  v.require(pole_pairs >= 1 && pole_pairs <= 100, "pole_pairs", pole_pairs, "", "must be 1 to 100");
  v.require_positive("torque_constant_nm_per_a", torque_constant_nm_per_a, "N·m/A");
  v.require(noise_a >= 0.0, "noise_a", noise_a, "A", "must not be negative");
  for (int k = 0; k < 3; ++k)
    v.require(std::isfinite(offset_a[k]), "offset_a", offset_a[k], "A", "must be finite");
  return v.problems();
}

PhaseCurrents motor_currents(const PmsmMotor& m, const std::vector<double>& t,
                             const std::vector<double>& torque, const std::vector<double>& speed,
                             double initial_angle) {
  Validator v;
  v.merge(m.validate());
  v.require(torque.size() == t.size() && speed.size() == t.size(), "traces",
            static_cast<double>(t.size()), "samples", "torque and speed need one value per time");
  v.throw_if_any("motor currents");
  const double peak_per_amp =
      m.measure == CurrentMeasure::kRms ? std::sqrt(2.0) : 1.0;  // Î per equivalent ampere
  // The stream of (seed, stream): seed_seq mixes the words, so neighbouring seeds and streams
  // give unrelated generator states.
  std::seed_seq sequence{m.seed, m.stream, 0x6d6f746fu /* "moto" */};
  std::mt19937_64 rng(sequence);
  std::normal_distribution<double> noise(0.0, 1.0);
  PhaseCurrents out;
  double angle = initial_angle;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (i > 0) angle += 0.5 * (speed[i] + speed[i - 1]) * (t[i] - t[i - 1]);
    const double theta = m.pole_pairs * angle;
    const double peak = peak_per_amp * torque[i] / m.torque_constant_nm_per_a;
    const double third = units::kTwoPi / 3.0;
    const double phase[3] = {-peak * std::sin(theta), -peak * std::sin(theta - third),
                             -peak * std::sin(theta + third)};
    double measured[3];
    for (int k = 0; k < 3; ++k)
      measured[k] = phase[k] + m.offset_a[k] + (m.noise_a > 0.0 ? m.noise_a * noise(rng) : 0.0);
    out.time_s.push_back(t[i]);
    out.iu_a.push_back(measured[0]);
    out.iv_a.push_back(measured[1]);
    out.iw_a.push_back(measured[2]);
    out.speed_rad_s.push_back(speed[i]);
    double wrapped = std::fmod(theta, units::kTwoPi);
    if (wrapped < 0.0) wrapped += units::kTwoPi;
    if (wrapped >= units::kTwoPi) wrapped = 0.0;
    out.rotor_angle_rad.push_back(wrapped);
  }
  return out;
}

}  // namespace cutdyn
