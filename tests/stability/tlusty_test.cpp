#include "cutdyn/stability/tlusty.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "support/reference_cases.hpp"

namespace cutdyn {
namespace {

using testing::table2_absolute_minimum_depth;
using testing::table2_conventional;

TEST(Tlusty, LobeMinimaEqualTheAbsoluteMinimumDepth) {
  const TurningProcess m = table2_conventional();
  const double a_min = table2_absolute_minimum_depth();  // 5.3708 mm
  const double w_star = m.modal.modes[0].natural_rad_s * std::sqrt(1.0 + 2.0 * 0.01);
  for (int lobe : {1, 3, 9, 27}) {
    // The speed at which lobe j reaches its minimum: τ = (2πj + ε(ω*))/ω*.
    const TlustyLobePoint p = tlusty_lobe_point(m.modal, Direction::kX, m.kf_pa, w_star, lobe);
    EXPECT_NEAR(p.depth_m, a_min, 1e-12);
    const TlustyResult r = tlusty_critical_depth(m.modal, Direction::kX, m.kf_pa, p.delay_s, 0.03);
    ASSERT_TRUE(r.boundary.found);
    EXPECT_NEAR(r.boundary.depth_m, a_min, 1e-9 * a_min) << "lobe " << lobe;
    EXPECT_NEAR(r.boundary.chatter_hz, units::rad_per_s_to_hz(w_star), 1e-6);
    EXPECT_EQ(r.lobe, lobe);
  }
}

TEST(Tlusty, SatisfiesTheCharacteristicEquationAndNeverGoesBelowTheMinimum) {
  const TurningProcess m = table2_conventional();
  const double a_min = table2_absolute_minimum_depth();
  for (double rpm = 500.0; rpm <= 5000.0; rpm += 37.0) {
    const double tau = 60.0 / rpm;
    const TlustyResult r = tlusty_critical_depth(m.modal, Direction::kX, m.kf_pa, tau, 0.5);
    ASSERT_TRUE(r.boundary.found);
    EXPECT_GE(r.boundary.depth_m, a_min * (1.0 - 1e-12));
    // 1 + Kt·w·G(ω)·(1 − e^(−iωτ)) = 0 at the returned depth and frequency (rpm ↔ rad/s ↔ Hz).
    const double w = units::hz_to_rad_per_s(r.boundary.chatter_hz);
    const std::complex<double> g = frf(m.modal, Direction::kX, w);
    const std::complex<double> residual =
        1.0 +
        m.kf_pa * r.boundary.depth_m * g * (1.0 - std::exp(std::complex<double>(0, -w * tau)));
    EXPECT_LT(std::abs(residual), 1e-8) << "rpm " << rpm;
    // Lobe number: whole chatter waves per revolution.
    EXPECT_EQ(r.lobe, static_cast<int>(std::floor(r.boundary.chatter_hz * tau)));
  }
}

TEST(Tlusty, TwoModesUseTheSummedFrf) {
  TurningProcess m = table2_conventional();
  m.modal.modes.push_back(mode_from_mass(Direction::kX, units::hz_to_rad_per_s(640.0), 0.03, 1.5));
  const double tau = 60.0 / 2200.0;
  const TlustyResult r = tlusty_critical_depth(m.modal, Direction::kX, m.kf_pa, tau, 0.05);
  ASSERT_TRUE(r.boundary.found);
  const double w = units::hz_to_rad_per_s(r.boundary.chatter_hz);
  const auto g = frf(m.modal, Direction::kX, w);
  EXPECT_NEAR(r.boundary.depth_m, -1.0 / (2.0 * m.kf_pa * g.real()), 1e-12);
  // The brute-force minimum over a fine frequency grid of w_lim where the phase condition
  // holds within the grid resolution cannot be lower than the returned depth.
  double brute = 1e9;
  for (double f = 1.0; f < 2000.0; f += 0.0005) {
    const double wf = units::hz_to_rad_per_s(f);
    const auto gf = frf(m.modal, Direction::kX, wf);
    if (gf.real() >= 0.0) continue;
    const double eps = 3.0 * units::kPi + 2.0 * std::arg(gf);
    const double mismatch = std::remainder(wf * tau - eps, units::kTwoPi);
    if (std::abs(mismatch) < 2e-3) brute = std::min(brute, -1.0 / (2.0 * m.kf_pa * gf.real()));
  }
  EXPECT_NEAR(r.boundary.depth_m, brute, 2e-3 * brute);
}

TEST(Tlusty, ReportsNotFoundAboveTheSearchLimit) {
  const TurningProcess m = table2_conventional();
  const TlustyResult r = tlusty_critical_depth(m.modal, Direction::kX, m.kf_pa, 0.05, 0.004);
  EXPECT_FALSE(r.boundary.found);
  EXPECT_EQ(r.boundary.depth_m, 0.004);
}

}  // namespace
}  // namespace cutdyn
