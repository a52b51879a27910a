#include "cutdyn/drive/motor_currents.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn {
namespace {

TEST(MotorCurrents, EquivalentCurrentIsTorqueOverTorqueConstant) {
  // For either measure, the equivalent current of the synthesised phases is |Te|/KT, whatever
  // the shaft angle; the phases are balanced (they sum to zero) and their frequency is the
  // electrical one, p·Ω.
  const std::vector<double> t{0.0, 1e-3, 2e-3, 3e-3, 4e-3};
  const std::vector<double> torque{2.0, -1.5, 0.7, 3.0, 0.0}, speed(5, 100.0);
  for (CurrentMeasure measure : {CurrentMeasure::kRms, CurrentMeasure::kSpaceVector}) {
    PmsmMotor m;
    m.pole_pairs = 4;
    m.torque_constant_nm_per_a = 1.621;
    m.measure = measure;
    const PhaseCurrents p = motor_currents(m, t, torque, speed, 0.3);
    for (std::size_t i = 0; i < t.size(); ++i) {
      EXPECT_NEAR(equivalent_current(p.iu_a[i], p.iv_a[i], p.iw_a[i], measure),
                  std::abs(torque[i]) / 1.621, 1e-12);
      EXPECT_NEAR(p.iu_a[i] + p.iv_a[i] + p.iw_a[i], 0.0, 1e-12);
    }
    // Electrical angle at sample 2: 4·(0.3 + 100·2e-3) = 2.0 rad: iu = −Î·sin 2.0.
    const double peak = (measure == CurrentMeasure::kRms ? std::sqrt(2.0) : 1.0) * 0.7 / 1.621;
    EXPECT_NEAR(p.iu_a[2], -peak * std::sin(2.0), 1e-12);
  }
}

TEST(MotorCurrents, NoiseAndOffsetAreWhatWasAsked) {
  PmsmMotor m;
  m.noise_a = 0.05;
  m.offset_a[1] = 0.2;
  const int n = 20000;
  std::vector<double> t(n), torque(n, 0.0), speed(n, 50.0);
  for (int i = 0; i < n; ++i) t[static_cast<std::size_t>(i)] = i * 1e-4;
  const PhaseCurrents p = motor_currents(m, t, torque, speed);
  double mean_v = 0, var_u = 0;
  for (int i = 0; i < n; ++i) {
    mean_v += p.iv_a[static_cast<std::size_t>(i)] / n;
    var_u += p.iu_a[static_cast<std::size_t>(i)] * p.iu_a[static_cast<std::size_t>(i)] / n;
  }
  EXPECT_NEAR(mean_v, 0.2, 4 * 0.05 / std::sqrt(n));  // the offset, to 4 standard errors
  EXPECT_NEAR(std::sqrt(var_u), 0.05, 4 * 0.05 / std::sqrt(2.0 * n));  // σ of the noise
  m.pole_pairs = 0;
  EXPECT_THROW(motor_currents(m, t, torque, speed), InvalidInput);
}

}  // namespace
}  // namespace cutdyn
