#include "cutdyn/stability/milling.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <utility>
#include <vector>

#include "cutdyn/core/units.hpp"
#include "cutdyn/stability/full_discretization.hpp"
#include "cutdyn/stability/multi_frequency.hpp"
#include "support/reference_cases.hpp"

namespace cutdyn {
namespace {

using units::kPi;
using units::kTwoPi;

MillingProcess benchmark(double immersion, bool both_directions = true) {
  return testing::insperger_benchmark(immersion, both_directions);
}

Eigen::Matrix2d direct_h(const MillingProcess& m, double rpm, double t) {
  return testing::direct_milling_h(m, rpm, t);
}

TEST(Milling, EntryAndExitAngles) {
  MillingProcess m = benchmark(1.0);
  EXPECT_NEAR(m.engagement.entry_angle(), 0.0, 1e-12);
  EXPECT_NEAR(m.engagement.exit_angle(), kPi, 1e-12);
  m.engagement.radial_immersion = 0.5;
  EXPECT_NEAR(m.engagement.entry_angle(), kPi / 2, 1e-12);
  m.engagement.down_milling = false;
  EXPECT_NEAR(m.engagement.entry_angle(), 0.0, 1e-12);
  EXPECT_NEAR(m.engagement.exit_angle(), kPi / 2, 1e-12);
}

TEST(Milling, DirectionalMatrixIsTheForceProjection) {
  // Fx, Fy of one tooth per unit Kt·a·Δ, from the tangential and radial forces directly.
  const double kr = 0.3;
  for (double phi : {0.1, 0.9, 2.0, 2.9}) {
    const Eigen::Matrix2d a = milling_directional_matrix(phi, kr);
    for (const Eigen::Vector2d& delta : {Eigen::Vector2d(1, 0), Eigen::Vector2d(0, 1)}) {
      const double h = delta.x() * std::sin(phi) + delta.y() * std::cos(phi);
      const double fx = -h * std::cos(phi) - kr * h * std::sin(phi);
      const double fy = h * std::sin(phi) - kr * h * std::cos(phi);
      const Eigen::Vector2d f = 0.5 * a * delta;
      EXPECT_NEAR(f.x(), fx, 1e-14);
      EXPECT_NEAR(f.y(), fy, 1e-14);
    }
  }
}

TEST(Milling, AverageCoefficientIsAltintasClosedForm) {
  // [Altintas & Budak 1995]: A0 = (z/2π)·[α], with the integrals evaluated at φst, φex.
  for (double immersion : {1.0, 0.5, 0.05}) {
    for (bool down : {true, false}) {
      MillingProcess m = benchmark(immersion);
      m.engagement.down_milling = down;
      const double kr = m.cutting.kr_pa / m.cutting.kt_pa, a = m.engagement.entry_angle(),
                   b = m.engagement.exit_angle();
      const auto F = [&](auto f) { return 0.5 * (f(b) - f(a)); };
      const double axx =
          F([&](double p) { return std::cos(2 * p) - 2 * kr * p + kr * std::sin(2 * p); });
      const double axy =
          F([&](double p) { return -std::sin(2 * p) - 2 * p + kr * std::cos(2 * p); });
      const double ayx =
          F([&](double p) { return -std::sin(2 * p) + 2 * p + kr * std::cos(2 * p); });
      const double ayy =
          F([&](double p) { return -std::cos(2 * p) - 2 * kr * p - kr * std::sin(2 * p); });
      Eigen::Matrix2d a0;
      a0 << axx, axy, ayx, ayy;
      a0 *= m.tool.teeth / kTwoPi;
      const DelayedSystem s = milling_system(m, 9000.0);
      const Eigen::MatrixXcd h0 = s.H.fourier(0);
      EXPECT_NEAR((h0.real() - (-0.5 * m.cutting.kt_pa) * a0).norm(), 0.0, 1e-6 * m.cutting.kt_pa);
      EXPECT_NEAR(h0.imag().norm(), 0.0, 1e-6 * m.cutting.kt_pa);
      // The mean over one whole period is the same matrix.
      EXPECT_NEAR((s.H.mean(0.0, s.H.period_s) - h0.real()).norm(), 0.0, 1e-6 * m.cutting.kt_pa);
    }
  }
}

TEST(Milling, StepMeansAgreeWithQuadratureToRounding) {
  // The means in closed form against 8-point Gauss–Legendre on the pieces between the window
  // edges (H is a trigonometric polynomial of degree 2 there: the rule is exact to rounding),
  // on steps short and long, inside a window, across its edges and over several periods; up
  // and down milling, slotting and low immersion, even and uneven pitch. (A step of length l at
  // angle φ is known to about ε·φ/l from its ends: 1e-10 for the shortest here.)
  static constexpr std::array<double, 4> kNode{0.1834346424956498, 0.5255324099163290,
                                               0.7966664774136267, 0.9602898564975363};
  static constexpr std::array<double, 4> kWeight{0.3626837833783620, 0.3137066458778873,
                                                 0.2223810344533745, 0.1012285362903763};
  for (const double immersion : {1.0, 0.5, 0.05}) {
    for (const bool down : {true, false}) {
      for (const bool uneven : {false, true}) {
        MillingProcess m = benchmark(immersion);
        m.engagement.down_milling = down;
        if (uneven) m.tool.pitch_rad = {units::deg_to_rad(150.0), units::deg_to_rad(210.0)};
        const double rpm = 7300.0;
        const DelayedSystem s = milling_system(m, rpm);
        // Uneven pitch: one delay term per tooth, H the sum of theirs.
        std::vector<const PeriodicCoefficient*> parts{&s.H};
        for (const DelayTerm& term : s.more_delays) parts.push_back(&term.H);
        ASSERT_EQ(parts.size(), uneven ? 2u : 1u);
        const auto mean = [&](double a, double b) {
          Eigen::Matrix2d sum = Eigen::Matrix2d::Zero();
          for (const PeriodicCoefficient* h : parts) sum += h->mean(a, b);
          return sum;
        };
        std::vector<double> edges;
        for (const PeriodicCoefficient* h : parts)
          edges.insert(edges.end(), h->breakpoints_s.begin(), h->breakpoints_s.end());
        std::sort(edges.begin(), edges.end());
        const double T = s.H.period_s;
        for (const auto& [a, b] : {std::pair{0.0, T}, {0.013 * T, 0.0137 * T},
                                   {0.2 * T, 0.71 * T}, {0.49 * T, 0.93 * T}, {0.0, 0.999 * T},
                                   {0.6 * T, 0.6 * T + 1e-6 * T}}) {
          std::vector<double> cuts{a};
          for (double e : edges)
            if (e > a && e < b) cuts.push_back(e);
          cuts.push_back(b);
          Eigen::Matrix2d q = Eigen::Matrix2d::Zero();
          for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
            const double mid = 0.5 * (cuts[i] + cuts[i + 1]), half = 0.5 * (cuts[i + 1] - cuts[i]);
            for (std::size_t g = 0; g < kNode.size(); ++g)
              for (const double sign : {-1.0, 1.0})
                q += kWeight[g] * half * direct_h(m, rpm, mid + sign * half * kNode[g]);
          }
          q /= b - a;
          EXPECT_LT((mean(a, b) - q).norm(), 1e-9 * m.cutting.kt_pa)
              << "immersion " << immersion << (down ? " down" : " up") << (uneven ? " uneven" : "")
              << " [" << a / T << ", " << b / T << "]·T";
        }
      }
    }
  }
}

TEST(Milling, StepMeansAndFourierCoefficientsMatchTheForceModel) {
  const MillingProcess m = benchmark(0.3);
  const double rpm = 7300.0;
  const DelayedSystem s = milling_system(m, rpm);
  const double T = s.H.period_s;
  EXPECT_NEAR(T, 60.0 / (rpm * 2), 1e-15);
  EXPECT_NEAR(s.delay_s, T, 1e-15);
  // Mean over a short step ≈ the direct value at its middle (away from the window edges).
  for (double t : {0.11 * T, 0.37 * T, 0.8 * T}) {
    const double h = 1e-7 * T;
    EXPECT_NEAR((s.H.mean(t - h, t + h) - direct_h(m, rpm, t)).norm(), 0.0, 1e-3 * m.cutting.kt_pa)
        << "t/T = " << t / T;
  }
  // Fourier coefficients against a midpoint-rule quadrature of the direct H(t).
  const int n = 200000;
  for (int p : {1, 2, 5}) {
    Eigen::Matrix2cd q = Eigen::Matrix2cd::Zero();
    for (int k = 0; k < n; ++k) {
      const double t = (k + 0.5) * T / n;
      q += direct_h(m, rpm, t).cast<std::complex<double>>() *
           std::exp(std::complex<double>(0.0, -kTwoPi * p * t / T));
    }
    q /= n;
    EXPECT_NEAR((s.H.fourier(p) - Eigen::MatrixXcd(q)).norm(), 0.0, 1e-4 * m.cutting.kt_pa)
        << "p = " << p;
  }
}

TEST(Milling, ZeroDepthSpectralRadiusIsTheStructuresDecay) {
  const MillingProcess m = benchmark(1.0);
  for (double rpm : {6000.0, 17000.0}) {
    const DelayedSystem s = milling_system(m, rpm);
    FdOptions o;
    o.steps_per_period = 40;
    const double zeta_wn = 0.011 * units::hz_to_rad_per_s(922.0);
    EXPECT_NEAR(fd_spectral_radius(s, fd_grid(s, o), 0.0), std::exp(-zeta_wn * s.delay_s), 1e-9);
  }
}

TEST(Milling, SlottingMethodsAgree) {
  // Slotting, both directions, 5000–25000 rpm. The full discretization (steps of 1/128 of the
  // structural period: converged to 0.03 %) and the multi-frequency solution (its harmonic
  // window raised from 6 to cover the mode) are independent and agree to 0.5 %; the zero-order
  // solution keeps only the mean coefficient and is within 10 % (within
  // 5 % except near the lobe peaks at 12 500 and 22 500–25 000 rpm, where it is 6–8 % low).
  const MillingProcess m = benchmark(1.0);
  for (double rpm = 5000.0; rpm <= 25000.0; rpm += 2500.0) {
    const DelayedSystem s = milling_system(m, rpm);
    MultiFrequencyOptions zoa, mf;
    zoa.harmonics = 0;
    zoa.depth_max_m = mf.depth_max_m = 0.01;
    mf.harmonics = 6;
    FdOptions fd;
    fd.max_step_fraction = 1.0 / 128.0;
    fd.depth_max_m = 0.01;
    const CriticalDepth a = multi_frequency_critical_depth(s, zoa);
    const CriticalDepth b = fd_critical_depth_by_radius(s, fd, RadiusSolver::kArnoldi, 1e-5);
    const CriticalDepth c = multi_frequency_critical_depth(s, mf);
    ASSERT_TRUE(a.found && b.found && c.found);
    EXPECT_NEAR(c.depth_m, b.depth_m, 0.005 * b.depth_m) << "rpm " << rpm;
    EXPECT_NEAR(a.depth_m, b.depth_m, 0.10 * b.depth_m) << "rpm " << rpm;
    EXPECT_EQ(b.bifurcation, Bifurcation::kHopf);
    EXPECT_NEAR(c.chatter_hz, b.chatter_hz, 2.0) << "rpm " << rpm;
  }
}

TEST(Milling, LowImmersionFlipLobesThatTheZeroOrderSolutionMisses) {
  // a/D = 0.05 (one direction, as in Insperger & Stépán's figures): at 10 000 and 15 000 rpm
  // the full discretization finds period-doubling boundaries — chatter at an odd multiple of
  // half the tooth-passing frequency — far below the zero-order lobes.
  const MillingProcess m = benchmark(0.05, false);
  for (double rpm : {10000.0, 15000.0}) {
    const DelayedSystem s = milling_system(m, rpm);
    MultiFrequencyOptions zoa;
    zoa.harmonics = 0;
    zoa.depth_max_m = 0.03;
    FdOptions fd;
    fd.steps_per_period = 80;
    fd.depth_max_m = 0.03;
    const CriticalDepth a = multi_frequency_critical_depth(s, zoa);
    const CriticalDepth reduced = fd_critical_depth(s, fd);
    const CriticalDepth dense = fd_critical_depth_dense(s, fd, 1e-7);
    ASSERT_TRUE(reduced.found && dense.found);
    EXPECT_EQ(reduced.bifurcation, Bifurcation::kFlip) << "rpm " << rpm;
    EXPECT_EQ(dense.bifurcation, Bifurcation::kFlip) << "rpm " << rpm;
    EXPECT_NEAR(reduced.depth_m, dense.depth_m, 1e-6 * dense.depth_m);
    const double tooth_hz = rpm / 60.0 * m.tool.teeth;
    const double harmonic = reduced.chatter_hz / (0.5 * tooth_hz);
    EXPECT_NEAR(harmonic, std::round(harmonic), 1e-6);
    EXPECT_EQ(static_cast<long>(std::round(harmonic)) % 2, 1);
    EXPECT_LT(reduced.depth_m, 0.7 * a.depth_m) << "rpm " << rpm;
  }
}

TEST(Milling, ArnoldiSpectralRadiusEqualsTheDenseOne) {
  // Slotting at 5000 rpm with 120 steps per tooth period (a 244-row map): the matrix-free
  // Arnoldi iteration converges and gives the dense eigenvalues' largest modulus.
  const MillingProcess m = benchmark(1.0);
  const DelayedSystem s = milling_system(m, 5000.0);
  FdOptions o;
  o.steps_per_period = 120;
  const FdGrid grid = fd_grid(s, o);
  for (double depth : {0.0, 0.03e-3, 0.048e-3, 0.07e-3}) {
    const SpectralRadius a = fd_spectral_radius_arnoldi(s, grid, depth);
    EXPECT_TRUE(a.arnoldi) << "depth " << depth;
    EXPECT_LT(a.operations, 200);
    EXPECT_NEAR(a.value, fd_spectral_radius(s, grid, depth), 1e-9) << "depth " << depth;
  }
}

TEST(Milling, DefaultDiscretizationIsWithinTheSearchTolerance) {
  // The default full discretization (quadratic interpolation, steps of 1/32 of the shortest
  // structural period) against the same at 1/128 (third order: 64× closer), by the Arnoldi
  // radius: the critical depth within 0.1 % — the search tolerance — on slotting, up-milling
  // at a/D 0.5 and 0.05 (flip lobes) and four modes, where the error is largest (0.052–0.078 %
  // measured; the linear interpolation at 1/64 was 0.08–0.30 % off on the same cases).
  struct Case {
    MillingProcess model;
    double rpm, depth_max;
  };
  const FdOptions defaults = MillingStabilityOptions{}.fd;
  ASSERT_EQ(defaults.order, 2);
  for (const Case& c : {Case{benchmark(1.0), 5000.0, 1e-3}, Case{benchmark(1.0), 14876.0, 1e-3},
                        Case{benchmark(1.0), 24400.0, 1e-3},
                        Case{testing::insperger_benchmark(0.5, true, false), 23447.6, 1e-3},
                        Case{testing::insperger_benchmark(0.05, true, false), 18685.7, 1e-3},
                        Case{testing::four_mode_milling(), 13925.7, 30e-3}}) {
    const DelayedSystem s = milling_system(c.model, c.rpm);
    FdOptions fine = defaults;
    fine.max_step_fraction = defaults.max_step_fraction / 4.0;
    FdOptions coarse = defaults;
    coarse.depth_max_m = fine.depth_max_m = c.depth_max;
    const CriticalDepth a =
        fd_critical_depth_by_radius(s, coarse, RadiusSolver::kArnoldi, 1e-6, 16);
    const CriticalDepth b = fd_critical_depth_by_radius(s, fine, RadiusSolver::kArnoldi, 1e-6, 16);
    ASSERT_TRUE(a.found && b.found);
    EXPECT_NEAR(a.depth_m, b.depth_m, 1e-3 * b.depth_m) << "rpm " << c.rpm;
    EXPECT_NEAR(a.chatter_hz, b.chatter_hz, 1e-3 * b.chatter_hz) << "rpm " << c.rpm;
  }
}

}  // namespace
}  // namespace cutdyn
