// Milling stability beyond the straight, evenly spaced cutter: helical flutes (axial slices),
// uneven pitch (one delay per tooth), unstable islands at low immersion, and turning as the
// special case of the same machinery. docs/models/milling-stability.md.
#include <gtest/gtest.h>

#include <cmath>

#include "cutdyn/core/units.hpp"
#include "cutdyn/stability/full_discretization.hpp"
#include "cutdyn/stability/milling.hpp"
#include "cutdyn/stability/multi_frequency.hpp"
#include "cutdyn/stability/tlusty.hpp"
#include "cutdyn/stability/turning.hpp"
#include "support/reference_cases.hpp"

namespace cutdyn {
namespace {

using testing::insperger_benchmark;
using units::kPi;
using units::kTwoPi;

// The benchmark structure made `scale` times stiffer (modal mass × scale, same 922 Hz), so
// that critical depths are millimetres and the flute's lag over the depth matters.
MillingProcess stiff_benchmark(double immersion, double scale) {
  MillingProcess m = insperger_benchmark(immersion);
  for (Mode& mode : m.modal.modes) mode.stiffness_n_per_m *= scale;
  return m;
}

MillingStabilityOptions options(MillingMethod method, double depth_max_m, int harmonics = 6) {
  MillingStabilityOptions o;
  o.method = method;
  o.depth_max_m = depth_max_m;
  o.harmonics = harmonics;
  o.rel_tol = 1e-5;
  return o;
}

TEST(MillingHelix, SlicesAverageTheStraightToothOverTheFluteLength) {
  // 30° helix, D = 20 mm, a = 8 mm: lag 2a·tanβ/D = 0.46 rad, 53 slices of at most 0.5°.
  // Step means of H against a fine quadrature (400 × 2000 points) of the force model over
  // the step and the flute length. The slices are a midpoint rule in depth with jumps at the
  // window edges: allowance 0.5 % of ‖H‖.
  MillingProcess m = insperger_benchmark(0.5);
  m.tool.helix_rad = units::deg_to_rad(30.0);
  const double depth = 8e-3, rpm = 7000.0;
  const double lag = m.tool.lag_angle(depth);
  EXPECT_NEAR(lag, 2.0 * depth * std::tan(m.tool.helix_rad) / m.tool.diameter_m, 1e-15);
  EXPECT_EQ(m.tool.slices(depth), static_cast<int>(std::ceil(lag / (kPi / 360.0))));
  const DelayedSystem s = milling_system(m, rpm, depth);
  const double T = s.delay_s;
  const Eigen::Matrix2d h0 = s.H.mean(0.0, T);
  for (const auto& [a, b] : {std::pair{0.0, T}, {0.1 * T, 0.3 * T}, {0.45 * T, 0.55 * T}}) {
    Eigen::Matrix2d q = Eigen::Matrix2d::Zero();
    constexpr int kT = 400, kZ = 2000;
    for (int i = 0; i < kT; ++i)
      for (int k = 0; k < kZ; ++k)
        q += testing::direct_milling_h(m, rpm, a + (b - a) * (i + 0.5) / kT, lag * (k + 0.5) / kZ);
    q /= static_cast<double>(kT) * kZ;
    EXPECT_LT((s.H.mean(a, b) - q).norm(), 5e-3 * h0.norm())
        << "[" << a / T << ", " << b / T << "]·T";
  }
}

TEST(MillingHelix, ZeroOrderSolutionDoesNotDependOnTheHelix) {
  // The mean of H over a period is the same for every slice: H0 is that of straight teeth.
  MillingProcess m = insperger_benchmark(0.3);
  const Eigen::MatrixXcd straight = milling_system(m, 9000.0).H.fourier(0);
  m.tool.helix_rad = units::deg_to_rad(40.0);
  for (double depth : {1e-3, 5e-3, 20e-3}) {
    EXPECT_LT((milling_system(m, 9000.0, depth).H.fourier(0) - straight).norm(),
              1e-12 * straight.norm());
  }
}

TEST(MillingHelix, UniformCutMakesTheCoefficientConstantAndTheBoundaryTheZeroOrderOne) {
  // When the flute's lag over the depth is one tooth pitch (2a·tanβ/D = 2π/z), every angle of
  // the period is cut somewhere along the flute at every instant: H(t) is its time mean H0,
  // the process is time-invariant and the zero-order solution is exact. So with the helix
  // chosen for a = the zero-order critical depth a0, the full discretization's spectral radius
  // at a0 is 1 (to its step error, 0.1 %), and equals that of a constant-coefficient system H0.
  const double rpm = 6000.0;
  MillingProcess m = stiff_benchmark(0.5, 100.0);
  const MillingBoundary zero =
      milling_critical_depth(m, rpm, options(MillingMethod::kZeroOrder, 0.05));
  ASSERT_TRUE(zero.boundary.found);
  const double a0 = zero.boundary.depth_m;
  m.tool.helix_rad = std::atan(kTwoPi / m.tool.teeth * m.tool.diameter_m / (2.0 * a0));
  EXPECT_NEAR(m.tool.lag_angle(a0), kPi, 1e-12);
  const DelayedSystem helical = milling_system(m, rpm, a0);
  const Eigen::Matrix2d h0 = helical.H.fourier(0).real();
  for (double f : {0.0, 0.2, 0.5, 0.8}) {
    const double t = f * helical.delay_s;
    EXPECT_LT((helical.H.mean(t, t + 0.05 * helical.delay_s) - h0).norm(), 2e-3 * h0.norm());
  }
  DelayedSystem constant = helical;
  constant.H = constant_coefficient(h0);
  FdOptions o;
  o.steps_per_period = 200;
  const double rho_helical = fd_spectral_radius(helical, fd_grid(helical, o), a0);
  const double rho_constant = fd_spectral_radius(constant, fd_grid(constant, o), a0);
  EXPECT_NEAR(rho_helical, 1.0, 1e-3);
  EXPECT_NEAR(rho_helical, rho_constant, 1e-4);
}

TEST(MillingHelix, MultiFrequencyAndFullDiscretizationAgree) {
  // Two independent treatments of the depth-dependent H: the full discretization searches the
  // depth with H(a) rebuilt at each a; the multi-frequency method (8 harmonics) solves
  // a = w_crit(H(a)). a/D = 0.5, 6000 rpm (critical depth about 12.8 mm): within 0.5 %.
  for (double helix_deg : {30.0, 45.0}) {
    MillingProcess m = stiff_benchmark(0.5, 100.0);
    m.tool.helix_rad = units::deg_to_rad(helix_deg);
    const MillingBoundary fd =
        milling_critical_depth(m, 6000.0, options(MillingMethod::kFullDiscretization, 0.03));
    const MillingBoundary mf =
        milling_critical_depth(m, 6000.0, options(MillingMethod::kMultiFrequency, 0.03, 8));
    ASSERT_TRUE(fd.boundary.found && mf.boundary.found);
    EXPECT_NEAR(mf.boundary.depth_m, fd.boundary.depth_m, 5e-3 * fd.boundary.depth_m)
        << "helix " << helix_deg;
    EXPECT_NEAR(mf.boundary.chatter_hz, fd.boundary.chatter_hz, 1.0);
    // The flute length is 12.8 mm·tan β / (π·20 mm / 2) of a pitch: the helix matters.
    m.tool.helix_rad = 0.0;
    const MillingBoundary straight =
        milling_critical_depth(m, 6000.0, options(MillingMethod::kFullDiscretization, 0.03));
    EXPECT_GT(std::abs(fd.boundary.depth_m - straight.boundary.depth_m),
              2e-3 * straight.boundary.depth_m);
  }
}

TEST(MillingHelix, MultiFrequencyFindsABoundaryFarBelowTheLimit) {
  // The helical multi-frequency search asks each trial depth a for a boundary no deeper than
  // 2a; at a = 0 (the first coarse step already unstable) the whole limit. A 30° helix on the
  // Insperger–Stépán structure, a/D 0.5, depth limit 30 mm: boundaries of 0.1–0.6 mm, inside
  // the first coarse cell (1.9 mm), against the full discretization to 0.5 %.
  MillingProcess m = insperger_benchmark(0.5);
  m.tool.helix_rad = units::deg_to_rad(30.0);
  for (double rpm : {5000.0, 9500.0, 14000.0}) {
    const MillingBoundary fd =
        milling_critical_depth(m, rpm, options(MillingMethod::kFullDiscretization, 0.03));
    const MillingBoundary mf =
        milling_critical_depth(m, rpm, options(MillingMethod::kMultiFrequency, 0.03));
    ASSERT_TRUE(fd.boundary.found && mf.boundary.found) << rpm;
    EXPECT_LT(fd.boundary.depth_m, 0.03 / 16.0) << rpm;
    EXPECT_NEAR(mf.boundary.depth_m, fd.boundary.depth_m, 5e-3 * fd.boundary.depth_m) << rpm;
    EXPECT_EQ(mf.boundary.bifurcation, fd.boundary.bifurcation) << rpm;
  }
}

TEST(MillingPitch, EqualPitchAnglesGiveTheEvenCutter) {
  // Four teeth given as four equal pitch angles: one delay term per tooth over a revolution
  // instead of one term over a tooth period. Same boundary to the step error.
  MillingProcess even = insperger_benchmark(0.5);
  even.tool.teeth = 4;
  MillingProcess listed = even;
  listed.tool.pitch_rad.assign(4, kTwoPi / 4);
  const DelayedSystem s = milling_system(listed, 7000.0);
  EXPECT_EQ(s.more_delays.size(), 3u);
  EXPECT_NEAR(s.H.period_s, 60.0 / 7000.0, 1e-15);
  for (double rpm : {5000.0, 7000.0, 9500.0}) {
    const auto o = options(MillingMethod::kFullDiscretization, 3e-3);
    const MillingBoundary a = milling_critical_depth(even, rpm, o);
    const MillingBoundary b = milling_critical_depth(listed, rpm, o);
    ASSERT_TRUE(a.boundary.found && b.boundary.found);
    EXPECT_NEAR(b.boundary.depth_m, a.boundary.depth_m, 5e-4 * a.boundary.depth_m) << rpm;
    EXPECT_NEAR(b.boundary.chatter_hz, a.boundary.chatter_hz, 0.5) << rpm;
  }
}

TEST(MillingPitch, UnevenPitchMethodsAgree) {
  // 70°/110°/70°/110°, a/D = 0.5: the full discretization (four delays) and the
  // multi-frequency method (6 harmonics of the mean tooth frequency = 24 of the spindle
  // frequency) within 0.5 %; the pitch changes the limit (by +4 % to +60 % here).
  MillingProcess even = insperger_benchmark(0.5);
  even.tool.teeth = 4;
  MillingProcess uneven = even;
  const double a = units::deg_to_rad(70.0), b = units::deg_to_rad(110.0);
  uneven.tool.pitch_rad = {a, b, a, b};
  for (double rpm : {5000.0, 9500.0}) {
    const MillingBoundary fd =
        milling_critical_depth(uneven, rpm, options(MillingMethod::kFullDiscretization, 3e-3));
    const MillingBoundary mf =
        milling_critical_depth(uneven, rpm, options(MillingMethod::kMultiFrequency, 3e-3, 6));
    const MillingBoundary ref =
        milling_critical_depth(even, rpm, options(MillingMethod::kFullDiscretization, 3e-3));
    ASSERT_TRUE(fd.boundary.found && mf.boundary.found && ref.boundary.found);
    EXPECT_NEAR(mf.boundary.depth_m, fd.boundary.depth_m, 5e-3 * fd.boundary.depth_m) << rpm;
    EXPECT_NEAR(mf.boundary.chatter_hz, fd.boundary.chatter_hz, 1.0) << rpm;
    EXPECT_GT(fd.boundary.depth_m, 1.02 * ref.boundary.depth_m) << rpm;
  }
}

TEST(MillingLobes, UnstableIslandAtLowImmersionIsNotSkipped) {
  // a/D = 0.05, one direction, 10 900 rpm: a flip lobe and a Hopf lobe overlap so that the
  // process is unstable in a band near 1.7–2.0 mm, stable above it up to about 4.5 mm.
  // The search (16 coarse depths to 10 mm, then Brent) must return the island's lower edge,
  // as a fine scan of 400 depths (second method) shows it.
  const MillingProcess m = insperger_benchmark(0.05, false);
  const double rpm = 10900.0, depth_max = 10e-3;
  const DelayedSystem s = milling_system(m, rpm);
  FdOptions o;
  o.depth_max_m = depth_max;
  const FdDiscretization fd(s, o);
  std::vector<double> changes;  // depths where stability changes, from a fine scan
  bool unstable = false;
  constexpr int kFine = 400;
  for (int i = 1; i <= kFine; ++i) {
    const double w = depth_max * i / kFine;
    const bool u = fd.spectral_radius_arnoldi(w).value >= 1.0;
    if (u != unstable) changes.push_back(w);
    unstable = u;
  }
  ASSERT_GE(changes.size(), 3u) << "no island at this speed";
  EXPECT_LT(changes[1] - changes[0], 0.5e-3);  // a narrow unstable band ...
  EXPECT_GT(changes[2] - changes[1], 1.5e-3);  // ... below a wide stable one
  const CriticalDepth c = fd_critical_depth_by_radius(s, o, RadiusSolver::kArnoldi, 1e-4, 16);
  ASSERT_TRUE(c.found);
  EXPECT_GT(c.depth_m, changes[0] - depth_max / kFine);
  EXPECT_LE(c.depth_m, changes[0]);
}

TEST(MillingLobes, TurningIsTheSpecialCaseOfTheSameMachinery) {
  // The solver the milling lobes use (period map, Arnoldi radius, coarse scan and Brent) on
  // the turning system of table 2 of [Chikishev2018] (one mode, constant coefficient): the
  // critical depth agrees with Tlusty's closed form to 0.5 % (the step error is about 0.1 %).
  const TurningProcess t = testing::table2_conventional();
  for (double rpm : {2900.0, 3500.0, 4200.0, 5000.0}) {
    const DelayedSystem s = turning_system(t, rpm);
    FdOptions o;
    o.depth_max_m = 0.03;
    o.steps_per_period = static_cast<int>(std::ceil(s.delay_s * 64.0 * testing::kTable2NaturalHz));
    const CriticalDepth fd = fd_critical_depth_by_radius(s, o, RadiusSolver::kArnoldi, 1e-5, 16);
    const auto closed =
        tlusty_critical_depth(t.modal, Direction::kX, t.kf_pa, 60.0 / rpm, o.depth_max_m);
    ASSERT_TRUE(fd.found && closed.boundary.found);
    EXPECT_NEAR(fd.depth_m, closed.boundary.depth_m, 5e-3 * closed.boundary.depth_m) << rpm;
    EXPECT_NEAR(fd.chatter_hz, closed.boundary.chatter_hz, 0.5) << rpm;
  }
}

}  // namespace
}  // namespace cutdyn
