#include "cutdyn/forces/duty_cycle.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn {
namespace {

// Second method: follow p(t) = v t + A sin(2πft) on a fine grid over many periods and count
// the time the tool spends at a new maximum of p (cutting).
double duty_cycle_by_kinematics(double v, double f, double A) {
  const double T = 1.0 / f;
  const int per_period = 200000;
  const double dt = T / per_period;
  double p_max = -1e300;
  long long cutting = 0, total = 0;
  for (long long k = 0; k < 6LL * per_period; ++k) {
    const double t = static_cast<double>(k) * dt;
    const double p = v * t + A * std::sin(units::kTwoPi * f * t);
    const bool cut = p >= p_max;
    p_max = std::max(p_max, p);
    if (k >= 2LL * per_period) {  // steady state
      cutting += cut ? 1 : 0;
      ++total;
    }
  }
  return static_cast<double>(cutting) / static_cast<double>(total);
}

TEST(DutyCycle, SourceTable1Value) {
  // [Chikishev2018, table 1]: v = 60 m/min, f = 20 kHz, A = 20 µm → r = 0.4095.
  const DutyCycle d = duty_cycle(units::m_per_min_to_m_per_s(60.0), 20000.0, 20e-6);
  EXPECT_NEAR(d.ratio, 0.4095, 0.0005);
  EXPECT_TRUE(d.separates);
  EXPECT_NEAR(d.period_s, 50e-6, 1e-15);
  EXPECT_NEAR(d.critical_speed_m_per_s, units::kTwoPi * 20000.0 * 20e-6, 1e-12);
  // u2 solves ρu2 + sin u2 = ρu1 + sin u1.
  EXPECT_NEAR(d.rho * d.contact_phase_rad + std::sin(d.contact_phase_rad),
              d.rho * d.separation_phase_rad + std::sin(d.separation_phase_rad), 1e-12);
}

TEST(DutyCycle, AgreesWithDirectKinematics) {
  for (double v : {0.3, 1.0, 1.8, 2.4}) {
    const double r = duty_cycle(v, 20000.0, 20e-6).ratio;
    EXPECT_NEAR(r, duty_cycle_by_kinematics(v, 20000.0, 20e-6), 2e-4) << "v = " << v;
  }
}

TEST(DutyCycle, NoSeparationAtOrAboveCriticalSpeedAndGrowsWithSpeed) {
  const double vc = units::kTwoPi * 20000.0 * 20e-6;
  EXPECT_EQ(duty_cycle(vc, 20000.0, 20e-6).ratio, 1.0);
  EXPECT_EQ(duty_cycle(1.5 * vc, 20000.0, 20e-6).ratio, 1.0);
  EXPECT_FALSE(duty_cycle(vc, 20000.0, 20e-6).separates);
  double previous = 0.0;
  for (int i = 1; i <= 100; ++i) {
    const double r = duty_cycle(vc * i / 100.0, 20000.0, 20e-6).ratio;
    EXPECT_GT(r, previous) << "at v/vc = " << i / 100.0;
    previous = r;
  }
  // Continuous at the critical speed.
  EXPECT_NEAR(duty_cycle(0.9999 * vc, 20000.0, 20e-6).ratio, 1.0, 0.02);
}

TEST(DutyCycle, RejectsBadInputNamingTheField) {
  EXPECT_THROW(duty_cycle(1.0, 0.0, 20e-6), InvalidInput);
  EXPECT_THROW(duty_cycle(-1.0, 20000.0, 20e-6), InvalidInput);
  try {
    duty_cycle(1.0, 20000.0, std::nan(""));
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("amplitude = nan"), std::string::npos) << e.what();
  }
  EXPECT_THROW(fixed_duty_cycle(0.0, 20000.0), InvalidInput);
  EXPECT_THROW(fixed_duty_cycle(1.2, 20000.0), InvalidInput);
}

TEST(ContactWindow, MeanIsTheExactIntegralOfTheWindow) {
  const ContactWindow g = duty_cycle(1.0, 20000.0, 20e-6).window();
  // Over whole periods the mean is r.
  EXPECT_NEAR(g.mean(0.3e-6, 0.3e-6 + 7 * g.period_s), g.duty_cycle, 1e-12);
  // Over an arbitrary interval it matches a fine Riemann sum of in_contact.
  const double t0 = 3.7e-6, t1 = 81.2e-6;
  const int n = 2000000;
  long long in = 0;
  for (int k = 0; k < n; ++k) in += g.in_contact(t0 + (t1 - t0) * (k + 0.5) / n) ? 1 : 0;
  EXPECT_NEAR(g.mean(t0, t1), static_cast<double>(in) / n, 2e-6);
  // The window starts where contact resumes: at the contact phase u2 of the kinematics.
  EXPECT_TRUE(g.in_contact(g.start_s + 1e-9));
  EXPECT_FALSE(g.in_contact(g.start_s - 1e-9));
}

TEST(PulsedForces, MeanIsDutyCycleTimesPeak) {
  // [Chikishev2018, table 1]: Kc = 2.1e3 MPa, Kt = 1.2e3 MPa, h = 0.15 mm, w = 0.2 mm.
  const double r = duty_cycle(1.0, 20000.0, 20e-6).ratio;
  const PulsedForces f = pulsed_forces(2.1e9, 1.2e9, 0.15e-3, 0.2e-3, r);
  EXPECT_NEAR(f.peak_cutting_n, 63.0, 1e-9);
  EXPECT_NEAR(f.peak_thrust_n, 36.0, 1e-9);
  EXPECT_NEAR(f.mean_cutting_n, 25.8, 0.05);  // r·K·h·w = 25.8 N, 14.7 N: docs/models/turning.md §2
  EXPECT_NEAR(f.mean_thrust_n, 14.7, 0.05);
}

}  // namespace
}  // namespace cutdyn
