#include "cutdyn/drive/feed_drive.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <vector>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn {
namespace {

using units::kPi;
using units::kTwoPi;

Transmission lever() {
  Transmission t;
  t.kind = Transmission::Kind::kLeverArm;
  t.output_diameter_m = 0.04;
  t.ratio = 0.5;
  t.idle_torque_nm = 0.3;
  return t;
}

Transmission screw() {
  Transmission t;
  t.kind = Transmission::Kind::kBallScrew;
  t.lead_m = 0.01;
  t.efficiency = 0.9;
  t.gear_ratio = 2.0;
  t.idle_torque_nm = 0.3;
  return t;
}

// A force on the cutter against the feed (−x), so that the x axis is resisted by
// F(t) = f0 + f1·sin(ωt); n samples over `periods` periods.
struct Trace {
  std::vector<double> t, fx, fy, fz;
};
Trace sine(double f0, double f1, double omega, int periods, int per_period) {
  Trace tr;
  const int n = periods * per_period;
  for (int i = 0; i <= n; ++i) {
    const double t = kTwoPi / omega * i / per_period;
    tr.t.push_back(t);
    tr.fx.push_back(-(f0 + f1 * std::sin(omega * t)));
    tr.fy.push_back(0.0);
    tr.fz.push_back(0.0);
  }
  return tr;
}

TEST(FeedDrive, LoadTorqueOfBothTransmissions) {
  // eq. 12: Mc = (d/2)·iΣ·Fn + Mc0 = 0.02·0.5·1000 + 0.3 = 10.3 N·m.
  EXPECT_NEAR(lever().load_torque(1000.0), 10.3, 1e-12);
  EXPECT_NEAR(lever().travel_per_rad(), 0.01, 1e-15);
  // Ball screw: Mc = Fn·p/(2π·η·i) + Mc0 = 1000·0.01/(2π·0.9·2) + 0.3 = 1.18419 N·m.
  EXPECT_NEAR(screw().load_torque(1000.0), 1000 * 0.01 / (kTwoPi * 0.9 * 2) + 0.3, 1e-12);
  EXPECT_NEAR(screw().load_torque(1000.0), 1.184194, 1e-6);
  EXPECT_NEAR(screw().travel_per_rad(), 0.01 / (kTwoPi * 2), 1e-15);
}

TEST(FeedDrive, TorqueRippleIsEquation14) {
  // ΔMc = ¼·d·iΣ·cos θ·(Fmax − Fmin): 0.25·0.04·0.5·cos 30°·(1500 − 500) = 4.3301 N·m.
  EXPECT_NEAR(torque_ripple(lever(), 500.0, 1500.0, kPi / 6),
              0.25 * 0.04 * 0.5 * std::cos(kPi / 6) * 1000, 1e-12);
  EXPECT_NEAR(torque_ripple(lever(), 500.0, 1500.0, kPi / 6), 4.330127, 1e-6);
  // The same from the simulated static drive, force at 30° to the axis.
  FeedAxis axis;
  axis.drive.transmission = lever();
  axis.drive.stiffness_nm_s_per_rad = -10000.0;
  axis.direction[0] = std::cos(kPi / 6);
  axis.direction[1] = std::sin(kPi / 6);
  const Trace tr = sine(1000.0, 500.0, 2 * kPi * 10, 3, 400);
  const FeedDriveResult r = simulate_feed_drive(axis, tr.t, tr.fx, tr.fy, tr.fz, 0.01);
  // The trace's force is along −x; its component against the axis is F·cos 30°.
  EXPECT_NEAR(r.torque_ripple_nm, torque_ripple(lever(), 500.0, 1500.0, kPi / 6), 1e-9);
}

TEST(FeedDrive, StaticCharacteristicSpeedDropErrorAndNonuniformity) {
  // Ω0 = v/(travel per rad) = 0.02/0.01 = 2 rad/s; |β| = 10 N·m·s/rad (a weak drive, so that
  // the numbers are large). Load Mc = 0.01·F + 0.3 with F = 100 + 50 sin ωt:
  // Mc from 0.8 to 1.8 (mean 1.3, ΔMc = 0.5) → Ω = 2 − Mc/10: Ωmax = 1.92, Ωmin = 1.82,
  // kδ = 0.10/3.74 = 0.026738, δ = 1.3/(2·10) = 6.5 %, ΔΩ = 0.05.
  FeedAxis axis;
  axis.drive.transmission = lever();
  axis.drive.stiffness_nm_s_per_rad = -10.0;
  const double omega = 2 * kPi * 5;
  const Trace tr = sine(100.0, 50.0, omega, 4, 1000);
  const FeedDriveResult r = simulate_feed_drive(axis, tr.t, tr.fx, tr.fy, tr.fz, 0.02);
  EXPECT_NEAR(r.commanded_speed_rad_s, 2.0, 1e-12);
  EXPECT_NEAR(r.mean_load_torque_nm, 1.3, 1e-3);  // sampled mean of the sine
  EXPECT_NEAR(r.torque_ripple_nm, 0.5, 1e-6);
  EXPECT_NEAR(r.speed_ripple_rad_s, 0.05, 1e-7);
  EXPECT_NEAR(r.k_delta, 0.1 / 3.74, 1e-6);
  EXPECT_EQ(r.k_delta_verdict, Verdict::kAcceptable);
  EXPECT_NEAR(r.static_error, 0.065, 1e-4);
  EXPECT_TRUE(r.static_error_ok);
  // Position error: the speed deviation −(ΔMc/|β|)·sin ωt integrates to an amplitude
  // travel·ΔMc/(|β|·ω): peak-to-peak 2·0.01·0.5/(10·ω).
  EXPECT_NEAR(r.position_error_pp_m, 2 * 0.01 * 0.5 / (10.0 * omega),
              1e-3 * 2 * 0.01 * 0.5 / (10.0 * omega));
  // A heavier load makes δ exceed 10 %: Mc = 0.01·250 + 0.3 = 2.8 → δ = 14 %.
  const Trace heavy = sine(250.0, 0.0, omega, 1, 10);
  const FeedDriveResult h = simulate_feed_drive(axis, heavy.t, heavy.fx, heavy.fy, heavy.fz, 0.02);
  EXPECT_NEAR(h.static_error, 0.14, 1e-12);
  EXPECT_FALSE(h.static_error_ok);
}

TEST(FeedDrive, NonuniformityVerdictsAtAndAroundTheThresholds) {
  EXPECT_EQ(nonuniformity_verdict(0.0), Verdict::kAcceptable);
  EXPECT_EQ(nonuniformity_verdict(0.2), Verdict::kAcceptable);
  EXPECT_EQ(nonuniformity_verdict(0.2 + 1e-12), Verdict::kMarginal);
  EXPECT_EQ(nonuniformity_verdict(0.4), Verdict::kMarginal);
  EXPECT_EQ(nonuniformity_verdict(0.4 + 1e-12), Verdict::kUnstable);
  // Through the drive: |β| chosen so that kδ lands on each side of 0.2 and 0.4.
  // Ω0 = 2, Mc = 0.01·F + 0.3, F = f0 + f1 sin: Ω = 2 − Mc/β.
  FeedAxis axis;
  axis.drive.transmission = lever();
  const Trace tr = sine(100.0, 100.0, 2 * kPi, 1, 400);  // Mc from 0.3 to 2.3
  for (const auto& [beta, verdict] :
       {std::pair{20.0, Verdict::kAcceptable},  // kδ = 0.1/1.935 = 0.052
        std::pair{3.0, Verdict::kMarginal},     // 0.333/1.567 = 0.213
        std::pair{1.2, Verdict::kUnstable}}) {  // 0.833/1.0 = 0.83
    axis.drive.stiffness_nm_s_per_rad = beta;
    const FeedDriveResult r = simulate_feed_drive(axis, tr.t, tr.fx, tr.fy, tr.fz, 0.02);
    const double wmax = 2 - 0.3 / beta, wmin = 2 - 2.3 / beta;
    EXPECT_NEAR(r.k_delta, (wmax - wmin) / (wmax + wmin), 1e-9) << beta;
    EXPECT_EQ(r.k_delta_verdict, verdict) << beta << " kδ " << r.k_delta;
  }
}

// The PI drive's response to a load: with e = Ω0 − Ω, J·ë + (Kp + b)·ė + Ki·e = dMc/dt.
struct PiDrive {
  double J = 2e-3, kp = 0.2, ki = 40.0, b = 0.0;
};

FeedAxis dynamic_axis(const PiDrive& p) {
  FeedAxis axis;
  axis.drive.transmission = lever();
  axis.drive.model = FeedDrive::Model::kDynamic;
  axis.drive.inertia_kg_m2 = p.J;
  axis.drive.kp_nm_s_per_rad = p.kp;
  axis.drive.ki_nm_per_rad = p.ki;
  axis.drive.viscous_nm_s_per_rad = p.b;
  return axis;
}

TEST(FeedDrive, DynamicDriveLoadStepMatchesTheAnalyticResponse) {
  // A load step ΔM at t1 from the steady state: ė(t1) = ΔM/J, e(t1) = 0, so
  // e(t) = ΔM/(J·ωd)·e^(−σs)·sin(ωd·s), s = t − t1, σ = Kp/(2J), ωd = √(Ki/J − σ²).
  // The load is linear between samples, so the step is a ramp over a first interval of 1 ns.
  const PiDrive p;
  const FeedAxis axis = dynamic_axis(p);
  const double force_step = 200.0;  // N → ΔM = 0.01·200 = 2 N·m
  const double dm = 0.01 * force_step, t1 = 1e-9;
  Trace tr;
  tr.t.push_back(0.0);
  tr.fx.push_back(0.0);
  for (int i = 0; i <= 4000; ++i) {
    tr.t.push_back(t1 + i * 5e-5);
    tr.fx.push_back(-force_step);
  }
  tr.fy.assign(tr.t.size(), 0.0);
  tr.fz.assign(tr.t.size(), 0.0);
  const FeedDriveResult r = simulate_feed_drive(axis, tr.t, tr.fx, tr.fy, tr.fz, 0.02, false);
  const double sigma = p.kp / (2 * p.J), wd = std::sqrt(p.ki / p.J - sigma * sigma);
  const double scale = dm / (p.J * wd);
  double worst = 0.0;
  for (std::size_t i = 1; i < tr.t.size(); ++i) {
    const double s = tr.t[i] - t1;
    const double e = scale * std::exp(-sigma * s) * std::sin(wd * s);
    worst = std::max(worst, std::abs((2.0 - r.speed_rad_s[i]) - e));
  }
  EXPECT_LT(worst, 1e-6 * scale);  // RK4, and the 1 ns ramp: ΔM·1e-9/(2J) ≈ 5e-7
  EXPECT_GT(scale, 0.1);           // a real excursion: 0.12 rad/s
}

TEST(FeedDrive, DynamicRippleFollowsTheLoopsFrequencyResponse) {
  // Load ripple M1·sin ωt: speed ripple amplitude |ω·M1/(Ki − J·ω² + i·(Kp + b)·ω)|; the
  // static characteristic would give a frequency-independent M1/|β|.
  const PiDrive p{2e-3, 0.2, 40.0, 0.01};
  const FeedAxis axis = dynamic_axis(p);
  for (double hz : {2.0, 20.0, 200.0}) {
    const double w = kTwoPi * hz;
    const Trace tr = sine(100.0, 50.0, w, 40, 200);
    const FeedDriveResult r = simulate_feed_drive(axis, tr.t, tr.fx, tr.fy, tr.fz, 0.02);
    // The last 10 periods (transients gone): half the range of Ω.
    double lo = 1e300, hi = -1e300;
    for (std::size_t i = tr.t.size() - 2000; i < tr.t.size(); ++i) {
      lo = std::min(lo, r.speed_rad_s[i]);
      hi = std::max(hi, r.speed_rad_s[i]);
    }
    const double m1 = 0.01 * 50.0;
    const double expected =
        std::abs(w * m1 / std::complex<double>(p.ki - p.J * w * w, (p.kp + p.b) * w));
    EXPECT_NEAR(0.5 * (hi - lo), expected, 0.01 * expected) << hz << " Hz";
  }
}

TEST(FeedDrive, TorqueLimitHoldsAndRejectsBadInput) {
  PiDrive p;
  FeedAxis axis = dynamic_axis(p);
  axis.drive.torque_limit_nm = 1.5;  // below the 2.3 N·m the load needs at its peak
  const Trace tr = sine(100.0, 100.0, kTwoPi * 2, 4, 500);
  const FeedDriveResult r = simulate_feed_drive(axis, tr.t, tr.fx, tr.fy, tr.fz, 0.02);
  for (double te : r.motor_torque_nm) EXPECT_LE(std::abs(te), 1.5 + 1e-12);
  EXPECT_GT(r.speed_ripple_rad_s, 1.0);  // the drive is dragged down while saturated
  // Bad input names every problem.
  FeedAxis bad;
  bad.drive.transmission.lead_m = -1.0;
  bad.direction[0] = 2.0;
  const std::vector<double> t{0.0, 0.0}, f{1.0, 1.0};
  try {
    simulate_feed_drive(bad, t, f, f, f, 0.01);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    const std::string all = e.what();
    EXPECT_NE(all.find("lead_m"), std::string::npos) << all;
    EXPECT_NE(all.find("stiffness_nm_s_per_rad"), std::string::npos) << all;
    EXPECT_NE(all.find("direction"), std::string::npos) << all;
  }
}

}  // namespace
}  // namespace cutdyn
