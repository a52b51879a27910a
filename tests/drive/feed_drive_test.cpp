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

TEST(FeedDrive, BackDrivenBallScrewUsesTheBackDrivingEfficiency) {
  // An aiding force (Fn < 0, e.g. down-milling pulling the table) back-drives the screw: the
  // torque it gives the motor is Fn·p·η'/(2π·i) with η' = 2 − 1/η, not Fn·p/(2π·η·i).
  // η = 0.9: η' = 0.888889; Fn = −1000 N, p = 10 mm, i = 2:
  // Mc = −1000·0.01·0.888889/(4π) + 0.3 = −0.707355 + 0.3 = −0.407355 N·m
  // (dividing by η gave −0.884194 + 0.3: 25 % more aiding torque, 1/(η·η') = 1.25).
  const Transmission t = screw();
  EXPECT_NEAR(t.back_driving_efficiency(), 2.0 - 1.0 / 0.9, 1e-15);
  EXPECT_NEAR(t.load_torque(-1000.0), -1000 * 0.01 * (2.0 - 1.0 / 0.9) / (kTwoPi * 2) + 0.3,
              1e-12);
  EXPECT_NEAR(t.load_torque(-1000.0), -0.407355, 1e-6);
  EXPECT_NEAR(t.torque_per_newton(-1.0) / t.torque_per_newton(1.0), 0.9 * (2.0 - 1.0 / 0.9),
              1e-12);
  // A resisting force still divides by η; the lever form has no losses either way.
  EXPECT_NEAR(t.load_torque(1000.0), 1000 * 0.01 / (kTwoPi * 0.9 * 2) + 0.3, 1e-12);
  EXPECT_NEAR(lever().load_torque(-1000.0), -0.02 * 0.5 * 1000 + 0.3, 1e-12);
  // A self-locking screw (η < 0.5, η' < 0): the motor must still drive an aiding load.
  Transmission locking = screw();
  locking.efficiency = 0.4;
  EXPECT_GT(locking.load_torque(-1000.0) - locking.idle_torque_nm, 0.0);
  // Through the drive: a force on the cutter along +x aids the x axis; the load trace uses η'.
  FeedAxis axis;
  axis.drive.transmission = t;
  axis.drive.stiffness_nm_s_per_rad = -100.0;
  const std::vector<double> time{0.0, 1e-3}, fx{1000.0, 1000.0}, zero{0.0, 0.0};
  const FeedDriveResult r = simulate_feed_drive(axis, time, fx, zero, zero, 0.01);
  EXPECT_NEAR(r.load_torque_nm[0], -0.407355, 1e-6);
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
  // kδ = 2·0.10/3.74 = 0.053476 (eq. 1, range over mean), δ = 1.3/(2·10) = 6.5 %, ΔΩ = 0.05.
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
  EXPECT_NEAR(r.k_delta, 0.2 / 3.74, 1e-6);
  EXPECT_NEAR(r.k_delta, 0.053476, 1e-6);
  EXPECT_EQ(r.k_delta_verdict, Verdict::kAcceptable);
  EXPECT_NEAR(r.static_error, 0.065, 1e-4);
  EXPECT_NEAR(r.mean_speed_rad_s, 2.0 - 1.3 / 10.0, 1e-9);  // the time average
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

TEST(FeedDrive, NonuniformityIsRangeOverMeanAsEquationOnePrintsIt) {
  // Hand cases of eq. 1, kδ = 2(Ωmax − Ωmin)/(Ωmax + Ωmin): 110/90 rad/s → 2·20/200 = 0.2;
  // 12/8 → 2·4/20 = 0.4; 1/0 (stalls) → 2; a constant speed → 0.
  EXPECT_DOUBLE_EQ(nonuniformity(90.0, 110.0), 0.2);
  EXPECT_DOUBLE_EQ(nonuniformity(8.0, 12.0), 0.4);
  EXPECT_DOUBLE_EQ(nonuniformity(0.0, 1.0), 2.0);
  EXPECT_DOUBLE_EQ(nonuniformity(5.0, 5.0), 0.0);
  EXPECT_DOUBLE_EQ(nonuniformity(-3.0, 1.0), 2.0);  // no forward mean: beyond every limit
  // The case that was reported wrongly: a half-range kδ of 0.207 ("marginal") is 0.413 by eq. 1,
  // beyond 0.4.
  const double wmin = 1.0, wmax = wmin * (1 + 0.207) / (1 - 0.207);
  EXPECT_NEAR((wmax - wmin) / (wmax + wmin), 0.207, 1e-12);
  EXPECT_NEAR(nonuniformity(wmin, wmax), 0.414, 1e-12);
  EXPECT_EQ(nonuniformity_verdict(nonuniformity(wmin, wmax)), Verdict::kBeyondLimit);
  // A speed trace with known extremes through the static drive: Ω0 = 2, Mc = 0.01·F + 0.3,
  // F = 150 ± 50 → Mc 1.3 … 2.3, |β| = 5: Ω from 1.54 to 1.74, kδ = 2·0.2/3.28 = 0.121951.
  FeedAxis axis;
  axis.drive.transmission = lever();
  axis.drive.stiffness_nm_s_per_rad = -5.0;
  const Trace tr = sine(150.0, 50.0, 2 * kPi, 1, 400);
  const FeedDriveResult r = simulate_feed_drive(axis, tr.t, tr.fx, tr.fy, tr.fz, 0.02);
  EXPECT_NEAR(r.k_delta, 0.121951, 1e-6);
  EXPECT_EQ(r.k_delta_verdict, Verdict::kAcceptable);
}

TEST(FeedDrive, NonuniformityVerdictsAtAndAroundTheThresholds) {
  EXPECT_EQ(nonuniformity_verdict(0.0), Verdict::kAcceptable);
  EXPECT_EQ(nonuniformity_verdict(0.2), Verdict::kAcceptable);
  EXPECT_EQ(nonuniformity_verdict(0.2 + 1e-12), Verdict::kMarginal);
  EXPECT_EQ(nonuniformity_verdict(0.4), Verdict::kMarginal);
  EXPECT_EQ(nonuniformity_verdict(0.4 + 1e-12), Verdict::kBeyondLimit);
  // The verdict says what the limit means: the linear model cannot go unstable.
  EXPECT_STREQ(to_string(Verdict::kBeyondLimit), "beyond-limit");
  EXPECT_STREQ(describe(Verdict::kBeyondLimit),
               "non-uniform beyond the source's 0.4 limit for regulated drives");
  // Through the drive: |β| chosen so that kδ lands on each side of 0.2 and 0.4.
  // Ω0 = 2, Mc = 0.01·F + 0.3, F = f0 + f1 sin: Ω = 2 − Mc/β.
  FeedAxis axis;
  axis.drive.transmission = lever();
  const Trace tr = sine(100.0, 100.0, 2 * kPi, 1, 400);  // Mc from 0.3 to 2.3
  for (const auto& [beta, verdict] :
       {std::pair{20.0, Verdict::kAcceptable},    // kδ = 2·0.1/3.87 = 0.052
        std::pair{4.0, Verdict::kMarginal},       // 2·0.5/3.35 = 0.299
        std::pair{3.0, Verdict::kBeyondLimit},    // 2·0.667/3.133 = 0.426 (half of it: 0.213)
        std::pair{2.5, Verdict::kBeyondLimit}}) {  // 2·0.8/2.96 = 0.54
    axis.drive.stiffness_nm_s_per_rad = beta;
    const FeedDriveResult r = simulate_feed_drive(axis, tr.t, tr.fx, tr.fy, tr.fz, 0.02);
    const double wmax = 2 - 0.3 / beta, wmin = 2 - 2.3 / beta;
    EXPECT_NEAR(r.k_delta, 2 * (wmax - wmin) / (wmax + wmin), 1e-9) << beta;
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

TEST(FeedDrive, LoadLagIsTheIntegratorsShareOfTheLoad) {
  // The motor's lag behind its programmed angle z = ∫(Ω0 − Ω)dt obeys
  // J·z̈ + (Kp + b)·ż + Ki·z = Mc + b·Ω0, so under a load M̄ + M1·sin ωt the table lags by
  // travel·[(M̄ − Mc0)/Ki + M1/|Ki − J·ω² + i(Kp + b)·ω|] at most (the idle motion's share
  // (Mc0 + b·Ω0)/Ki removed). Against that closed form at three frequencies; the static
  // characteristic has no such bounded lag (it drifts: δ).
  const PiDrive p{2e-3, 0.2, 40.0, 0.01};
  const FeedAxis axis = dynamic_axis(p);
  const double travel = axis.drive.transmission.travel_per_rad();  // 0.01 m/rad
  for (double hz : {2.0, 20.0, 200.0}) {
    const double w = kTwoPi * hz;
    const Trace tr = sine(100.0, 50.0, w, 40, 200);
    const FeedDriveResult r =
        simulate_feed_drive(axis, tr.t, tr.fx, tr.fy, tr.fz, 0.02, true, {kTwoPi / w});
    ASSERT_TRUE(r.load_lag_max_m);
    ASSERT_EQ(r.load_lag_m.size(), tr.t.size());
    const double m1 = 0.01 * 50.0, mean = 0.01 * 100.0;  // Mc0 = 0.3 is idle
    const double ripple = m1 / std::abs(std::complex<double>(p.ki - p.J * w * w, (p.kp + p.b) * w));
    const double expected = travel * (mean / p.ki + ripple);
    EXPECT_NEAR(*r.load_lag_max_m, expected, 1e-3 * expected) << hz << " Hz";
  }
  FeedAxis fixed = dynamic_axis(p);
  fixed.drive.model = FeedDrive::Model::kStatic;
  fixed.drive.stiffness_nm_s_per_rad = 10.0;
  const Trace tr = sine(100.0, 50.0, kTwoPi * 20.0, 40, 200);
  const FeedDriveResult r = simulate_feed_drive(fixed, tr.t, tr.fx, tr.fy, tr.fz, 0.02);
  EXPECT_FALSE(r.load_lag_max_m);
  EXPECT_TRUE(r.load_lag_m.empty());
}

// A load that starts away from its mean, so that the drive has a start-up transient:
// F = f0 + f1·cos ωt (the first sample at f0 + f1).
Trace cosine(double f0, double f1, double omega, int periods, int per_period) {
  Trace tr = sine(f0, f1, omega, periods, per_period);
  for (std::size_t i = 0; i < tr.t.size(); ++i) tr.fx[i] = -(f0 + f1 * std::cos(omega * tr.t[i]));
  return tr;
}

TEST(FeedDrive, PonlyLoopSummariesAreOfTheDetectedSteadyState) {
  // P-only loop (Ki = 0): J·dΩ/dt = Kp·(Ω0 − Ω) − Mc − b·Ω, Mc = 0.01·F + 0.3 = 1.3 + 0.5 cos ωt.
  // Periodic steady state: Ω̄ = (Kp·Ω0 − 1.3)/(Kp + b) = 0.7/1.01 = 0.693069 (65 % below
  // Ω0 = 2: δ = 0.653465), ripple amplitude 0.5/|Kp + b + iJω| = 0.078569 at 20 Hz,
  // kδ = 2·2A/(2Ω̄) = 0.226727. Started at the equilibrium of the first sample's load (1.8 N·m),
  // the speed falls from 0.198 with the time constant J/(Kp + b) = 49.5 ms, one forcing period.
  const PiDrive p{0.05, 1.0, 0.0, 0.01};
  const FeedAxis axis = dynamic_axis(p);
  const double w = kTwoPi * 20.0, period = 1.0 / 20.0;
  const Trace tr = cosine(100.0, 50.0, w, 20, 200);
  SteadyStateOptions steady;
  steady.period_s = period;
  const FeedDriveResult r =
      simulate_feed_drive(axis, tr.t, tr.fx, tr.fy, tr.fz, 0.02, false, steady);
  const double mean = 0.7 / 1.01;
  const double amplitude = 0.5 / std::abs(std::complex<double>(1.01, p.J * w));
  EXPECT_TRUE(r.steady_checked);
  EXPECT_TRUE(r.steady);
  EXPECT_TRUE(r.warnings.empty());
  // The transient (e^(−t/49.5 ms) from 0.5 rad/s) is within 1 % of the ripple's peak-to-peak
  // after about 6 periods; the detection waits for it, and not for much longer.
  EXPECT_GE(r.steady_from_s, 3 * period);
  EXPECT_LE(r.steady_from_s, 12 * period);
  EXPECT_GE(r.steady_periods, 8);
  // The tolerance bounds each extreme by 1 % of the peak-to-peak: 2 % of the amplitude.
  EXPECT_NEAR(r.mean_speed_rad_s, mean, 0.02 * amplitude);
  EXPECT_NEAR(r.speed_ripple_rad_s, amplitude, 0.02 * amplitude);
  EXPECT_NEAR(r.k_delta, 2 * amplitude / mean, 0.05 * 2 * amplitude / mean);
  EXPECT_NEAR(r.static_error, 1.0 - mean / 2.0, 1e-3);
  EXPECT_FALSE(r.static_error_ok);  // the P-only loop keeps 65 % of speed error
  EXPECT_EQ(r.k_delta_verdict, Verdict::kMarginal);
  // A long run (300 periods, the last 10 summarised by hand) agrees.
  const Trace long_tr = cosine(100.0, 50.0, w, 300, 200);
  const FeedDriveResult l =
      simulate_feed_drive(axis, long_tr.t, long_tr.fx, long_tr.fy, long_tr.fz, 0.02, false);
  double lo = 1e300, hi = -1e300;
  for (std::size_t i = long_tr.t.size() - 2001; i < long_tr.t.size(); ++i) {
    lo = std::min(lo, l.speed_rad_s[i]);
    hi = std::max(hi, l.speed_rad_s[i]);
  }
  EXPECT_NEAR(0.5 * (hi - lo), amplitude, 1e-4 * amplitude);  // the long run is the analytic one
  EXPECT_NEAR(r.speed_ripple_rad_s, 0.5 * (hi - lo), 0.02 * amplitude);
  // Without the period the summary is of the whole run, transient included, and says so.
  const FeedDriveResult whole = simulate_feed_drive(axis, tr.t, tr.fx, tr.fy, tr.fz, 0.02, false);
  EXPECT_FALSE(whole.steady_checked);
  ASSERT_EQ(whole.warnings.size(), 1u);
  EXPECT_NE(whole.warnings[0].find("steady state not checked"), std::string::npos);
  EXPECT_GT(whole.speed_ripple_rad_s, 2.5 * amplitude);  // the former ±0.60 against ±0.17
}

TEST(FeedDrive, SoftPiLoopSummariesAreOfTheDetectedSteadyStateOrWarn) {
  // A soft PI loop (loop frequency √(Ki/J) = 7.1 Hz, decay σ = Kp/(2J) = 5 /s) under a 20 Hz
  // load ripple M1 = 0.05 N·m: speed ripple ω·M1/|Ki − Jω² + i·Kp·ω| = 0.226854 rad/s about
  // Ω0 = 2 (the integrator removes the mean error): kδ = 2·2A/(2·Ω0) = 0.226854. The start at
  // the first sample's load, 0.05 N·m above the mean, rings with 0.56 rad/s decaying at 5 /s.
  const PiDrive p{2e-3, 0.02, 4.0, 0.0};
  const FeedAxis axis = dynamic_axis(p);
  const double w = kTwoPi * 20.0, period = 1.0 / 20.0;
  const double amplitude =
      std::abs(w * 0.05 / std::complex<double>(p.ki - p.J * w * w, p.kp * w));
  SteadyStateOptions steady;
  steady.period_s = period;
  const Trace tr = cosine(100.0, 5.0, w, 100, 200);
  const FeedDriveResult r =
      simulate_feed_drive(axis, tr.t, tr.fx, tr.fy, tr.fz, 0.02, false, steady);
  EXPECT_TRUE(r.steady);
  EXPECT_TRUE(r.warnings.empty());
  // 0.56·e^(−5t) < 1 % of 2A = 0.0045 needs t > 0.96 s; the geometric tail adds a little.
  EXPECT_GE(r.steady_from_s, 0.9);
  EXPECT_LE(r.steady_from_s, 2.0);
  EXPECT_NEAR(r.speed_ripple_rad_s, amplitude, 0.02 * amplitude);
  EXPECT_NEAR(r.mean_speed_rad_s, 2.0, 0.02 * amplitude);
  EXPECT_NEAR(r.static_error, 0.0, 0.01 * amplitude);
  EXPECT_NEAR(r.k_delta, 2 * amplitude / 2.0, 0.03 * amplitude);
  // The whole run's ripple is the transient's.
  const FeedDriveResult whole = simulate_feed_drive(axis, tr.t, tr.fx, tr.fy, tr.fz, 0.02, false);
  EXPECT_GT(whole.speed_ripple_rad_s, 1.5 * amplitude);
  // Eight periods (0.4 s) are not enough: the summary is of the last period, with a warning.
  const Trace short_tr = cosine(100.0, 5.0, w, 8, 200);
  const FeedDriveResult s =
      simulate_feed_drive(axis, short_tr.t, short_tr.fx, short_tr.fy, short_tr.fz, 0.02, false,
                          steady);
  EXPECT_TRUE(s.steady_checked);
  EXPECT_FALSE(s.steady);
  EXPECT_EQ(s.steady_periods, 1);
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("no periodic steady state within the run"), std::string::npos)
      << s.warnings[0];
  // Two periods cannot show it at all.
  const Trace two = cosine(100.0, 5.0, w, 2, 200);
  const FeedDriveResult t2 =
      simulate_feed_drive(axis, two.t, two.fx, two.fy, two.fz, 0.02, false, steady);
  EXPECT_FALSE(t2.steady);
  EXPECT_NE(t2.warnings[0].find("at least 3"), std::string::npos) << t2.warnings[0];
}

TEST(FeedDrive, StaticDriveIsSteadyOnceTheLoadIsPeriodic) {
  // The static characteristic has no memory: a periodic load is steady from the first period.
  FeedAxis axis;
  axis.drive.transmission = lever();
  axis.drive.stiffness_nm_s_per_rad = -10.0;
  SteadyStateOptions steady;
  steady.period_s = 0.2;
  const Trace tr = sine(100.0, 50.0, kTwoPi * 5, 6, 200);
  const FeedDriveResult r = simulate_feed_drive(axis, tr.t, tr.fx, tr.fy, tr.fz, 0.02, true,
                                                steady);
  EXPECT_TRUE(r.steady);
  EXPECT_NEAR(r.steady_from_s, 0.0, 1e-9);
  EXPECT_EQ(r.steady_periods, 6);
  EXPECT_NEAR(r.k_delta, 0.2 / 3.74, 1e-6);
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
