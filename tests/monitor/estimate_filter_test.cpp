// The estimate is the true force through a stated filter (docs/models/monitor.md §4.1): the
// filter's closed forms, and the whole chain — a simulated cut, the feed drive under its load
// with a PI speed loop, the motor's phase currents — estimated back from the currents.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <random>
#include <vector>

#include "cutdyn/core/units.hpp"
#include "cutdyn/drive/feed_drive.hpp"
#include "cutdyn/drive/motor_currents.hpp"
#include "cutdyn/monitor/force_estimator.hpp"
#include "cutdyn/simulate/milling_simulation.hpp"
#include "monitor/drive_chain.hpp"

namespace cutdyn {
namespace {

using units::kPi;
using units::kTwoPi;

TEST(MonitorEstimateFilter, ContinuousLimitClosedForms) {
  // For f_b·Δt → 0 the filter is (2πf_b)²/(s + 2πf_b)²: gain 1/(1 + (f/f_b)²), lag
  // 2·atan(f/f_b); 0.5 and 90° at f_b, −3 dB at f_b·sqrt(√2 − 1) = 0.6436·f_b.
  const EstimateFilter h{50.0, 1e-6};
  EXPECT_NEAR(h.gain(50.0), 0.5, 1e-4);
  EXPECT_NEAR(h.lag_deg(50.0), 90.0, 0.01);
  EXPECT_NEAR(h.minus_3db_hz(), 50.0 * std::sqrt(std::sqrt(2.0) - 1.0), 1e-3);
  EXPECT_NEAR(h.gain(20.0), 1.0 / (1.0 + 0.16), 1e-4);
  EXPECT_NEAR(h.lag_deg(20.0), 2.0 * std::atan(0.4) * 180.0 / kPi, 0.01);
  EXPECT_NEAR(h.delay_s(), 2.0 / (kTwoPi * 50.0), 1e-6);
}

TEST(MonitorEstimateFilter, ResponseMatchesTheRecursionOnASinusoid) {
  // A second method: the recursion itself (step means of a sinusoid, exact, then two
  // first-order stages) against the closed form, at 1 kHz with f_b = 100 Hz.
  const double dt = 1e-3, fb = 100.0;
  const EstimateFilter h{fb, dt};
  const double r = std::exp(-kTwoPi * fb * dt);
  for (double f : {10.0, 60.0, 150.0, 400.0}) {
    const double w = kTwoPi * f;
    double y1 = 0, y2 = 0;
    std::complex<double> sum = 0;
    const int n0 = 2000, n = 20000;
    for (int k = 1; k <= n0 + n; ++k) {
      const double t1 = k * dt, t0 = t1 - dt;
      const double mean = (std::sin(w * t1) - std::sin(w * t0)) / (w * dt);  // of cos(wt)
      y1 += (1 - r) * (mean - y1);
      y2 += (1 - r) * (y1 - y2);
      if (k > n0) sum += y2 * std::polar(1.0, -w * t1);
    }
    const std::complex<double> measured = 2.0 * sum / static_cast<double>(n);
    EXPECT_NEAR(std::abs(measured), h.gain(f), 2e-3 * h.gain(f)) << f;
    EXPECT_NEAR(-std::arg(measured) * 180 / kPi, h.lag_deg(f) - (h.lag_deg(f) > 180 ? 360 : 0),
                0.2)
        << f;
  }
}

TEST(MonitorEstimateFilter, NoiseSigmaMatchesSimulation) {
  // Only white noise on the phases (0.1 A) and the speed (0.2 rad/s) at a constant speed:
  // the scatter of the estimate over 200 000 samples equals the σ the estimator reports
  // (closed form of Σh²) within 3 %.
  AxisCalibration c;
  c.model = {0.017, 1.621, 0.2103, 15.6, 0.00632, CurrentMeasure::kRms};
  c.current_noise_a = 0.1 / std::sqrt(3.0);
  c.speed_noise_rad_s = 0.2;
  EstimatorOptions o;
  o.bandwidth_hz = 80.0;
  AxisForceEstimator est(c, o);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  const double dt = 1e-3, w = 50.0, id = 5.0;
  double s1 = 0, s2 = 0, sig = 0;
  const int n0 = 1000, n = 200000;
  double angle = 0;
  for (int k = 0; k < n0 + n; ++k) {
    angle += 4 * w * dt;
    const double p = std::sqrt(2.0) * id;
    const ForceEstimate e = est.update(
        k * dt, p * std::cos(angle) + 0.1 * g(rng), p * std::cos(angle - kTwoPi / 3) + 0.1 * g(rng),
        p * std::cos(angle + kTwoPi / 3) + 0.1 * g(rng), w + 0.2 * g(rng));
    if (k < n0) continue;
    s1 += e.force_n;
    s2 += e.force_n * e.force_n;
    sig = e.force_sigma_n;
  }
  const double mean = s1 / n, sd = std::sqrt(s2 / n - mean * mean);
  EXPECT_NEAR(sd / sig, 1.0, 0.03) << sd << " vs " << sig;
}

struct FilterCase {
  double loop_hz, rpm, bandwidth_hz;
};

class MonitorEstimateFilterChain : public ::testing::TestWithParam<FilterCase> {};

TEST_P(MonitorEstimateFilterChain, EstimateIsTheForceThroughTheStatedFilter) {
  // Up-milling, 4 teeth, Ø50 mm, 30° helix, a/D = 0.5, 0.25 mm/tooth, B = 4 mm: tooth
  // frequency 40 Hz (600 rpm) or 400 Hz (6000 rpm), 50 samples per tooth period. Exact
  // parameters, no noise: the estimate must equal the true axis force through H (the step
  // mean, here by the trapezoid rule, then Q) within 2 % RMS, and its tooth harmonic must
  // have H's gain (5 %) and lag (5°) relative to the true force's.
  const FilterCase c = GetParam();
  double feed = 0.0;
  const MillingSimulationResult sim =
      testing::milling_cut(c.rpm, false, c.rpm > 1000 ? 60 : 8, feed);
  std::vector<double> fn, zero(sim.fx_n.size(), 0.0);
  for (double f : sim.fx_n) fn.push_back(-f);  // resistance to the +x feed
  testing::DriveAxisParameters drive;  // the x axis of the tests, no noise
  drive.loop_hz = c.loop_hz;
  const FeedAxis axis = testing::drive_axis(drive);
  const FeedDriveResult d = simulate_feed_drive(axis, sim.time_s, sim.fx_n, zero, zero, feed);
  const PhaseCurrents p = motor_currents(*axis.motor, sim.time_s, d.motor_torque_nm, d.speed_rad_s);

  AxisCalibration cal;
  cal.model = testing::drive_axis_model(drive);
  EstimatorOptions eo;
  eo.bandwidth_hz = c.bandwidth_hz;
  AxisForceEstimator est(cal, eo);
  const double dt = sim.time_s[1] - sim.time_s[0];
  const EstimateFilter h{c.bandwidth_hz, dt};
  const double r = std::exp(-kTwoPi * c.bandwidth_hz * dt);
  const double f_tooth = 4 * c.rpm / 60.0;  // 4 teeth
  const double settle = 0.5 * sim.time_s.back();
  double y1 = fn[0], y2 = fn[0], se = 0, sf = 0;
  std::complex<double> he = 0, hf = 0;
  int n = 0;
  for (std::size_t i = 0; i < fn.size(); ++i) {
    const ForceEstimate e = est.update(sim.time_s[i], p.iu_a[i], p.iv_a[i], p.iw_a[i], d.speed_rad_s[i]);
    if (i > 0) {
      const double mean = 0.5 * (fn[i] + fn[i - 1]);
      y1 += (1 - r) * (mean - y1);
      y2 += (1 - r) * (y1 - y2);
    }
    if (sim.time_s[i] < settle) continue;
    se += (e.force_n - y2) * (e.force_n - y2);
    sf += y2 * y2;
    const std::complex<double> rot = std::polar(1.0, -kTwoPi * f_tooth * sim.time_s[i]);
    he += e.force_n * rot;
    hf += fn[i] * rot;
    ++n;
  }
  const double rel = std::sqrt(se / sf);
  EXPECT_LT(rel, 0.02) << "RMS error " << 100 * rel << " % of the filtered force";
  const std::complex<double> ratio = he / hf;
  const double lag = -std::arg(ratio) * 180 / kPi;
  EXPECT_NEAR(std::abs(ratio) / h.gain(f_tooth), 1.0, 0.05);
  EXPECT_NEAR(lag, h.lag_deg(f_tooth), 5.0);
  std::printf("loop %g Hz, tooth %g Hz, f_b %g Hz: RMS error %.3f %%, harmonic gain %.4f (H %.4f), "
              "lag %.2f deg (H %.2f)\n",
              c.loop_hz, f_tooth, c.bandwidth_hz, 100 * rel, std::abs(ratio), h.gain(f_tooth), lag,
              h.lag_deg(f_tooth));
}

INSTANTIATE_TEST_SUITE_P(LoopsAndTeeth, MonitorEstimateFilterChain,
                         ::testing::Values(FilterCase{100, 600, 100}, FilterCase{500, 600, 100},
                                           FilterCase{100, 6000, 1000}, FilterCase{500, 6000, 1000},
                                           FilterCase{100, 6000, 400}, FilterCase{500, 600, 40}),
                         [](const ::testing::TestParamInfo<FilterCase>& i) {
                           return "Loop" + std::to_string(int(i.param.loop_hz)) + "HzTooth" +
                                  std::to_string(int(i.param.rpm / 15)) + "HzFb" +
                                  std::to_string(int(i.param.bandwidth_hz)) + "Hz";
                         });

}  // namespace
}  // namespace cutdyn
