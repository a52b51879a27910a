#include "cutdyn/stability/full_discretization.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "cutdyn/core/error.hpp"
#include "cutdyn/stability/multi_frequency.hpp"
#include "cutdyn/stability/tlusty.hpp"
#include "support/reference_cases.hpp"

namespace cutdyn {
namespace {

using testing::table2_conventional;
using testing::table2_vibration;

// Searched up to 0.2 m so that every speed has a boundary (between lobes it exceeds 30 mm).
constexpr double kDepthLimit = 0.2;

double closed_form(const TurningProcess& m, double rpm, double r = 1.0) {
  return tlusty_critical_depth(m.modal, Direction::kX, r * m.kf_pa, 60.0 / rpm, kDepthLimit)
      .boundary.depth_m;
}

TEST(FullDiscretization, ZeroDepthSpectralRadiusIsTheStructuresDecay) {
  // At w = 0 the period map is e^(A0·T) plus a nilpotent shift: ρ = exp(−ζ·ωn·T).
  const double zeta_wn = 0.01 * units::hz_to_rad_per_s(testing::kTable2NaturalHz);
  struct Case {
    TurningProcess model;
    double rpm;
    int steps;
  };
  // Dense Φ of dimension 2 + L, L = delay / step: kept to a few hundred here.
  for (const Case& c :
       {Case{table2_conventional(), 3000.0, 0}, Case{table2_conventional(), 3000.0, 30},
        Case{table2_vibration(20000.0), 5000.0, 0}, Case{table2_vibration(700.0), 3000.0, 0}}) {
    const DelayedSystem s = turning_system(c.model, c.rpm);
    FdOptions o;
    o.steps_per_period = c.steps;
    const FdGrid grid = fd_grid(s, o);
    EXPECT_NEAR(fd_spectral_radius(s, grid, 0.0), std::exp(-zeta_wn * grid.period_s), 1e-9);
  }
}

TEST(FullDiscretization, ConstantCoefficientMatchesClosedFormWithinOnePercent) {
  const TurningProcess m = table2_conventional();
  TurningStabilityOptions o;
  o.depth_max_m = kDepthLimit;
  for (double rpm = 500.0; rpm <= 5000.0; rpm += 20.0) {
    const TurningBoundary fd = turning_critical_depth(m, rpm, o);
    const double exact = closed_form(m, rpm);
    ASSERT_TRUE(fd.boundary.found);
    EXPECT_NEAR(fd.boundary.depth_m, exact, 0.01 * exact) << "rpm " << rpm;
    EXPECT_NEAR(fd.boundary.chatter_hz,
                tlusty_critical_depth(m.modal, Direction::kX, m.kf_pa, 60.0 / rpm, kDepthLimit)
                    .boundary.chatter_hz,
                0.05);
  }
}

TEST(FullDiscretization, TwoModesMatchTheClosedForm) {
  // A second, stiffer and more damped mode at 640 Hz: the FRF is the sum of both.
  TurningProcess m = table2_conventional();
  m.modal.modes.push_back(mode_from_mass(Direction::kX, units::hz_to_rad_per_s(640.0), 0.03, 1.5));
  TurningStabilityOptions o;
  o.depth_max_m = kDepthLimit;
  for (double rpm = 700.0; rpm <= 6000.0; rpm += 265.0) {
    const TurningBoundary fd = turning_critical_depth(m, rpm, o);
    const auto exact =
        tlusty_critical_depth(m.modal, Direction::kX, m.kf_pa, 60.0 / rpm, kDepthLimit);
    ASSERT_TRUE(fd.boundary.found && exact.boundary.found) << "rpm " << rpm;
    EXPECT_NEAR(fd.boundary.depth_m, exact.boundary.depth_m, 0.01 * exact.boundary.depth_m)
        << "rpm " << rpm;
    EXPECT_NEAR(fd.boundary.chatter_hz, exact.boundary.chatter_hz, 0.5) << "rpm " << rpm;
  }
}

TEST(FullDiscretization, SecondOrderConvergenceInTheStep) {
  // Error against the closed form for steps of 1/16 ... 1/256 of the structural period: each
  // halving divides it by four (the table is in docs/models/turning.md).
  const TurningProcess m = table2_conventional();
  for (double rpm : {800.0, 1400.0, 3000.0}) {
    const DelayedSystem s = turning_system(m, rpm);
    const double exact = closed_form(m, rpm);
    double previous = 0.0;
    for (double fraction : {1.0 / 16, 1.0 / 32, 1.0 / 64, 1.0 / 128, 1.0 / 256}) {
      FdOptions o;
      o.max_step_fraction = fraction;
      const double err = std::abs(fd_critical_depth(s, o).depth_m - exact) / exact;
      if (previous > 0.0) {
        EXPECT_NEAR(previous / err, 4.0, 0.2) << "rpm " << rpm << ", step fraction " << fraction;
      }
      if (fraction == FdOptions{}.max_step_fraction) {
        EXPECT_LT(err, 1.5e-3);  // the default step
      }
      previous = err;
    }
  }
}

TEST(FullDiscretization, ReducedFormEqualsDenseTransitionMatrix) {
  // The same discretization: the textbook dense Φ with bisection on its spectral radius, and
  // the reduced multiplier-on-the-unit-circle form, agree to the bisection tolerance.
  struct Case {
    TurningProcess model;
    double rpm;
    int steps;
  };
  for (const Case& c :
       {Case{table2_conventional(), 3000.0, 30}, Case{table2_conventional(), 4700.0, 24},
        Case{table2_vibration(1000.0), 3000.0, 0}, Case{table2_vibration(700.0), 4000.0, 0}}) {
    const DelayedSystem s = turning_system(c.model, c.rpm);
    FdOptions o;
    o.steps_per_period = c.steps;
    const CriticalDepth reduced = fd_critical_depth(s, o);
    const CriticalDepth dense = fd_critical_depth_dense(s, o, 1e-8);
    ASSERT_TRUE(reduced.found && dense.found);
    EXPECT_NEAR(reduced.depth_m, dense.depth_m, 2e-7 * dense.depth_m) << "rpm " << c.rpm;
    EXPECT_NEAR(reduced.chatter_hz, dense.chatter_hz, 1e-3 * dense.chatter_hz);
  }
}

TEST(FullDiscretization, UltrasonicLobesAgreeWithAveragedTheory) {
  // f = 20 kHz ≫ fn = 228.8 Hz: the contact window only scales Kt by r.
  const TurningProcess m = table2_vibration(20000.0);
  TurningStabilityOptions o;
  o.depth_max_m = kDepthLimit;
  for (double rpm = 500.0; rpm <= 5000.0; rpm += 45.0) {
    const TurningBoundary fd = turning_critical_depth(m, rpm, o);
    const double averaged = closed_form(m, rpm, testing::kTable2DutyCycle);
    ASSERT_TRUE(fd.boundary.found);
    EXPECT_NEAR(fd.boundary.depth_m, averaged, 0.02 * averaged) << "rpm " << rpm;
    // And above the conventional lobe at every speed.
    EXPECT_GT(fd.boundary.depth_m, closed_form(m, rpm)) << "rpm " << rpm;
  }
}

TEST(FullDiscretization, LowFrequencyVibrationAgreesWithMultiFrequency) {
  // f = 700 Hz, about three times the natural frequency: the averaged theory is no longer
  // exact, the multi-frequency solution is.
  const TurningProcess m = table2_vibration(700.0);
  TurningStabilityOptions fd, mf;
  mf.method = TurningMethod::kMultiFrequency;
  mf.harmonics = 8;
  for (double rpm : {900.0, 1800.0, 3100.0, 4600.0}) {
    const double a = turning_critical_depth(m, rpm, fd).boundary.depth_m;
    const double b = turning_critical_depth(m, rpm, mf).boundary.depth_m;
    EXPECT_NEAR(a, b, 0.02 * b) << "rpm " << rpm;
  }
}

TEST(FullDiscretization, RejectsAnUndampedStructureAndBadOptions) {
  TurningProcess m = table2_conventional();
  DelayedSystem s = turning_system(m, 2000.0);
  s.A0(1, 1) = 0.0;  // no damping: not asymptotically stable alone
  EXPECT_THROW(fd_critical_depth(s, FdOptions{}), InvalidInput);
  FdOptions bad;
  bad.max_step_fraction = 0.0;
  EXPECT_THROW(fd_critical_depth(turning_system(m, 2000.0), bad), InvalidInput);
  try {
    MultiFrequencyOptions o;
    o.harmonics = -1;
    multi_frequency_critical_depth(turning_system(m, 2000.0), o);
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("harmonics = -1"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace cutdyn
