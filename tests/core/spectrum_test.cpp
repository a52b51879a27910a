#include "cutdyn/core/spectrum.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn {
namespace {

std::vector<double> sampled(std::size_t n, double dt, double mean,
                            const std::vector<std::pair<double, double>>& sines) {
  std::vector<double> x(n, mean);
  for (std::size_t i = 0; i < n; ++i)
    for (const auto& [amplitude, hz] : sines)
      x[i] += amplitude * std::sin(units::kTwoPi * hz * static_cast<double>(i) * dt + 0.3);
  return x;
}

// Sines on bins read their amplitudes at their frequencies, the mean at 0 Hz; the window's
// leakage stays in the neighbouring bins.
TEST(Spectrum, SinesOnBinsReadTheirAmplitudes) {
  const std::size_t n = 1000;
  const double dt = 1e-3;  // bins every 1 Hz
  const Spectrum s = amplitude_spectrum(sampled(n, dt, 0.7, {{2.0, 50.0}, {0.25, 213.0}}), dt);
  ASSERT_EQ(s.frequency_hz.size(), n / 2 + 1);
  EXPECT_DOUBLE_EQ(s.frequency_hz[50], 50.0);
  EXPECT_NEAR(s.amplitude[50], 2.0, 1e-12);
  EXPECT_NEAR(s.amplitude[213], 0.25, 1e-12);
  EXPECT_NEAR(s.amplitude[0], 0.7, 1e-12);
  EXPECT_NEAR(s.amplitude[49], 1.0, 1e-12);  // Hann: half the amplitude in each neighbour
  EXPECT_LT(s.amplitude[60], 1e-12);
}

// Off a bin, the peak is still at the nearest bin, within the Hann window's scalloping loss
// (at most 1.42 dB: 0.849 of the amplitude).
TEST(Spectrum, SineBetweenBinsPeaksAtTheNearestBin) {
  const double dt = 1e-4;
  const Spectrum s = amplitude_spectrum(sampled(4096, dt, 0.0, {{1.0, 777.7}}), dt);
  const auto peak = std::max_element(s.amplitude.begin(), s.amplitude.end()) - s.amplitude.begin();
  EXPECT_NEAR(s.frequency_hz[static_cast<std::size_t>(peak)], 777.7, 0.5 / (4096 * dt));
  EXPECT_GT(s.amplitude[static_cast<std::size_t>(peak)], 0.84);
  EXPECT_LE(s.amplitude[static_cast<std::size_t>(peak)], 1.0 + 1e-12);
}

TEST(Spectrum, RefusesWhatHasNoSpectrum) {
  EXPECT_THROW(amplitude_spectrum({1.0, 2.0}, 1e-3), InvalidInput);
  EXPECT_THROW(amplitude_spectrum({1.0, 2.0, 3.0, 4.0}, 0.0), InvalidInput);
  EXPECT_THROW(amplitude_spectrum({1.0, std::numeric_limits<double>::quiet_NaN(), 3.0, 4.0}, 1.0),
               InvalidInput);
}

}  // namespace
}  // namespace cutdyn
