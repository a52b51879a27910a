// Teach-in band and the overload, breakage and wear alarms, each at a known event time.
#include "cutdyn/monitor/force_band.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

#include "cutdyn/core/error.hpp"

namespace cutdyn {
namespace {

constexpr double kDt = 1e-3;

// A run of `seconds` at 1 kHz with force f(t).
ForceRun run_of(double seconds, const std::function<double(double)>& f) {
  ForceRun r;
  for (int k = 0; k * kDt < seconds - 1e-12; ++k) {
    r.time_s.push_back(k * kDt);
    r.force_n.push_back(f(k * kDt));
  }
  return r;
}

// Reference cycle: 0.1 s in the air (0 N), then 1000 N until 2 s.
double reference(double t) { return t < 0.1 ? 0.0 : 1000.0; }

// The events of a monitored run.
std::vector<AlarmEvent> monitor(const ForceBand& band, const ForceRun& run,
                                const AlarmOptions& o = {}) {
  AlarmMonitor m(band, o);
  for (std::size_t k = 0; k < run.time_s.size(); ++k) m.update(run.time_s[k], run.force_n[k]);
  return m.events();
}

TEST(MonitorBand, TeachInFromReferenceRuns) {
  // Two runs, ±50 N apart: in a cutting bin the mean is 1000 N and σ = 50·√(20/19) N (10
  // samples of each run per bin), so the band is 1000 ± (3σ + 10 % of 1000 + 5 % of the
  // peak 1000) N; the air bins are not cutting.
  const ForceBand band = teach_band({run_of(2.0, [](double t) { return reference(t) + 50; }),
                                     run_of(2.0, [](double t) { return reference(t) - 50; })});
  ASSERT_EQ(band.mean_n.size(), 200u);
  const std::size_t b = band.bin(1.0);
  EXPECT_EQ(b, 100u);
  EXPECT_NEAR(band.mean_n[b], 1000.0, 1e-9);
  EXPECT_NEAR(band.sigma_n[b], 50.0 * std::sqrt(20.0 / 19.0), 1e-9);
  EXPECT_NEAR(band.upper_n[b], 1000.0 + 3 * band.sigma_n[b] + 150.0, 1e-9);
  EXPECT_NEAR(band.lower_n[b], 1000.0 - 3 * band.sigma_n[b] - 150.0, 1e-9);
  EXPECT_EQ(band.cutting[b], 1);
  EXPECT_EQ(band.cutting[5], 0);
  EXPECT_THROW(teach_band({}), InvalidInput);
}

// The time at which L = F0 + (F1 − F0)(1 − exp(−(t − t0)/τ)) reaches `limit`.
double crossing(double f0, double f1, double t0, double tau, double limit) {
  return t0 - tau * std::log(1.0 - (limit - f0) / (f1 - f0));
}

TEST(MonitorBand, NoAlarmOnAnotherRunLikeTheReference) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g(0.0, 20.0);
  const ForceBand band = teach_band({run_of(2.0, [&](double t) { return reference(t) + g(rng); })});
  EXPECT_TRUE(monitor(band, run_of(2.0, [&](double t) { return reference(t) + g(rng); })).empty());
}

TEST(MonitorBand, OverloadAtKnownTime) {
  // Noise-free reference: band 1000 ± 150 N. The force jumps to 1500 N at 1.2345 s; the level
  // (τ = 10 ms) crosses 1150 N 3.6 ms after the first sample at 1.235 s, confirmed 5 ms later.
  const ForceBand band = teach_band({run_of(2.0, reference)});
  const auto events =
      monitor(band, run_of(2.0, [](double t) { return t >= 1.2345 ? 1500.0 : reference(t); }));
  // A lasting 50 % overload also raises the wear indicator, later: nothing else.
  ASSERT_GE(events.size(), 1u);
  EXPECT_EQ(events[0].kind, AlarmKind::kOverload);
  for (std::size_t k = 1; k < events.size(); ++k) {
    EXPECT_EQ(events[k].kind, AlarmKind::kWear);
    EXPECT_GT(events[k].time_s, events[0].detected_s + 0.1);
  }
  const double expected = crossing(1000, 1500, 1.235, 0.01, 1150);
  EXPECT_NEAR(events[0].time_s, expected, kDt);
  EXPECT_NEAR(events[0].detected_s - events[0].time_s, 0.005, kDt);
  EXPECT_NEAR(events[0].limit_n, 1150.0, 1e-9);
}

TEST(MonitorBand, BreakageAtKnownTime) {
  // The force drops to 300 N at 0.8 s (a broken tooth): the level crosses 850 N then.
  const ForceBand band = teach_band({run_of(2.0, reference)});
  const auto events =
      monitor(band, run_of(2.0, [](double t) { return t >= 0.8 ? 300.0 : reference(t); }));
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, AlarmKind::kBreakage);
  EXPECT_NEAR(events[0].time_s, crossing(1000, 300, 0.8, 0.01, 850), kDt);
  // In the air (not a cutting bin) a missing force is no breakage.
  EXPECT_TRUE(monitor(band, run_of(0.1, [](double) { return 0.0; })).empty());
}

TEST(MonitorBand, WearAtKnownTimeAcrossCycles) {
  // A 1 s reference cycle cutting 1000 N throughout, wide band (±45 %) so that only wear
  // fires; monitored over 6 cycles, the force rises by 5 %/s from 1.5 s. The relative excess
  // of the level is 0.05·(t − 1.5 − τ) after a short transient, and W, its low-pass with
  // τw = 0.5 s, is 0.05·(s − τw·(1 − e^(−s/τw))) with s = t − 1.5 − τ: W = 0.15 at s ≈ 3.5 s.
  BandOptions o;
  o.relative_margin = 0.4;
  const ForceBand band = teach_band({run_of(1.0, [](double) { return 1000.0; })}, o);
  EXPECT_NEAR(band.cycle_s, 1.0, 1e-12);
  const auto events = monitor(
      band, run_of(6.0, [](double t) { return 1000.0 * (1.0 + 0.05 * std::max(0.0, t - 1.5)); }));
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, AlarmKind::kWear);
  double s = 3.0;  // solve 0.05·(s − 0.5·(1 − e^(−2s))) = 0.15 by Newton
  for (int i = 0; i < 20; ++i)
    s -= (0.05 * (s - 0.5 * (1 - std::exp(-2 * s))) - 0.15) / (0.05 * (1 - std::exp(-2 * s)));
  EXPECT_NEAR(events[0].time_s, 1.5 + 0.01 + s, 0.01);
}

}  // namespace
}  // namespace cutdyn
