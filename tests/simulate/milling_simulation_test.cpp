#include "cutdyn/simulate/milling_simulation.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <tuple>
#include <vector>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/simulate/detail/modal_stepper.hpp"
#include "cutdyn/stability/milling.hpp"
#include "support/reference_cases.hpp"

namespace cutdyn {
namespace {

using units::kPi;

// A force-only study (no regeneration, rigid cutter): mechanistic law, no edge terms.
MillingCut force_study(int teeth, double entry, double exit) {
  MillingCut c;
  c.process.tool.teeth = teeth;
  c.process.tool.diameter_m = 0.02;
  c.process.engagement.entry_rad = entry;
  c.process.engagement.exit_rad = exit;
  c.spindle_rad_s = units::rpm_to_rad_per_s(3000.0);
  c.feed_per_tooth_m = 0.1e-3;
  c.width_m = 2e-3;
  c.process.cutting = MechanisticForceLaw{6e8, 2e8, 0.0, 0.0};
  c.regenerative = false;
  return c;
}

// `revolutions` with every step recorded (up to 100 000) and the last revolution summarised.
MillingSimulationOptions recorded_run(double revolutions, int steps_per_tooth) {
  MillingSimulationOptions o;
  o.revolutions = revolutions;
  o.summary_revolutions = 1;
  o.steps_per_tooth = steps_per_tooth;
  o.max_recorded_samples = 100000;
  return o;
}

MillingSimulationOptions short_run() {
  MillingSimulationOptions o;
  o.revolutions = 3;
  o.summary_revolutions = 1;
  return o;
}

// The progress hook: a hundred reports in order, and a throw from it stops the run there.
TEST(MillingSimulation, ReportsProgressAndStopsWhenTheReportThrows) {
  const MillingCut cut = force_study(2, 0.0, kPi / 2);
  std::vector<int> done;
  MillingSimulationOptions o = short_run();
  o.progress = [&](int d, int total) {
    EXPECT_EQ(total, 100);
    done.push_back(d);
  };
  const MillingSimulationResult whole = simulate_milling(cut, o);
  ASSERT_EQ(done.size(), 100u);
  for (int k = 0; k < 100; ++k) EXPECT_EQ(done[static_cast<std::size_t>(k)], k);
  struct Stop {};
  int calls = 0;
  o.progress = [&](int d, int) {
    ++calls;
    if (d == 10) throw Stop{};
  };
  EXPECT_THROW(simulate_milling(cut, o), Stop);
  EXPECT_EQ(calls, 11);
  o.progress = nullptr;  // and the hook does not change the result
  EXPECT_EQ(simulate_milling(cut, o).force_n, whole.force_n);
}

TEST(MillingSimulation, UniformCutHasNoForcePulsation) {
  // [Ermolaev2020] eq. 6: with B·z·tanβ/(π·d) = q an integer the flute covers q pitches and the
  // total force of the mechanistic law without edge terms is constant (ΔP < 1e-3, here to
  // rounding); for q = 0.5 and 1.3 it pulsates clearly. Four teeth, d = 20 mm, β = 30°, quarter
  // immersion (up-milling), so that the teeth's windows do not overlap.
  for (double q : {1.0, 2.0, 0.5, 1.3}) {
    MillingCut c = force_study(4, 0.0, 0.5 * kPi);
    c.process.tool.helix_rad = units::deg_to_rad(30.0);
    c.width_m = q * kPi * c.process.tool.diameter_m /
                (c.process.tool.teeth * std::tan(c.process.tool.helix_rad));
    const MillingSimulationResult r = simulate_milling(c, short_run());
    if (q == 1.0 || q == 2.0)
      EXPECT_LT(r.force_pulsation, 1e-3) << "q " << q;
    else
      EXPECT_GT(r.force_pulsation, 0.1) << "q " << q;
    EXPECT_NEAR(r.mean_teeth_in_cut, 1.0, 1e-9) << "q " << q;  // z·ψ/2π
  }
}

TEST(MillingSimulation, PulsationIsFullBelowOneToothInCutAndFallsWithTeethAndAngle) {
  // [Ermolaev2020] fig. 6b: straight teeth, down-milling with contact angle ψ. While the mean
  // number of teeth in cut z·ψ/2π is below one there are instants with no tooth in cut: ΔP = 100 %.
  // Above, ΔP falls as z grows (compared at z and 2z) and as ψ grows at fixed z.
  double previous_at_z8 = 2.0;
  for (double psi_deg : {60.0, 90.0, 120.0, 150.0}) {
    const double psi = units::deg_to_rad(psi_deg);
    const auto pulsation = [&](int z) {
      const MillingSimulationResult r =
          simulate_milling(force_study(z, kPi - psi, kPi), short_run());
      EXPECT_NEAR(r.mean_teeth_in_cut, z * psi / (2 * kPi), 0.02) << "z " << z;
      return r.force_pulsation;
    };
    for (int z = 1; z * psi < 2 * kPi - 1e-9; ++z)
      EXPECT_NEAR(pulsation(z), 1.0, 1e-12) << "psi " << psi_deg << " z " << z;
    const int z1 = static_cast<int>(std::ceil(2 * kPi / psi + 1e-9));
    EXPECT_LT(pulsation(2 * z1), pulsation(z1)) << "psi " << psi_deg;
    const double at_z8 = pulsation(8);
    EXPECT_LT(at_z8, previous_at_z8) << "psi " << psi_deg;
    previous_at_z8 = at_z8;
  }
}

TEST(MillingSimulation, ClosedFormHelixAgreesWithSlicesWhenEverySliceIsInCut) {
  // [Ermolaev2020] eqs. 8–9 average the force direction over the flute's lag with the leading
  // section's chip and window. With a force that does not depend on the chip (edge coefficients
  // only) the two forms agree at every instant when each tooth's slices are all in or all out of
  // the window. Slotting, 2 teeth, lag 20°.
  MillingCut c = force_study(2, 0.0, kPi);
  c.process.cutting = MechanisticForceLaw{0.0, 0.0, 2e4, 1e4};
  c.process.tool.helix_rad = units::deg_to_rad(30.0);
  c.width_m = units::deg_to_rad(20.0) * c.process.tool.diameter_m /
              (2.0 * std::tan(c.process.tool.helix_rad));
  MillingSimulationOptions o = short_run();
  o.max_recorded_samples = 1000000;  // every step
  const MillingSimulationResult slices = simulate_milling(c, o);
  o.closed_form_helix = true;
  const MillingSimulationResult closed = simulate_milling(c, o);
  ASSERT_EQ(slices.time_s.size(), closed.time_s.size());
  // The slices are the midpoint rule of that average: error at most δ²/24 of the force, δ the
  // slice lag; allowance twice that.
  const double lag = c.lag_angle();
  const double delta = lag / slices.slices;
  const double tol = delta * delta / 12.0;
  const double scale = std::hypot(2e4, 1e4) * c.width_m;  // |edge force| of one tooth
  EXPECT_GT(slices.slices, 10);
  int compared = 0;
  for (std::size_t i = 0; i < slices.time_s.size(); ++i) {
    // Tooth tips at θ and θ + π: every slice of each tooth in or out when θ mod π lies in
    // (lag, π), away from the step's rounding.
    const double theta = std::fmod(c.spindle_rad_s * slices.time_s[i], kPi);
    if (theta < lag + 1e-6 || theta > kPi - 1e-6) continue;
    EXPECT_NEAR(slices.fx_n[i], closed.fx_n[i], tol * scale) << i;
    EXPECT_NEAR(slices.fy_n[i], closed.fy_n[i], tol * scale) << i;
    ++compared;
  }
  EXPECT_GT(compared, static_cast<int>(slices.time_s.size()) / 2);
}

TEST(MillingSimulation, S1LawWithoutLagAndContactIsTheMechanisticLaw) {
  // c = B·√(Kt² + Kr²) at φrez = atan(Kr/Kt), T2 = 0, P0 = 0: the same force at every step,
  // with regeneration and a helix (docs/models/milling-simulation.md, force frame decision).
  MillingCut mech = force_study(3, 0.3, kPi);
  mech.process.modal = testing::insperger_benchmark(1.0).modal;
  mech.regenerative = true;
  mech.process.tool.helix_rad = units::deg_to_rad(30.0);
  mech.width_m = 0.05e-3;
  MillingCut s1 = mech;
  s1.process.s1_law = ErmolaevForceLaw{
      mech.width_m * std::hypot(6e8, 2e8), 0.0, 0.0, 1.0, std::atan2(2e8, 6e8), 0.0};
  MillingSimulationOptions o = short_run();
  o.max_recorded_samples = 1000000;
  const MillingSimulationResult a = simulate_milling(mech, o), b = simulate_milling(s1, o);
  ASSERT_EQ(a.fx_n.size(), b.fx_n.size());
  double scale = 0.0;
  for (double f : a.force_n) scale = std::max(scale, f);
  for (std::size_t i = 0; i < a.fx_n.size(); ++i) {
    ASSERT_NEAR(a.fx_n[i], b.fx_n[i], 1e-9 * scale) << i;
    ASSERT_NEAR(a.fy_n[i], b.fy_n[i], 1e-9 * scale) << i;
  }
}

TEST(MillingSimulation, ZeroOrderHoldStepIsTheExactFreeVibration) {
  // One mode in x, released from x0 at rest: x(t) = x0·e^(−ζωt)(cos ωd·t + ζ/√(1−ζ²)·sin ωd·t).
  ModalModel m;
  const double wn = 2 * kPi * 500.0, zeta = 0.03, k = 2e7;
  m.modes.push_back(Mode{Direction::kX, wn, zeta, k});
  const double h = 1.3e-5;
  const ModalStepper stepper(m, {Direction::kX}, h);
  Eigen::VectorXd x = stepper.static_state(Eigen::VectorXd::Constant(1, 1e-3 * k));
  const double x0 = stepper.output(x)(0);
  EXPECT_NEAR(x0, 1e-3, 1e-15);
  const double wd = wn * std::sqrt(1 - zeta * zeta);
  for (int n = 1; n <= 2000; ++n) {
    stepper.step(x, Eigen::VectorXd::Zero(1));
    const double t = n * h;
    const double exact = x0 * std::exp(-zeta * wn * t) *
                         (std::cos(wd * t) + zeta / std::sqrt(1 - zeta * zeta) * std::sin(wd * t));
    ASSERT_NEAR(stepper.output(x)(0), exact, 1e-9 * x0) << "step " << n;
  }
}

// The simulation of `model` at `factor` × the full discretization's critical depth.
MillingSimulationResult at_factor(const MillingProcess& m, double rpm, double critical,
                                  double factor, MillingSimulationOptions o) {
  return testing::simulate_model(m, rpm, factor * critical, o);
}

// The runs of the lobe confirmations: 100 revolutions, summary over the last 5.
MillingSimulationOptions long_run() {
  MillingSimulationOptions o;
  o.revolutions = 100;
  o.summary_revolutions = 5;
  return o;
}

TEST(MillingSimulation, ConfirmsTheLobesAtThreeSpeeds) {
  // The milling-stability default (Insperger–Stépán slotting, both directions): at three
  // speeds the simulation with regeneration is stable at 0.9× the full discretization's
  // critical depth and chatters at 1.1×.
  const MillingProcess m = testing::insperger_benchmark(1.0);
  for (double rpm : {6000.0, 10000.0, 18000.0}) {
    MillingStabilityOptions so;
    so.depth_max_m = 1e-3;
    so.rel_tol = 1e-5;
    const double critical = milling_critical_depth(m, rpm, so).boundary.depth_m;
    for (double factor : {0.9, 1.1}) {
      const MillingSimulationResult r = at_factor(m, rpm, critical, factor, long_run());
      EXPECT_EQ(r.chatter, factor > 1.0)
          << rpm << " rpm, " << factor << "× critical: indicator " << r.chatter_indicator
          << ", growth " << r.growth_per_period;
    }
  }
}

TEST(MillingSimulation, ConfirmsTheHelicalAndUnevenPitchLobes) {
  // Two independent models of the same cutters: the slices and stored surfaces of the
  // simulation against the stability model's axial slices and delay terms
  // (docs/models/milling-stability.md, "Helical cutters" and "Uneven pitch").
  // (a) 4 teeth, 45° helix, a/D = 0.5, structure 30× stiffer (critical depths of 2–18 mm, so
  //     the flute's lag matters); (b) 4 teeth, 70°/110° pitch, slotting. Stable at 0.9×, chatter
  //     at 1.1×. (With uneven pitch at partial immersion the forced vibration alone throws the
  //     teeth out of the cut near the boundary, where a linear boundary does not apply.)
  MillingProcess helical = testing::insperger_benchmark(0.5);
  helical.tool.teeth = 4;
  helical.tool.helix_rad = units::deg_to_rad(45.0);
  for (Mode& mode : helical.modal.modes) mode.stiffness_n_per_m *= 30.0;
  MillingProcess uneven = testing::insperger_benchmark(1.0);
  uneven.tool.teeth = 4;
  const double a = units::deg_to_rad(70.0), b = units::deg_to_rad(110.0);
  uneven.tool.pitch_rad = {a, b, a, b};
  for (const auto& [model, rpms, depth_max] :
       {std::tuple{helical, std::vector<double>{5000.0, 9500.0}, 0.03},
        std::tuple{uneven, std::vector<double>{7000.0}, 3e-3}}) {
    for (double rpm : rpms) {
      MillingStabilityOptions so;
      so.depth_max_m = depth_max;
      so.rel_tol = 1e-5;
      const double critical = milling_critical_depth(model, rpm, so).boundary.depth_m;
      for (double factor : {0.9, 1.1}) {
        const MillingSimulationResult r = at_factor(model, rpm, critical, factor, long_run());
        EXPECT_EQ(r.chatter, factor > 1.0)
            << (model.tool.helix_rad > 0 ? "helix " : "pitch ") << rpm << " rpm, " << factor
            << "×: indicator " << r.chatter_indicator << ", growth " << r.growth_per_period;
      }
    }
  }
}

// The depth (as a fraction of `critical`) at which the perturbation's fitted growth changes
// sign, by bisection over [0.9, 1.1]× to 1e-4; each run must call chatter exactly when the
// growth is positive.
double simulated_boundary(const MillingProcess& m, double rpm, double critical) {
  double lo = 0.9, hi = 1.1;
  for (int i = 0; i < 11; ++i) {
    const double mid = 0.5 * (lo + hi);
    const MillingSimulationResult r = at_factor(m, rpm, critical, mid, MillingSimulationOptions{});
    EXPECT_EQ(r.chatter, r.growth_per_period > 0.0) << rpm << " rpm, " << mid << "×";
    (r.growth_per_period > 0.0 ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

TEST(MillingSimulation, BoundaryIsTheFullDiscretizationsWithinOnePercent) {
  // Default settings (first-order hold of the force, 64 steps per mode period, 30
  // revolutions, growth of the perturbation from the periodic forced vibration). Against the
  // full discretization to rel_tol 1e-6: (a) one mode in x, slotting, down (the lobes give
  // 0.409 mm at 5000 rpm, 0.325 at 16 200; the zero-order-hold simulation started to grow at
  // ≈0.38 and ≈0.315, 3–7 % low); (b) a/D = 0.05 and 0.1 on their flip lobes and a Hopf lobe;
  // (c) 4 teeth, 45° helix, a/D = 0.5, structure 30× stiffer (35–44 slices). Measured: within
  // 0.72 % everywhere (0.9991–1.0019 except a/D = 0.05 at 20 000 rpm, 0.9929); tolerance 1 %.
  const MillingProcess slot = testing::insperger_benchmark(1.0, false);
  const MillingProcess low5 = testing::insperger_benchmark(0.05, false);
  const MillingProcess low10 = testing::insperger_benchmark(0.1, false);
  MillingProcess helical = testing::insperger_benchmark(0.5);
  helical.tool.teeth = 4;
  helical.tool.helix_rad = units::deg_to_rad(45.0);
  for (Mode& mode : helical.modal.modes) mode.stiffness_n_per_m *= 30.0;
  struct Case {
    const MillingProcess* model;
    double rpm;
    Bifurcation expected;
  };
  for (const Case& c :
       {Case{&slot, 5000.0, Bifurcation::kHopf}, Case{&slot, 16200.0, Bifurcation::kHopf},
        Case{&low5, 16000.0, Bifurcation::kFlip}, Case{&low5, 20000.0, Bifurcation::kHopf},
        Case{&low10, 14000.0, Bifurcation::kFlip}, Case{&low10, 18000.0, Bifurcation::kFlip},
        Case{&helical, 5000.0, Bifurcation::kHopf}, Case{&helical, 9500.0, Bifurcation::kHopf}}) {
    MillingStabilityOptions so;
    // (Above an island of flip instability the scan would find the next boundary.)
    so.depth_max_m = c.model->tool.helix_rad > 0.0 ? 0.05 : 0.02;
    so.rel_tol = 1e-6;
    const CriticalDepth fd = milling_critical_depth(*c.model, c.rpm, so).boundary;
    EXPECT_EQ(fd.bifurcation, c.expected) << c.rpm << " rpm";
    const double ratio = simulated_boundary(*c.model, c.rpm, fd.depth_m);
    EXPECT_NEAR(ratio, 1.0, 0.01) << "a/D " << c.model->engagement.radial_immersion << ", helix "
                                  << c.model->tool.helix_rad << ", " << c.rpm << " rpm: simulated "
                                  << ratio << " × the lobes' " << fd.depth_m * 1e3 << " mm";
  }
}

TEST(MillingSimulation, ZeroChipEdgesKeepTheirRegenerativeForce) {
  // At a node on a zero-chip edge of the window (θ = π in down-milling, 0 in up-milling) the
  // rigid chip is zero, and the sign of the node's own chip (its vibration alone) decided the
  // contact: half the time the node's share of the regenerative force was dropped, an O(Δt)
  // error that put the simulated boundary above the lobes by 1.8 % (a/D 0.25, down and up) and
  // 0.8 % (a/D 0.5) at 22 128 rpm, and by 1.2 % on the four-mode case at 1872 rpm (there a node
  // that rounding put a hair inside θ = π). Now the contact at an edge node is decided in the
  // window: measured within 0.03 % of the full discretization (1/512 of the shortest period).
  struct Case {
    MillingProcess model;
    double rpm;
    double tolerance;
  };
  for (const Case& c : {Case{testing::insperger_benchmark(0.25, true, true), 22128.0, 1e-3},
                        Case{testing::insperger_benchmark(0.25, true, false), 22128.0, 1e-3},
                        Case{testing::insperger_benchmark(0.5, true, true), 22128.0, 1e-3},
                        Case{testing::four_mode_milling(0.05, true), 1872.0, 2e-3}}) {
    MillingStabilityOptions so;
    so.depth_max_m = 0.03;
    so.rel_tol = 1e-7;
    so.fd.max_step_fraction = 1.0 / 512.0;
    const double critical = milling_critical_depth(c.model, c.rpm, so).boundary.depth_m;
    EXPECT_NEAR(simulated_boundary(c.model, c.rpm, critical), 1.0, c.tolerance)
        << "a/D " << c.model.engagement.radial_immersion
        << (c.model.engagement.down_milling ? " down, " : " up, ") << c.rpm << " rpm";
  }
}

TEST(MillingSimulation, RunawayGrowthStopsTheRunWithFiniteOutputs) {
  // The milling-insperger example at 10 000 rpm (lobes: 0.0715 mm) at 1 mm and 1000 mm: the
  // zero-order-hold run reached 4.9e47 µm (1 mm, "stable"), NaN in ΔP (5 mm) and inf (1000 mm).
  // Now: stopped as a runaway, chatter, every trace and summary value finite and bounded.
  const MillingProcess m = testing::insperger_benchmark(1.0);
  for (double depth : {1e-3, 5e-3, 1.0}) {
    MillingSimulationOptions o;
    o.revolutions = 100;
    o.summary_revolutions = 5;
    const MillingSimulationResult r = at_factor(m, 10000.0, depth, 1.0, o);
    EXPECT_EQ(r.status, SimulationStatus::kRunaway) << depth;
    EXPECT_TRUE(r.chatter) << depth;
    EXPECT_GT(r.stop_time_s, 0.0);
    EXPECT_LT(r.stop_time_s, 100 * 60.0 / 10000.0) << depth;
    EXPECT_NE(r.verdict().find("chatter (runaway growth, stopped at t = "), std::string::npos)
        << r.verdict();
    ASSERT_FALSE(r.time_s.empty());
    EXPECT_LE(r.time_s.back(), r.stop_time_s);
    for (const auto* trace : {&r.fx_n, &r.fy_n, &r.force_n, &r.x_m, &r.y_m, &r.teeth_in_cut})
      for (double v : *trace) ASSERT_TRUE(std::isfinite(v)) << depth;
    // 1000 × (s_z + the forced vibration) < 1 m (at 1 m of depth the forced vibration alone is
    // metres).
    if (depth < 0.01) {
      for (double v : r.x_m) ASSERT_LT(std::abs(v), 1.0) << depth;
    }
    for (double v : {r.force_pulsation, r.mean_force_n, r.peak_force_n, r.min_force_n,
                     r.vibration_pp_x_m, r.vibration_pp_y_m, r.chatter_indicator,
                     r.growth_per_period, r.growth_rate_per_s, r.contact_loss})
      EXPECT_TRUE(std::isfinite(v)) << depth;
    EXPECT_LE(r.force_pulsation, 1.0);
  }
  // Below the boundary the same run completes.
  MillingSimulationOptions o;
  o.revolutions = 100;
  const MillingSimulationResult stable = at_factor(m, 10000.0, 0.06e-3, 1.0, o);
  EXPECT_EQ(stable.status, SimulationStatus::kCompleted);
  EXPECT_FALSE(stable.chatter);
  EXPECT_EQ(stable.verdict(), "stable");
}

TEST(MillingSimulation, FirstOrderHoldStepIsExactForALinearForce) {
  // One mode, force ramping linearly from 0: x(t) = (F'/k)·(t − 2ζ/ωn + e^(−ζωn t)·(2ζ/ωn·cos
  // ωd t + (2ζ² − 1)/ωd·sin ωd t)) [the ramp response of a damped oscillator]. The
  // first-order-hold step reproduces it to rounding; a zero-order hold would lag by h/2.
  ModalModel m;
  const double wn = 2 * kPi * 500.0, zeta = 0.03, k = 2e7, rate = 1e4;  // N/s
  m.modes.push_back(Mode{Direction::kX, wn, zeta, k});
  const double h = 1.3e-5, wd = wn * std::sqrt(1 - zeta * zeta);
  const ModalStepper stepper(m, {Direction::kX}, h);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(2);
  double worst = 0.0, scale = 0.0;
  for (int n = 1; n <= 2000; ++n) {
    stepper.step_linear(x, Eigen::VectorXd::Constant(1, rate * (n - 1) * h),
                        Eigen::VectorXd::Constant(1, rate * n * h));
    const double t = n * h;
    const double exact =
        rate / k *
        (t - 2 * zeta / wn +
         std::exp(-zeta * wn * t) *
             (2 * zeta / wn * std::cos(wd * t) + (2 * zeta * zeta - 1) / wd * std::sin(wd * t)));
    worst = std::max(worst, std::abs(stepper.output(x)(0) - exact));
    scale = std::max(scale, std::abs(exact));
  }
  EXPECT_LT(worst, 1e-9 * scale);
}

TEST(MillingSimulation, ErmolaevPresetPulsationFirstFallsThenRisesWithTheLag) {
  // [Ermolaev2020] fig. 6a with the preset ermolaev2020 (five teeth, φN = π/6, s_z = 1 relative
  // unit): ΔP falls from T2 = 0 to a minimum near 0.05 s and rises above it by T2 = 0.3 s.
  const auto pulsation = [](double t2) {
    MillingCut c;
    c.process.tool.teeth = 5;
    c.process.tool.diameter_m = 1.0;
    c.width_m = 1.0;
    c.process.tool.helix_rad = std::atan(kPi / 12.0);  // φN = 2B·tanβ/d = π/6
    c.process.engagement.entry_rad = kPi / 6;
    c.process.engagement.exit_rad = kPi;
    c.spindle_rad_s = 2 * kPi;
    c.feed_per_tooth_m = 1.0;
    c.process.s1_law = ErmolaevForceLaw{25.0, t2, 3.0, 0.2, 0.0, kPi / 5};
    c.regenerative = false;
    MillingSimulationOptions o;
    o.revolutions = 6;
    o.summary_revolutions = 1;
    o.steps_per_tooth = 200;
    return simulate_milling(c, o).force_pulsation;
  };
  const double at0 = pulsation(0.0), at005 = pulsation(0.05), at03 = pulsation(0.3);
  EXPECT_LT(at005, at0);
  EXPECT_GT(at03, 2.0 * at0);
}

TEST(MillingSimulation, UnwindowedLagIsTheLaggedSineOfTheToothPath) {
  // lag_input = unwindowed ([Ermolaev2020] eqs. 3 and 5 as printed): U lags X = s_z·sin θ
  // around the whole revolution, so in the steady state it is the first-order response to a
  // sine, U = s_z·sin(θ − δ)/√(1 + (ωT2)²), tan δ = ωT2, and the cutting force ΣP of one straight
  // tooth is c·U inside the window and 0 outside — also where c·U < 0 (δ > entry). Closed form
  // against the simulation, for several T2 and windows, to 0.5 % of c·s_z (the step holds X).
  for (double t2 : {0.05, 0.2, 0.5}) {
    for (auto [entry, exit] : {std::pair{kPi / 6, kPi}, std::pair{0.0, 0.5 * kPi}}) {
      MillingCut c = force_study(1, entry, exit);
      c.spindle_rad_s = 2 * kPi;
      c.feed_per_tooth_m = 1e-3;
      c.process.s1_law = ErmolaevForceLaw{
          25e3, t2, 3.0, 0.2e-3, 0.0, kPi / 5, ErmolaevForceLaw::LagInput::kUnwindowed};
      const MillingSimulationResult r = simulate_milling(c, recorded_run(8, 4000));
      const double wt = c.spindle_rad_s * t2, delta = std::atan(wt);
      const double amplitude = 25e3 * 1e-3 / std::sqrt(1.0 + wt * wt);
      double worst = 0.0, lowest = 1e300;
      for (std::size_t i = 0; i < r.time_s.size(); ++i) {
        if (r.time_s[i] < 6.0) continue;  // steady: T2 ≤ 0.5 s, six revolutions of 1 s
        const double theta = std::fmod(c.spindle_rad_s * r.time_s[i], 2 * kPi);
        if (std::abs(theta - entry) < 1e-3 || std::abs(theta - exit) < 1e-3) continue;  // edges
        const bool in = theta > entry && theta < exit;
        const double expected = in ? amplitude * std::sin(theta - delta) : 0.0;
        worst = std::max(worst, std::abs(r.cutting_force_n[i] - expected));
        if (in) lowest = std::min(lowest, r.cutting_force_n[i]);
      }
      EXPECT_LT(worst, 5e-3 * 25.0) << "T2 " << t2 << " entry " << entry;
      if (delta > entry + 0.1) {
        EXPECT_LT(lowest, 0.0) << "T2 " << t2;  // the force reverses
      }
      // It reverses or reaches zero inside the window: ΔP of ΣP is 1 by its definition.
      EXPECT_NEAR(r.cutting_force_pulsation, 1.0, 1e-12);
    }
  }
}

TEST(MillingSimulation, ForceOnlyCutStartsOnItsPeriodicForcedVibration) {
  // A chip from the feed alone, the S1 law with a lag and an almost undamped mode (ζ = 1.6e-5,
  // 503 Hz) whose period nearly divides the revolution (2.005 periods at 15 060 rpm, where the
  // periodic start's 1/|I − Φ_T| is large): the cutter's vibration is the periodic forced one,
  // repeating every tooth period to rounding. (Before, U started from 0 and the chatter
  // perturbation was added: 40 µm of free 503 Hz vibration, 81 µm peak to peak.) Three speeds,
  // T2 fixed in angle (72°) and in time (0.2 s, a lag over hundreds of revolutions).
  const double wn = 2 * kPi * 503.29;
  for (double rpm : {15060.0, 7560.0, 6000.0}) {
    for (bool angle : {true, false}) {
      MillingCut c = force_study(5, kPi / 6, kPi);
      c.process.tool.diameter_m = 0.02;
      c.process.tool.helix_rad = units::deg_to_rad(30.0);
      c.width_m = 9.069e-3;
      c.feed_per_tooth_m = 1e-3;
      c.spindle_rad_s = units::rpm_to_rad_per_s(rpm);
      c.process.modal.modes = {Mode{Direction::kX, wn, 1.58e-5, 1e7},
                               Mode{Direction::kY, wn, 1.58e-5, 1e7}};
      ErmolaevForceLaw law{25e3, angle ? 0.0 : 0.2, 3.0, 0.2e-3, 0.0, kPi / 5};
      if (angle) law.t2_angle_rad = 0.4 * kPi;
      c.process.s1_law = law;
      const MillingSimulationResult r = simulate_milling(c, recorded_run(6, 200));
      const std::size_t n = r.x_m.size(), tooth = 200;
      double worst = 0.0;
      for (std::size_t i = n - 1000; i < n; ++i)
        worst = std::max(worst, std::abs(r.x_m[i] - r.x_m[i - tooth]));
      EXPECT_LT(worst, 1e-9 * r.vibration_pp_x_m + 1e-15) << rpm << " rpm";
      EXPECT_LT(r.chatter_indicator, 1e-6) << rpm << " rpm";
    }
  }
}

TEST(MillingSimulation, RejectsABadCutNamingEveryProblem) {
  MillingCut c = force_study(3, 1.0, 0.5);
  c.width_m = -1.0;
  c.process.tool.pitch_rad = {1.0, 1.0};
  try {
    simulate_milling(c, short_run());
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    const std::string all = e.what();
    EXPECT_NE(all.find("entry_rad"), std::string::npos) << all;
    EXPECT_NE(all.find("width_m"), std::string::npos) << all;
    EXPECT_NE(all.find("pitch_rad"), std::string::npos) << all;
  }
}

}  // namespace
}  // namespace cutdyn
