#include "cutdyn/simulate/growth_estimate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <vector>

namespace cutdyn {
namespace {

// Samples of Σ c_i·μ_i^k, observed through two channels (real and imaginary parts at two
// fixed phases), for k = 0 … count − 1.
std::vector<std::vector<double>> sum_of_powers(const std::vector<std::complex<double>>& mu,
                                               const std::vector<double>& weight, int count) {
  std::vector<std::vector<double>> out;
  for (int k = 0; k < count; ++k) {
    std::complex<double> a = 0.0, b = 0.0;
    for (std::size_t i = 0; i < mu.size(); ++i) {
      const std::complex<double> term = weight[i] * std::pow(mu[i], k);
      a += term;
      b += term * std::polar(1.0, 0.7 + static_cast<double>(i));
    }
    out.push_back({a.real(), b.real()});
  }
  return out;
}

TEST(GrowthEstimate, FindsAGrowingRootMaskedByALargerDecayingOne) {
  // The situation of a simulation 1 % above a boundary (measured there: +0.0013 per period
  // under a neighbour decaying at −0.0096 and 20× larger): the log-amplitude falls for the
  // whole run, the multiplier is found exactly.
  const std::vector<std::complex<double>> mu = {std::polar(std::exp(-0.0096), 2.1),
                                                std::polar(std::exp(0.0013), 0.4),
                                                std::polar(std::exp(-0.3), -1.3)};
  const auto samples = sum_of_powers(mu, {1.0, 0.05, 0.5}, 60);
  std::vector<double> log_amplitude;
  for (std::size_t k = 30; k < samples.size(); ++k)
    log_amplitude.push_back(std::log(std::hypot(samples[k][0], samples[k][1])));
  EXPECT_LT(index_slope(log_amplitude), 0.0);  // the amplitude's slope says "decays"
  const auto estimate = dominant_multiplier(sum_of_powers(mu, {1.0, 0.05, 0.5}, 60));
  ASSERT_TRUE(estimate.has_value());
  EXPECT_NEAR(estimate->growth_per_period, 0.0013, 1e-8);
  EXPECT_EQ(estimate->components, 6);  // three complex roots seen through real channels
}

TEST(GrowthEstimate, LeavesTwoRootsCloserThanTheSamplesResolveToTheSlope) {
  // A symmetric structure (equal x and y modes) gives pairs of multipliers a fraction of 1/N
  // apart; in a simulated response the pencil splits such a pair at random and its larger
  // half is biased up (measured: +0.0001 per period beside −0.0027, at 0.985–0.99 of a helical
  // cutter's boundary, where the neighbouring depths gave −0.0015 and −0.0036). Such an
  // estimate is refused, so that the log-amplitude's slope and its settledness decide.
  const double angle = 2.0 * std::acos(-1.0) / 3.0;
  const auto close = sum_of_powers(
      {std::polar(std::exp(-0.0027), angle), std::polar(std::exp(0.0001), angle + 1e-3)},
      {1.0, 0.01}, 120);
  EXPECT_FALSE(dominant_multiplier(close).has_value());
  // The same pair 0.05 apart (4.5 times the resolution 1/90 of the 90 samples used): resolved.
  const auto apart = sum_of_powers(
      {std::polar(std::exp(-0.0027), angle), std::polar(std::exp(0.0001), angle + 0.05)},
      {1.0, 0.01}, 120);
  const auto estimate = dominant_multiplier(apart);
  ASSERT_TRUE(estimate.has_value());
  EXPECT_NEAR(estimate->growth_per_period, 0.0001, 1e-8);
}

TEST(GrowthEstimate, ADecayingResponseStaysDecaying) {
  for (double rate : {-1e-4, -0.02, -0.5}) {
    const auto estimate =
        dominant_multiplier(sum_of_powers({std::polar(std::exp(rate), 1.0),
                                           std::polar(std::exp(2.0 * rate - 0.05), 2.5)},
                                          {1.0, 1.0}, 80));
    ASSERT_TRUE(estimate.has_value()) << rate;
    EXPECT_NEAR(estimate->growth_per_period, rate, 1e-8) << rate;
  }
}

TEST(GrowthEstimate, RefusesSamplesThatAreNotAFewExponentials) {
  // A response sampled out of step with a periodic excitation, or a nonlinear one, is not a
  // sum of a few powers: the held-out quarter is not predicted and there is no estimate (the
  // simulation then falls back on the slope and says whether that settled).
  std::vector<std::vector<double>> switched, modulated;
  for (int k = 0; k < 120; ++k) {
    const double t = k;
    // A decaying oscillation that changes abruptly in the held-out quarter (as at a loss of
    // contact), and one whose frequency drifts.
    switched.push_back(k < 100 ? std::vector<double>{std::pow(0.98, t) * std::cos(0.5 * t),
                                                     std::pow(0.98, t) * std::sin(0.5 * t)}
                               : std::vector<double>{0.3 * std::cos(1.3 * t), 0.0});
    modulated.push_back({std::exp(-0.01 * t) * std::cos(0.3 * t + 0.5 * std::sin(0.05 * t * t)),
                         std::exp(-0.01 * t) * std::sin(0.3 * t * (1.0 + 0.01 * t))});
  }
  EXPECT_FALSE(dominant_multiplier(switched).has_value());
  EXPECT_FALSE(dominant_multiplier(modulated).has_value());
  // Too few samples, or none of them nonzero.
  EXPECT_FALSE(dominant_multiplier(sum_of_powers({0.9}, {1.0}, 10)).has_value());
  EXPECT_FALSE(dominant_multiplier(std::vector<std::vector<double>>(50, {0.0, 0.0})).has_value());
}

TEST(GrowthEstimate, SlopeSettlesOnlyWhenBothHalvesAgree) {
  std::vector<double> line, turning;
  for (int k = 0; k < 60; ++k) {
    line.push_back(-0.01 * k);
    // Falls (slope −0.049 over the first half), then rises (+0.044): +0.004 over the whole.
    turning.push_back(std::log(std::exp(-0.1 * k) + 0.05 * std::exp(0.05 * k)));
  }
  EXPECT_NEAR(index_slope(line), -0.01, 1e-12);
  EXPECT_TRUE(slope_settled(line));
  EXPECT_FALSE(slope_settled(turning));  // falls, then rises
  EXPECT_FALSE(slope_settled({0.0, -1.0}));
}

}  // namespace
}  // namespace cutdyn
