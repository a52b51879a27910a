// The sign of the motor torque (docs/models/monitor.md §1, §4.5): the signed torque current
// from the rotor angle (Park transform), and the warning without it.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cutdyn/core/units.hpp"
#include "cutdyn/drive/equivalent_current.hpp"
#include "cutdyn/monitor/force_estimator.hpp"
#include "monitor/drive_chain.hpp"

namespace cutdyn {
namespace {

using units::kTwoPi;

TEST(MonitorTorqueSign, ParkTransformGivesTheSignedCurrent) {
  // The drive library's convention iu = −Î·sin θe, iv = −Î·sin(θe − 2π/3), iw = −Î·sin(θe +
  // 2π/3): the signed current is Î (space vector) or Î/√2 (RMS), of the torque's sign, and
  // its magnitude is equivalent_current() — for 200 random angles and currents of both signs.
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> angle(-20.0, 20.0), peak(-30.0, 30.0);
  for (int k = 0; k < 200; ++k) {
    const double th = angle(rng), p = peak(rng);
    const double iu = -p * std::sin(th), iv = -p * std::sin(th - kTwoPi / 3),
                 iw = -p * std::sin(th + kTwoPi / 3);
    EXPECT_NEAR(signed_equivalent_current(iu, iv, iw, th, CurrentMeasure::kSpaceVector), p, 1e-12);
    EXPECT_NEAR(signed_equivalent_current(iu, iv, iw, th, CurrentMeasure::kRms), p / std::sqrt(2.0),
                1e-12);
    EXPECT_NEAR(std::abs(signed_equivalent_current(iu, iv, iw, th, CurrentMeasure::kRms)),
                equivalent_current(iu, iv, iw, CurrentMeasure::kRms), 1e-12);
  }
}

TEST(MonitorTorqueSign, ParkNoiseIsUnbiasedWithTheStatedSigma) {
  // White noise σ = 0.1 A per phase on a current of 0.05 A (below the noise): the signed
  // current's mean over 200 000 samples is the true one (no bias, unlike the magnitude) and
  // its scatter is equivalent_current_sigma (1 %).
  std::mt19937_64 rng(4);
  std::normal_distribution<double> g(0.0, 0.1);
  double s1 = 0, s2 = 0, mag = 0;
  const int n = 200000;
  for (int k = 0; k < n; ++k) {
    const double th = 0.001 * k, p = 0.05;
    const double iu = -p * std::sin(th) + g(rng), iv = -p * std::sin(th - kTwoPi / 3) + g(rng),
                 iw = -p * std::sin(th + kTwoPi / 3) + g(rng);
    const double i = signed_equivalent_current(iu, iv, iw, th, CurrentMeasure::kSpaceVector);
    s1 += i;
    s2 += i * i;
    mag += equivalent_current(iu, iv, iw, CurrentMeasure::kSpaceVector);
  }
  const double mean = s1 / n, sd = std::sqrt(s2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.05, 4 * 0.0816 / std::sqrt(n));
  EXPECT_NEAR(sd / equivalent_current_sigma(0.1, CurrentMeasure::kSpaceVector), 1.0, 0.01);
  EXPECT_GT(mag / n, 0.1);  // the magnitude: biased to about twice the noise σ
}

// Down-milling at 600 rpm on an axis with small friction (Tnzm 0.5 N·m, X 0.01): the cut pulls
// the table along the feed (the true mean of Fn is negative), and the motor brakes.
struct DownMilling {
  testing::DriveAxisParameters p;
  AxisRun log;
  DownMilling() {
    p.friction_nm = 0.5;
    p.viscous = 0.01;
    p.noise_a = 0.025;
    double feed = 0;
    const auto sim = testing::milling_cut(600.0, true, 12, feed);
    log = testing::drive_log(p, sim, feed);
  }
};

TEST(MonitorTorqueSign, DownMillingRightSignWithTheAngleAndAWarningWithout) {
  const DownMilling d;
  AxisCalibration cal;
  cal.model = testing::drive_axis_model(d.p);
  EstimatorOptions o;
  o.bandwidth_hz = 100.0;
  AxisForceEstimator with(cal, o), without(cal, o);
  double truth = 0, est_with = 0, est_without = 0;
  int n = 0, doubtful_with = 0, doubtful_without = 0;
  for (const AxisSample& s : d.log) {
    const ForceEstimate a =
        with.update(s.time_s, s.iu_a, s.iv_a, s.iw_a, s.speed_rad_s, s.rotor_angle_rad);
    const ForceEstimate b = without.update(s.time_s, s.iu_a, s.iv_a, s.iw_a, s.speed_rad_s);
    if (s.time_s < 0.4) continue;  // the filter and the drive settled
    truth += s.force_n;
    est_with += a.force_n;
    est_without += b.force_n;
    doubtful_with += a.torque_sign_doubtful;
    doubtful_without += b.torque_sign_doubtful;
    ++n;
  }
  truth /= n;
  est_with /= n;
  est_without /= n;
  ASSERT_LT(truth, -200.0);  // the premise: an aiding load
  // With the angle: the mean is right to 1 % (over whole tooth periods the filter keeps it).
  EXPECT_NEAR(est_with, truth, 0.01 * std::abs(truth)) << est_with << " vs " << truth;
  EXPECT_EQ(doubtful_with, 0);
  // Without it the estimate is wrong (the magnitude's sign is taken as the motion's) and
  // flagged: the torque passes through zero twice per tooth period.
  EXPECT_GT(std::abs(est_without - truth), 0.3 * std::abs(truth));
  EXPECT_GT(doubtful_without, 2 * 4 * 5);  // at least twice per tooth, 40 Hz, 0.4 s and more
  std::printf(
      "down-milling: true mean %.1f N, with the angle %.1f N, without %.1f N "
      "(%d of %d samples flagged)\n",
      truth, est_with, est_without, doubtful_without, n);
}

TEST(MonitorTorqueSign, NoFlagOnAResistingCut) {
  // Up-milling with the same drive (the load resists the feed, the torque keeps its sign):
  // no sample is flagged — the warning does not cry wolf.
  testing::DriveAxisParameters p;
  p.noise_a = 0.025;
  double feed = 0;
  const auto sim = testing::milling_cut(600.0, false, 12, feed);
  const AxisRun log = testing::drive_log(p, sim, feed);
  AxisCalibration cal;
  cal.model = testing::drive_axis_model(p);
  cal.current_noise_a = equivalent_current_sigma(0.025, p.measure);
  AxisForceEstimator est(cal, EstimatorOptions{100.0, 0.5});
  int flagged = 0;
  for (const AxisSample& s : log)
    flagged += est.update(s.time_s, s.iu_a, s.iv_a, s.iw_a, s.speed_rad_s).torque_sign_doubtful;
  EXPECT_EQ(flagged, 0);
}

}  // namespace
}  // namespace cutdyn

namespace cutdyn {
namespace {

// The mean estimate after 0.2 s of a log, with the calibration's current noise (`corrected`)
// and without it (`plain`), the mean σ and how many samples are flagged.
struct MeanEstimate {
  double corrected = 0.0, plain = 0.0, sigma = 0.0;
  int flagged = 0, samples = 0;
};
MeanEstimate mean_estimate(const testing::DriveAxisParameters& p, const AxisRun& log,
                           double phase_noise_a) {
  AxisCalibration raw;
  raw.model = testing::drive_axis_model(p);
  AxisCalibration c = raw;
  c.current_noise_a = equivalent_current_sigma(phase_noise_a, p.measure);
  AxisForceEstimator corrected(c, EstimatorOptions{50.0, 0.5});
  AxisForceEstimator plain(raw, EstimatorOptions{50.0, 0.5});
  MeanEstimate m;
  for (const AxisSample& s : log) {
    const ForceEstimate a = corrected.update(s.time_s, s.iu_a, s.iv_a, s.iw_a, s.speed_rad_s);
    const ForceEstimate b = plain.update(s.time_s, s.iu_a, s.iv_a, s.iw_a, s.speed_rad_s);
    if (s.time_s < 0.2) continue;
    m.corrected += a.force_n;
    m.plain += b.force_n;
    m.sigma += a.force_sigma_n;
    m.flagged += a.torque_sign_doubtful;
    ++m.samples;
  }
  m.corrected /= m.samples;
  m.plain /= m.samples;
  m.sigma /= m.samples;
  return m;
}

TEST(MonitorLightLoad, NoiseBiasOfTheMagnitudeIsCorrected) {
  // A light load (Tnzm 0.3 N·m, X 0.01, no force: Id ≈ 0.2 A rms at 2 rad/s) with 0.05 and
  // 0.1 A of noise per phase: the magnitude is biased up by ≈ σ_Id²/Id (σ_Id = σ/√3), about
  // +1.1 and +4.3 N of force. With the calibration's current noise the estimator
  // removes it: the mean over 1 s is within 0.8 N of the true 0 N (measured in the output);
  // without the correction (a calibration that states no current noise) it is not.
  testing::DriveAxisParameters p;
  p.friction_nm = 0.3;
  p.viscous = 0.01;
  std::vector<double> t;
  for (int i = 0; i <= 10000; ++i) t.push_back(i * 2e-4);
  const auto d = testing::drive_traces(p, t, std::vector<double>(t.size(), 0.0), 2.0);
  for (double noise : {0.05, 0.1}) {
    testing::DriveAxisParameters q = p;
    q.noise_a = noise;
    const AxisRun log = testing::noisy_log(q, d, 0.0, 7);
    const MeanEstimate e = mean_estimate(p, log, noise);
    const double m_c = e.corrected, m_p = e.plain, sig = e.sigma;
    const double id = 0.32 / 1.621, sid = equivalent_current_sigma(noise, p.measure);
    const double expected_bias = 1.621 * sid * sid / id / 0.00632;
    std::printf(
        "noise %.2f A: mean estimate %.2f N corrected, %.2f N plain (second-order bias "
        "%.2f N), mean sigma %.1f N\n",
        noise, m_c, m_p, expected_bias, sig);
    EXPECT_NEAR(m_p, expected_bias, 0.2 * expected_bias);  // the premise: the bias is there
    EXPECT_LT(std::abs(m_c), 0.8);
    EXPECT_LT(std::abs(m_c), 0.25 * std::abs(m_p));
  }
}

TEST(MonitorLightLoad, CurrentBelowTheNoiseIsCoveredBySigmaAndFlagged) {
  // The light axis of ermolaev2020's x (Tnzm 0.05 N·m, X 0.002, KBlf 2 mm, KT 1.621 rms)
  // under an aiding 10.9 N at 2.5 rad/s: the true current, 0.02 A, is below the noise σ_Id of
  // 0.025–0.1 A per phase (ν = 1.4 … 0.36). The magnitude's bias cannot be removed sample by
  // sample there (a per-sample inverse is itself biased); what remains must lie within the
  // stated σ, and at least 99 % of the samples are flagged (the sign is unknown).
  // Uncorrected, the error is larger.
  const testing::DriveAxisParameters p = testing::light_axis();
  std::vector<double> t;
  for (int i = 0; i <= 10000; ++i) t.push_back(i * 2e-4);
  const auto d = testing::drive_traces(p, t, std::vector<double>(t.size(), -10.9), 2.5);
  for (double noise : {0.025, 0.05, 0.1}) {
    testing::DriveAxisParameters q = p;
    q.noise_a = noise;
    const AxisRun log = testing::noisy_log(q, d, 0.0, 11);
    const MeanEstimate e = mean_estimate(p, log, noise);
    const double m_c = e.corrected, m_p = e.plain, sig = e.sigma;
    const int flagged = e.flagged, n = e.samples;
    std::printf(
        "light load below the noise, %.3f A: mean estimate %.1f N corrected, %.1f N "
        "plain (true -10.9 N), mean sigma %.1f N, %d of %d samples flagged\n",
        noise, m_c, m_p, sig, flagged, n);
    EXPECT_LE(std::abs(m_c + 10.9), sig) << noise;
    EXPECT_LT(std::abs(m_c + 10.9), std::abs(m_p + 10.9)) << noise;
    EXPECT_GE(flagged, 0.99 * n) << noise;
  }
}

}  // namespace
}  // namespace cutdyn
