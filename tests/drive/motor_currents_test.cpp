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
    // The electrical angle is given with the currents, wrapped into [0, 2π): sample 4 is
    // 4·(0.3 + 100·4e-3) = 2.8 rad, and each phase is −Î·sin(θe − k·2π/3).
    EXPECT_NEAR(p.rotor_angle_rad[2], 2.0, 1e-12);
    EXPECT_NEAR(p.rotor_angle_rad[4], 2.8, 1e-12);
    for (std::size_t i = 0; i < t.size(); ++i) {
      const double pk =
          (measure == CurrentMeasure::kRms ? std::sqrt(2.0) : 1.0) * torque[i] / 1.621;
      EXPECT_NEAR(p.iv_a[i], -pk * std::sin(p.rotor_angle_rad[i] - 2 * units::kPi / 3), 1e-12);
    }
  }
  // A long run wraps: 4 pole pairs at 100 rad/s for 1 s is 400 rad = 63.66 turns.
  PmsmMotor m;
  const std::vector<double> tt{0.0, 1.0}, tq{1.0, 1.0}, sp{100.0, 100.0};
  const PhaseCurrents p = motor_currents(m, tt, tq, sp);
  EXPECT_NEAR(p.rotor_angle_rad[1], 400.0 - 63 * units::kTwoPi, 1e-9);
}

namespace {
// Pearson correlation of two equally long series.
double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  const double n = static_cast<double>(a.size());
  double ma = 0, mb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ma += a[i] / n;
    mb += b[i] / n;
  }
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}
}  // namespace

TEST(MotorCurrents, NoiseStreamsAreIndependentPerAxisAndReproducibleBySeed) {
  // Zero torque: the phases are the noise alone. n = 20000 samples: the correlation of two
  // independent streams has a standard error 1/√n = 0.0071; 4 of them is 0.028.
  const int n = 20000;
  std::vector<double> t(n), torque(n, 0.0), speed(n, 50.0);
  for (int i = 0; i < n; ++i) t[static_cast<std::size_t>(i)] = i * 1e-4;
  PmsmMotor x;
  x.noise_a = 0.05;
  x.seed = 7;
  PmsmMotor y = x;
  y.stream = 1;  // the second axis of the same run
  const PhaseCurrents px = motor_currents(x, t, torque, speed);
  const PhaseCurrents py = motor_currents(y, t, torque, speed);
  const double bound = 4.0 / std::sqrt(static_cast<double>(n));
  EXPECT_LT(std::abs(correlation(px.iu_a, py.iu_a)), bound);
  EXPECT_LT(std::abs(correlation(px.iv_a, py.iw_a)), bound);
  // The same axis one sample later (the old fixed seed reused the same sequence on every axis:
  // any shift of it would correlate fully).
  std::vector<double> xs(px.iu_a.begin() + 1, px.iu_a.end()), ys(py.iu_a.begin(), py.iu_a.end() - 1);
  EXPECT_LT(std::abs(correlation(xs, ys)), bound);
  // The same seed and stream reproduce the run exactly; another seed gives another,
  // uncorrelated run.
  const PhaseCurrents again = motor_currents(x, t, torque, speed);
  EXPECT_EQ(again.iu_a, px.iu_a);
  EXPECT_EQ(again.iw_a, px.iw_a);
  PmsmMotor other = x;
  other.seed = 8;
  const PhaseCurrents po = motor_currents(other, t, torque, speed);
  EXPECT_NE(po.iu_a, px.iu_a);
  EXPECT_LT(std::abs(correlation(po.iu_a, px.iu_a)), bound);
  // Seed 8 stream 0 is not seed 7 stream 1 either (the pair is mixed, not added).
  EXPECT_LT(std::abs(correlation(po.iu_a, py.iu_a)), bound);
  EXPECT_NE(po.iu_a, py.iu_a);
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
