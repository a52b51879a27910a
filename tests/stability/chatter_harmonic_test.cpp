// The chatter harmonic of a Floquet solution: the folded, Parseval-stopped sums on uniform
// samples (detail::dominant_frequency_hz_uniform) against the direct sum over every harmonic
// (detail::dominant_frequency_hz) — the same harmonic, hence the same frequency to the last
// digit, for spectra with one dominant line, several lines, a flat (white) spectrum and a line
// at the Nyquist end, for odd, even and prime step counts.
#include "cutdyn/stability/detail/chatter_harmonic.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <random>
#include <vector>

#include "cutdyn/core/units.hpp"

namespace cutdyn {
namespace {

using cplx = std::complex<double>;

struct Samples {
  std::vector<double> times;
  std::vector<cplx> values;
};

// n + 1 samples at t_i = −i·T/n, as the period map's history: lines at harmonics `lines`
// (k of the direct sum) with amplitudes `amplitudes`, plus complex noise of `noise`.
Samples signal(int n, double period, double theta, const std::vector<int>& lines,
               const std::vector<double>& amplitudes, double noise, std::mt19937& rng) {
  std::normal_distribution<double> gauss;
  const int kmax = n / 2;
  Samples s;
  for (int i = 0; i <= n; ++i) {
    const double t = -static_cast<double>(i) * period / n;
    cplx v(noise * gauss(rng), noise * gauss(rng));
    for (std::size_t l = 0; l < lines.size(); ++l) {
      const double w = (theta + units::kTwoPi * (lines[l] - kmax)) / period;
      v += amplitudes[l] * std::polar(1.0, w * t + gauss(rng));
    }
    s.times.push_back(t);
    s.values.push_back(v);
  }
  return s;
}

// For even n the harmonics k = 0 and k = n have the same sum (the Nyquist alias): the direct
// sum picks between their two frequencies by rounding, so either is the same answer there.
void expect_same(int n, double period, double theta, const Samples& s, const char* what) {
  const double direct = detail::dominant_frequency_hz(theta, period, s.times, s.values, n);
  const double uniform = detail::dominant_frequency_hz_uniform(theta, period, n, s.values);
  const int kmax = n / 2;
  const double edge_low = std::abs(theta - units::kTwoPi * kmax) / period / units::kTwoPi;
  const double edge_high = std::abs(theta + units::kTwoPi * kmax) / period / units::kTwoPi;
  const auto at_alias = [&](double f) {
    return n % 2 == 0 && (std::abs(f - edge_low) < 1e-9 * f || std::abs(f - edge_high) < 1e-9 * f);
  };
  if (at_alias(direct)) {
    EXPECT_TRUE(at_alias(uniform)) << what << ", n " << n << ", theta " << theta;
    return;
  }
  EXPECT_EQ(direct, uniform) << what << ", n " << n << ", theta " << theta;
}

TEST(ChatterHarmonic, FoldedSumsFindTheDirectSumsHarmonic) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-units::kPi, units::kPi);
  for (int n : {8, 9, 71, 142, 143, 355, 512}) {
    const double period = 60.0 / (2.0 * 5000.0) * 143.0 / n;
    std::uniform_int_distribution<int> harmonic(0, n - 1);
    for (int trial = 0; trial < 20; ++trial) {
      const double theta = angle(rng);
      // One line near the low end (a chatter frequency near a mode) with a little noise.
      const int low = n / 2 + std::uniform_int_distribution<int>(-3, 3)(rng);
      expect_same(n, period, theta, signal(n, period, theta, {low}, {1.0}, 0.05, rng), "one line");
      // Two lines of nearly equal size anywhere.
      expect_same(n, period, theta,
                  signal(n, period, theta, {harmonic(rng), harmonic(rng)}, {1.0, 0.97}, 0.01, rng),
                  "two lines");
      // White noise: no line stands out, the sums must run through every harmonic.
      expect_same(n, period, theta, signal(n, period, theta, {}, {}, 1.0, rng), "white");
      // A line at the highest frequencies, among the last the folded sums reach.
      expect_same(n, period, theta, signal(n, period, theta, {1}, {1.0}, 0.2, rng), "high line");
    }
  }
}

TEST(ChatterHarmonic, PureLineGivesItsFrequency) {
  // A single line at 922 Hz sampled over one tooth period of 2 teeth at 12 000 rpm.
  const int n = 143;
  const double period = 60.0 / (2.0 * 12000.0);
  const double f = 922.0, w = units::kTwoPi * f;
  const double theta = std::remainder(w * period, units::kTwoPi);  // the multiplier's angle
  std::vector<cplx> values;
  std::vector<double> times;
  for (int i = 0; i <= n; ++i) {
    const double t = -static_cast<double>(i) * period / n;
    times.push_back(t);
    values.push_back(std::polar(1.0, w * t));
  }
  EXPECT_NEAR(detail::dominant_frequency_hz_uniform(theta, period, n, values), f, 1e-9);
  EXPECT_NEAR(detail::dominant_frequency_hz(theta, period, times, values, n), f, 1e-9);
}

}  // namespace
}  // namespace cutdyn
