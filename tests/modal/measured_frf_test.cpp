#include "cutdyn/modal/measured_frf.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>
#include <limits>
#include <numbers>

namespace cutdyn {
namespace {

ModalModel two_modes() {
  return ModalModel{{Mode{Direction::kX, 2 * std::numbers::pi * 500.0, 0.02, 2e7},
                     Mode{Direction::kX, 2 * std::numbers::pi * 1200.0, 0.03, 5e7}}};
}

TEST(MeasuredFrf, SampledTableReturnsTheModesAtItsPointsAndInterpolatesBetween) {
  const ModalModel model = two_modes();
  const MeasuredFrf table = sample_frf(model, Direction::kX, linear_frequencies(0, 3000, 30001));
  EXPECT_TRUE(table.validate().empty());
  for (double f : {0.0, 123.4, 499.95, 1200.0, 2999.99, 3000.0}) {
    const std::complex<double> exact = frf(model, Direction::kX, 2 * std::numbers::pi * f);
    // 0.1 Hz spacing, ζ·fn ≥ 10 Hz: linear interpolation is within 1e-4 of |G| peak.
    EXPECT_LT(std::abs(table.at(f) - exact), 1e-4 * std::abs(exact) + 1e-13) << f;
  }
}

// The interval holding f is guessed from f's place in the band and corrected; on grids that
// are evenly spaced, log-spaced, clustered or random the value must be the definition's:
// linear interpolation within the interval [f(j−1), f(j)] that holds f, found by bisection.
TEST(MeasuredFrf, LookupMatchesBisectionOnUnevenGrids) {
  const auto by_bisection = [](const MeasuredFrf& t, double f) {
    const auto hi = std::upper_bound(t.frequency_hz.begin(), t.frequency_hz.end(), f);
    const std::size_t j = std::clamp<std::size_t>(
        static_cast<std::size_t>(hi - t.frequency_hz.begin()), 1, t.frequency_hz.size() - 1);
    const double s = (f - t.frequency_hz[j - 1]) / (t.frequency_hz[j] - t.frequency_hz[j - 1]);
    return t.receptance_m_per_n[j - 1] +
           s * (t.receptance_m_per_n[j] - t.receptance_m_per_n[j - 1]);
  };
  std::mt19937 rng(7);
  std::vector<std::vector<double>> grids;
  grids.push_back(linear_frequencies(0.0, 3000.0, 2951));
  std::vector<double> log_spaced, clustered, random{0.0};
  for (int i = 0; i < 400; ++i) log_spaced.push_back(std::pow(10.0, 1.0 + 3.0 * i / 399.0));
  for (int i = 0; i < 300; ++i) clustered.push_back(i < 290 ? 1000.0 + 0.01 * i : 1e4 + 1e3 * i);
  std::uniform_real_distribution<double> gap(1e-3, 50.0);
  for (int i = 0; i < 500; ++i) random.push_back(random.back() + gap(rng));
  grids.push_back(log_spaced);
  grids.push_back(clustered);
  grids.push_back(random);
  grids.push_back({5.0, 6.0, 7.0});
  for (const std::vector<double>& f : grids) {
    MeasuredFrf t;
    t.frequency_hz = f;
    for (std::size_t i = 0; i < f.size(); ++i)
      t.receptance_m_per_n.emplace_back(std::sin(0.37 * static_cast<double>(i)), std::cos(1.3 * static_cast<double>(i)));
    std::uniform_real_distribution<double> at(t.min_hz(), t.max_hz());
    std::vector<double> probes = f;  // every table point, then points between
    for (int k = 0; k < 3000; ++k) probes.push_back(at(rng));
    for (double q : probes) {
      const std::complex<double> want = by_bisection(t, q);
      EXPECT_LT(std::abs(t.at(q) - want), 1e-12 * (1.0 + std::abs(want))) << q << " of " << f.size();
    }
  }
}

TEST(MeasuredFrf, ValidationNamesEachBadPoint) {
  MeasuredFrf bad;
  bad.frequency_hz = {10.0, 10.0, 5.0, std::numeric_limits<double>::quiet_NaN()};
  bad.receptance_m_per_n = {{1e-8, 0}, {1e-8, 0}, {std::nan(""), 0}, {1e-8, 0}};
  const auto problems = bad.validate();
  ASSERT_GE(problems.size(), 3u);
  EXPECT_NE(problems[0].find("frequency_hz[1]"), std::string::npos) << problems[0];
  const MeasuredFrf too_few{{1.0, 2.0}, {{0, 0}, {0, 0}}, {}};
  EXPECT_FALSE(too_few.validate().empty());
  const MeasuredFrf unequal{{1.0, 2.0, 3.0}, {{0, 0}}, {}};
  EXPECT_FALSE(unequal.validate().empty());
}

}  // namespace
}  // namespace cutdyn
