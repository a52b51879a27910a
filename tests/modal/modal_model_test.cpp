#include "cutdyn/modal/modal_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <string>
#include <unsupported/Eigen/MatrixFunctions>

#include "cutdyn/core/units.hpp"

namespace cutdyn {
namespace {

// The table-2 structure of [Chikishev2018]: 228.8 Hz, 2.26e8 N/m, zeta = 0.01.
Mode table2_mode() { return Mode{Direction::kX, units::hz_to_rad_per_s(228.8), 0.01, 2.26e8}; }

TEST(Frf, StaticAndResonantValuesOfOneMode) {
  ModalModel model{{table2_mode()}};
  const double k = 2.26e8, zeta = 0.01;
  EXPECT_NEAR(std::real(frf(model, Direction::kX, 0.0)), 1.0 / k, 1e-20);
  // At resonance G = 1/(2iζk): purely imaginary, magnitude 1/(2ζk).
  const auto g = frf(model, Direction::kX, model.modes[0].natural_rad_s);
  EXPECT_NEAR(std::real(g), 0.0, 1e-22);
  EXPECT_NEAR(std::imag(g), -1.0 / (2.0 * zeta * k), 1e-6 / (2.0 * zeta * k));
  // Minimum of Re G is -1/(4ζ(1+ζ)k) at r = sqrt(1+2ζ) (classical result).
  const double r = std::sqrt(1.0 + 2.0 * zeta);
  const auto gmin = frf(model, Direction::kX, r * model.modes[0].natural_rad_s);
  EXPECT_NEAR(std::real(gmin), -1.0 / (4.0 * zeta * (1.0 + zeta) * k), 1e-12 / k);
  // No modes in y: zero response.
  EXPECT_EQ(frf(model, Direction::kY, 1000.0), std::complex<double>(0.0, 0.0));
}

TEST(Frf, ModesInOneDirectionAdd) {
  Mode a = table2_mode();
  Mode b = mode_from_mass(Direction::kX, units::hz_to_rad_per_s(600.0), 0.03, 2.0);
  ModalModel both{{a, b}};
  const double w = 2000.0;
  EXPECT_NEAR(std::abs(frf(both, Direction::kX, w) - frf(ModalModel{{a}}, Direction::kX, w) -
                       frf(ModalModel{{b}}, Direction::kX, w)),
              0.0, 1e-22);
  EXPECT_NEAR(b.mass_kg(), 2.0, 1e-12);
}

TEST(ModalStateSpace, TransferFunctionEqualsFrf) {
  Mode a = table2_mode();
  Mode b = mode_from_mass(Direction::kX, units::hz_to_rad_per_s(600.0), 0.03, 2.0);
  Mode c = mode_from_mass(Direction::kY, units::hz_to_rad_per_s(900.0), 0.02, 1.0);
  ModalModel model{{a, c, b}};
  const auto ss = modal_state_space(model, {Direction::kX, Direction::kY});
  ASSERT_EQ(ss.A.rows(), 6);
  for (double w : {0.0, 500.0, 1437.6, 3770.0, 10000.0}) {
    const Eigen::MatrixXcd h = ss.C.cast<std::complex<double>>() *
                               (std::complex<double>(0.0, w) * Eigen::MatrixXcd::Identity(6, 6) -
                                ss.A.cast<std::complex<double>>())
                                   .inverse() *
                               ss.B.cast<std::complex<double>>();
    const auto gx = frf(model, Direction::kX, w);
    const auto gy = frf(model, Direction::kY, w);
    EXPECT_NEAR(std::abs(h(0, 0) - gx), 0.0, 1e-9 * std::abs(gx));
    EXPECT_NEAR(std::abs(h(1, 1) - gy), 0.0, 1e-9 * std::abs(gy));
    EXPECT_NEAR(std::abs(h(0, 1)), 0.0, 1e-25);
  }
}

// A mode with a complex residue (non-proportional damping, modal_model.hpp): the receptance,
// the state space and the static value against the pole-residue form
// A/(iω − λ) + A*/(iω − λ*), A = −i·ωn²/(2·k·ωd)·e^(iφ), λ = −ζωn + iωd, computed directly.
TEST(ComplexResidueMode, ReceptanceAndStateSpaceAreThePoleResidueForm) {
  using cd = std::complex<double>;
  for (double zeta : {0.005, 0.05, 0.3}) {
    for (double phi_deg : {-80.0, -35.0, -6.4, 0.0, 12.0, 45.0, 89.0}) {
      Mode m{Direction::kX, units::hz_to_rad_per_s(730.0), zeta, 3.0e7,
             units::deg_to_rad(phi_deg)};
      const double wn = m.natural_rad_s, wd = wn * std::sqrt(1.0 - zeta * zeta);
      const cd lambda(-zeta * wn, wd);
      const cd residue =
          cd(0.0, -wn * wn / (2.0 * m.stiffness_n_per_m * wd)) * std::polar(1.0, m.residue_phase_rad);
      const ModalModel model{{m}};
      ASSERT_TRUE(model.validate().empty()) << phi_deg;
      const auto ss = modal_state_space(model, {Direction::kX});
      for (double w : {0.0, 0.3 * wn, 0.99 * wn, wn, 1.02 * wn, 4.0 * wn, 40.0 * wn}) {
        const cd s(0.0, w);
        const cd expected = residue / (s - lambda) + std::conj(residue) / (s - std::conj(lambda));
        const cd g = frf(model, Direction::kX, w);
        const std::string what = "ζ " + std::to_string(zeta) + ", φ " +
                                 std::to_string(phi_deg) + "°, ω/ωn " + std::to_string(w / wn);
        EXPECT_LT(std::abs(g - expected), 1e-12 * std::abs(expected)) << what;
        const cd h = (ss.C.cast<cd>() *
                      (s * Eigen::MatrixXcd::Identity(2, 2) - ss.A.cast<cd>()).inverse() *
                      ss.B.cast<cd>())(0, 0);
        EXPECT_LT(std::abs(h - expected), 1e-11 * std::abs(expected)) << what;
      }
      // The static compliance is b0/ωn² = G(0); a real mode's is 1/k.
      const auto [b0, b1] = receptance_numerator(m);
      EXPECT_NEAR(std::real(frf(model, Direction::kX, 0.0)), b0 / (wn * wn),
                  1e-12 * std::abs(b0) / (wn * wn));
      if (phi_deg == 0.0) {
        EXPECT_EQ(b1, 0.0);
        EXPECT_EQ(ss.C(0, 1), 0.0);
        EXPECT_EQ(ss.C(0, 0), 1.0);
      }
    }
  }
}

TEST(ComplexResidueMode, APhaseOfAQuarterTurnOrMoreIsRefused) {
  for (double phi_deg : {90.0, -90.0, 120.0}) {
    const ModalModel bad{{Mode{Direction::kX, 3000.0, 0.02, 1e7, units::deg_to_rad(phi_deg)}}};
    const auto problems = bad.validate();
    ASSERT_EQ(problems.size(), 1u) << phi_deg;
    EXPECT_NE(problems[0].find("modes[0].residue_phase_rad"), std::string::npos) << problems[0];
  }
}

TEST(ModalModel, ValidateNamesEachBadField) {
  ModalModel bad{{Mode{Direction::kX, -1.0, 1.2, 0.0}}};
  const auto problems = bad.validate();
  ASSERT_EQ(problems.size(), 3u);
  EXPECT_NE(problems[0].find("modes[0].natural_rad_s = -1"), std::string::npos);
  EXPECT_NE(problems[1].find("modes[0].damping_ratio = 1.2"), std::string::npos);
  EXPECT_NE(problems[2].find("modes[0].stiffness_n_per_m = 0"), std::string::npos);
  EXPECT_FALSE(ModalModel{}.validate().empty());
}

}  // namespace
}  // namespace cutdyn
