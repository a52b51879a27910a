#include "cutdyn/stability/full_discretization.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/stability/milling.hpp"
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

TEST(FullDiscretization, QuadraticInterpolationConvergesAtThirdOrder) {
  // The same closed form with the quadratic interpolation (order 2), by the spectral radius
  // (the reduced form takes order 1 only): each halving of the step divides the error by
  // about eight (6.9–7.8 measured from 1/16 on), against four for order 1, and at equal steps
  // the error is 8–14× smaller. Steps of 1/16 … 1/64 of the structural period over the delay.
  const TurningProcess m = table2_conventional();
  for (double rpm : {800.0, 1400.0, 3000.0}) {
    const DelayedSystem s = turning_system(m, rpm);
    const double exact = closed_form(m, rpm);
    const auto error = [&](int order, double fraction) {
      FdOptions o;
      o.order = order;
      o.depth_max_m = kDepthLimit;
      o.steps_per_period =
          static_cast<int>(std::lround(s.delay_s * testing::kTable2NaturalHz / fraction));
      const CriticalDepth c = fd_critical_depth_by_radius(s, o, RadiusSolver::kArnoldi, 1e-10, 16);
      EXPECT_TRUE(c.found);
      return std::abs(c.depth_m - exact) / exact;
    };
    double previous = error(2, 1.0 / 16);
    for (double fraction : {1.0 / 32, 1.0 / 64}) {
      const double err = error(2, fraction);
      EXPECT_GT(previous / err, 6.5) << "rpm " << rpm << ", step fraction " << fraction;
      EXPECT_LT(previous / err, 8.5) << "rpm " << rpm << ", step fraction " << fraction;
      previous = err;
    }
    EXPECT_LT(error(2, 1.0 / 32), error(1, 1.0 / 32) / 7.0) << "rpm " << rpm;
  }
}

TEST(FullDiscretization, QuadraticInterpolationDenseEqualsArnoldi) {
  // Order 2 on milling maps with delayed values on the nodes one period back (even pitch) and
  // between nodes (uneven pitch: four delays): the matrix-free product (the unrestarted
  // Arnoldi, not a fallback) and the dense matrix give the same dominant multiplier.
  std::vector<std::pair<std::string, DelayedSystem>> systems;
  MillingProcess uneven = testing::insperger_benchmark(0.5);
  uneven.tool.teeth = 4;
  uneven.tool.pitch_rad = {units::deg_to_rad(70.0), units::deg_to_rad(110.0),
                           units::deg_to_rad(70.0), units::deg_to_rad(110.0)};
  systems.emplace_back("slotting", milling_system(testing::insperger_benchmark(1.0), 9000.0));
  systems.emplace_back("up-milling a/D 0.05",
                       milling_system(testing::insperger_benchmark(0.05, true, false), 14000.0));
  systems.emplace_back("uneven pitch", milling_system(uneven, 9500.0));
  for (const auto& [name, s] : systems) {
    FdOptions o;
    o.order = 2;
    o.max_step_fraction = 1.0 / 32;
    const FdDiscretization fd(s, o);
    for (double w : {0.0, 1e-4, 5e-4, 2e-3}) {
      const DominantMultiplier a = fd.dominant_multiplier(w, RadiusSolver::kArnoldi);
      const DominantMultiplier d = fd.dominant_multiplier(w, RadiusSolver::kDense);
      EXPECT_TRUE(a.krylov) << name << ", w " << w;
      EXPECT_NEAR(a.radius, d.radius, 1e-8 * d.radius) << name << ", w " << w;
      EXPECT_NEAR(std::abs(a.mu - d.mu), 0.0, 1e-7 * d.radius) << name << ", w " << w;
    }
  }
}

TEST(FullDiscretization, QuadraticInterpolationOnWindowsAndSingleStepPeriods) {
  // Turning maps, whose multipliers crowd the unit circle (the Arnoldi radius falls back to
  // the dense matrix there), by the dense critical depth on steps of 1/32:
  // * vibration-assisted at 700 Hz — a window period that does not divide the delay, so the
  //   delayed values lie between nodes — against the reduced method on 1/256 (order 1, 4e-5
  //   from its 1/512): order 2 within 5e-4 (measured 1.7e-4), order 1 6.9e-3 off;
  // * conventional, constant H, discretized with one step per period (node j − 1 is the step's
  //   own start one period back) — against the closed form: order 2 within 5e-4 (measured
  //   3.0–4.2e-4), order 1 3.3–4.4e-3 off.
  for (double rpm : {4600.0}) {
    const DelayedSystem s = turning_system(table2_vibration(700.0), rpm);
    FdOptions converged;
    converged.max_step_fraction = 1.0 / 256;
    converged.depth_max_m = kDepthLimit;
    const double reference = fd_critical_depth(s, converged).depth_m;
    const auto error = [&](int order) {
      FdOptions o;
      o.order = order;
      o.max_step_fraction = 1.0 / 32;
      o.depth_max_m = kDepthLimit;
      return std::abs(fd_critical_depth_dense(s, o, 1e-7).depth_m / reference - 1.0);
    };
    EXPECT_LT(error(2), 5e-4) << "vibration-assisted, rpm " << rpm;
    EXPECT_LT(error(2), error(1) / 5.0) << "vibration-assisted, rpm " << rpm;
  }
  const TurningProcess m = table2_conventional();
  for (double rpm : {3000.0, 4600.0}) {
    const DelayedSystem s = turning_system(m, rpm);
    const double exact = closed_form(m, rpm);
    const auto error = [&](int order) {
      FdOptions o;
      o.order = order;
      o.max_step_fraction = 1.0 / 32;
      o.depth_max_m = kDepthLimit;
      EXPECT_EQ(fd_grid(s, o).steps(), 1);
      return std::abs(fd_critical_depth_dense(s, o, 1e-7).depth_m / exact - 1.0);
    };
    EXPECT_LT(error(2), 5e-4) << "constant H, rpm " << rpm;
    EXPECT_LT(error(2), error(1) / 5.0) << "constant H, rpm " << rpm;
  }
}

TEST(FullDiscretization, QuadraticInterpolationConvergesToTheLinearOnesLimit) {
  // An uneven-pitch cutter (70°/110°/70°/110°, four delays whose delayed instants fall
  // between nodes, interpolated on three nodes) and the up-milling flip lobes of a/D 0.05:
  // orders 1 and 2 converge to the same depth, order 2 from closer with half the steps.
  // Reference: order 2 at 1/128 of the structural period.
  MillingProcess uneven = testing::insperger_benchmark(0.5);
  uneven.tool.teeth = 4;
  uneven.tool.pitch_rad = {units::deg_to_rad(70.0), units::deg_to_rad(110.0),
                           units::deg_to_rad(70.0), units::deg_to_rad(110.0)};
  struct Case {
    MillingProcess model;
    double rpm;
  };
  for (const Case& c : {Case{uneven, 5000.0}, Case{uneven, 9500.0},
                        Case{testing::insperger_benchmark(0.05, true, false), 18700.0}}) {
    const DelayedSystem s = milling_system(c.model, c.rpm);
    const auto depth = [&](int order, double fraction) {
      FdOptions o;
      o.order = order;
      o.max_step_fraction = fraction;
      o.depth_max_m = 3e-3;
      const CriticalDepth found =
          fd_critical_depth_by_radius(s, o, RadiusSolver::kArnoldi, 1e-8, 16);
      EXPECT_TRUE(found.found);
      return found.depth_m;
    };
    const double reference = depth(2, 1.0 / 128);
    const double linear = std::abs(depth(1, 1.0 / 64) / reference - 1.0);
    const double quadratic = std::abs(depth(2, 1.0 / 32) / reference - 1.0);
    EXPECT_LT(linear, 4e-3) << "rpm " << c.rpm;
    EXPECT_LT(quadratic, 1e-3) << "rpm " << c.rpm;
    EXPECT_LT(quadratic, linear) << "rpm " << c.rpm;
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
  FdOptions order;
  order.order = 3;
  EXPECT_THROW(fd_grid(turning_system(m, 2000.0), order), InvalidInput);
  order.order = 2;  // the reduced form is the linear interpolation's
  EXPECT_THROW(fd_critical_depth(turning_system(m, 2000.0), order), InvalidInput);
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
