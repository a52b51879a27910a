// The eigenvalues a boundary scan needs (detail/large_eigenvalues.hpp): Arnoldi's method and
// inverse iteration against the dense Schur decomposition, on the multi-frequency method's
// matrices K(ω) = G·H·D built here independently of the library's builder, on matrices with a
// prescribed spectrum, and at the edges (a small matrix, every eigenvalue large, K = 0); then
// the multi-frequency critical depth with and without them.
#include "cutdyn/stability/detail/large_eigenvalues.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <random>
#include <string>
#include <vector>

#include "cutdyn/core/units.hpp"
#include "cutdyn/modal/modal_model.hpp"
#include "cutdyn/stability/milling.hpp"
#include "cutdyn/stability/multi_frequency.hpp"
#include "cutdyn/stability/turning.hpp"
#include "support/reference_cases.hpp"

namespace cutdyn {
namespace {

using cplx = std::complex<double>;

// K(ω) straight from its definition (multi_frequency.hpp): blocks
// G(ω + pΩ)·Σk Hk(p − q)·(exp(−i(ω + qΩ)τk) − 1), p, q = −P−1..P.
Eigen::MatrixXcd hill_matrix(const DelayedSystem& s, int P, double w) {
  const int r = s.outputs();
  const double omega = units::kTwoPi / s.H.period_s;
  const int lo = -P - 1, hi = P, n = hi - lo + 1;
  Eigen::MatrixXcd K = Eigen::MatrixXcd::Zero(r * n, r * n);
  for (int p = lo; p <= hi; ++p) {
    const Eigen::MatrixXcd G = s.frequency_response(w + p * omega);
    for (int q = lo; q <= hi; ++q) {
      Eigen::MatrixXcd sum = Eigen::MatrixXcd::Zero(r, r);
      for (const DelayTerm& t : s.delay_terms())
        sum += t.H.fourier(p - q) * (std::polar(1.0, -(w + q * omega) * t.delay_s) - 1.0);
      K.block((p - lo) * r, (q - lo) * r, r, r) = G * sum;
    }
  }
  return K;
}

struct HillCase {
  std::string name;
  DelayedSystem system;
  double depth_max_m;
};

MillingProcess one_tooth_low_immersion() {
  MillingProcess m = testing::insperger_benchmark(0.03, true, true);
  m.tool.teeth = 1;
  return m;
}

MillingProcess uneven_pitch() {
  MillingProcess m = testing::insperger_benchmark(0.5, true, true);
  m.tool.teeth = 4;
  m.tool.pitch_rad = {units::deg_to_rad(70.0), units::deg_to_rad(110.0), units::deg_to_rad(70.0),
                      units::deg_to_rad(110.0)};
  return m;
}

std::vector<HillCase> hill_cases() {
  std::vector<HillCase> cases;
  cases.push_back(
      {"four modes 4000 rpm", milling_system(testing::four_mode_milling(), 4000.0), 30e-3});
  cases.push_back({"four modes up 11000 rpm",
                   milling_system(testing::four_mode_milling(0.2, false), 11000.0), 30e-3});
  cases.push_back(
      {"one tooth a/D 0.03", milling_system(one_tooth_low_immersion(), 29600.0), 30e-3});
  cases.push_back({"uneven pitch, four terms", milling_system(uneven_pitch(), 8000.0), 1e-3});
  cases.push_back({"slotting", milling_system(testing::insperger_benchmark(1.0), 9000.0), 1e-3});
  TurningProcess vat = testing::table2_vibration();
  vat.vibration->duty_cycle = 0.2;
  cases.push_back({"vibration-assisted turning", turning_system(vat, 900.0), 30e-3});
  return cases;
}

// Every dense eigenvalue of at least the threshold is among the returned ones (to 1e-9 of its
// modulus), each returned pair above the threshold is an eigenpair (residual 1e-9), and the
// nearest eigenvalue to a target near each large one is the dense one.
TEST(LargeEigenvalues, ArnoldiFindsEveryEigenvalueAboveTheThresholdOnHillMatrices) {
  for (const HillCase& c : hill_cases()) {
    MultiFrequencyOptions o;
    o.depth_max_m = c.depth_max_m;
    const int P = std::max(multi_frequency_harmonics(c.system, o), 20);
    // ω over [0, Ω/2], or over the structure's response band where Ω is far above it.
    const double span =
        std::min(units::kTwoPi / c.system.H.period_s, 2.0 * response_band_rad_s(c.system));
    const double threshold = 0.25 / c.depth_max_m;  // as the scan asks
    detail::LargeEigenvalues solver;
    int arnoldi = 0, found = 0;
    for (double fraction : {0.0, 0.07, 0.19, 0.33, 0.41, 0.5}) {
      const std::string where = c.name + " at ω = " + std::to_string(fraction) + " Ω";
      const Eigen::MatrixXcd K = hill_matrix(c.system, P, fraction * span);
      ASSERT_GT(K.rows(), 32) << where;  // large enough for Arnoldi
      const Eigen::ComplexEigenSolver<Eigen::MatrixXcd> dense(K, false);
      solver.compute(K, threshold, true);
      if (!solver.dense()) ++arnoldi;
      const Eigen::VectorXcd& got = solver.eigenvalues();
      int large = 0;
      for (Eigen::Index i = 0; i < dense.eigenvalues().size(); ++i) {
        const cplx v = dense.eigenvalues()(i);
        if (std::abs(v) < threshold) continue;
        ++large;
        double nearest = INFINITY;
        for (Eigen::Index j = 0; j < got.size(); ++j)
          nearest = std::min(nearest, std::abs(got(j) - v));
        EXPECT_LE(nearest, 1e-9 * std::abs(v)) << where << ": λ = " << v << " missing";
        // Inverse iteration from a target 0.1 % off finds the same eigenvalue.
        const cplx target = v * cplx(1.001, 0.0005);
        const auto [near, vector] = solver.nearest(K, target, true);
        double closest = INFINITY;
        for (Eigen::Index j = 0; j < dense.eigenvalues().size(); ++j)
          closest = std::min(closest, std::abs(dense.eigenvalues()(j) - target));
        EXPECT_NEAR(std::abs(near - target), closest, 1e-9 * std::abs(v)) << where;
        EXPECT_NEAR(vector.norm(), 1.0, 1e-12) << where;
        EXPECT_LE((K * vector - near * vector).norm(), 1e-9 * std::abs(near)) << where;
      }
      for (Eigen::Index j = 0; j < got.size(); ++j) {
        if (std::abs(got(j)) < threshold) continue;
        const Eigen::VectorXcd v = solver.eigenvectors().col(j);
        EXPECT_NEAR(v.norm(), 1.0, 1e-12) << where;
        EXPECT_LE((K * v - got(j) * v).norm(), 1e-9 * std::abs(got(j))) << where;
      }
      found += large;
    }
    EXPECT_GT(arnoldi, 0) << c.name << ": Arnoldi never used";
    EXPECT_GT(found, 0) << c.name << ": nothing to find";
  }
}

// A non-normal matrix X·diag(λ)·X⁻¹ with 6 eigenvalues of modulus 3–50 and a tail of 194
// falling geometrically from 0.5 (as the multi-frequency matrices' do): the six to 1e-9, in
// every one of 20 random bases.
TEST(LargeEigenvalues, PrescribedSpectrumInRandomNonNormalBases) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int n = 200;
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::VectorXcd lambda(n);
    for (int i = 0; i < n; ++i)
      lambda(i) = i < 6 ? std::polar(3.0 + 47.0 * (i / 5.0), 3.0 * u(random))
                        : std::polar(0.5 * std::pow(0.85, i - 6), 3.0 * u(random));
    Eigen::MatrixXcd X(n, n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) X(i, j) = cplx(u(random), u(random));
    X += 5.0 * Eigen::MatrixXcd::Identity(n, n);  // well conditioned, far from normal
    const Eigen::MatrixXcd K = X * lambda.asDiagonal() * X.inverse();
    detail::LargeEigenvalues solver;
    solver.compute(K, 1.0, false);
    EXPECT_FALSE(solver.dense()) << trial;
    for (int i = 0; i < 6; ++i) {
      double nearest = INFINITY;
      for (Eigen::Index j = 0; j < solver.eigenvalues().size(); ++j)
        nearest = std::min(nearest, std::abs(solver.eigenvalues()(j) - lambda(i)));
      EXPECT_LE(nearest, 1e-9 * std::abs(lambda(i))) << "trial " << trial << ", λ" << i;
    }
  }
}

TEST(LargeEigenvalues, EdgesFallBackToTheDenseSolverOrStopAtAnInvariantSpace) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto random_matrix = [&](int n) {
    Eigen::MatrixXcd K(n, n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) K(i, j) = cplx(u(random), u(random));
    return K;
  };
  detail::LargeEigenvalues solver;
  // Small: the dense solver, every eigenvalue.
  const Eigen::MatrixXcd small = random_matrix(20);
  solver.compute(small, 1.0, true);
  EXPECT_TRUE(solver.dense());
  EXPECT_EQ(solver.eigenvalues().size(), 20);
  // Every eigenvalue above the threshold: the basis would pass N/2, so the dense solver.
  const Eigen::MatrixXcd all = random_matrix(80) + 40.0 * Eigen::MatrixXcd::Identity(80, 80);
  solver.compute(all, 1.0, false);
  EXPECT_TRUE(solver.dense());
  EXPECT_EQ(solver.eigenvalues().size(), 80);
  // K = 0: an invariant space at once, no eigenvalue above the threshold.
  solver.compute(Eigen::MatrixXcd::Zero(64, 64), 1.0, true);
  EXPECT_FALSE(solver.dense());
  for (Eigen::Index j = 0; j < solver.eigenvalues().size(); ++j)
    EXPECT_EQ(solver.eigenvalues()(j), cplx(0.0));
  // Rank two: both nonzero eigenvalues, exactly (invariant space after three vectors).
  Eigen::MatrixXcd a = random_matrix(64), b = random_matrix(64);
  const Eigen::MatrixXcd rank2 = a.leftCols(2) * b.topRows(2);
  const Eigen::ComplexEigenSolver<Eigen::MatrixXcd> dense(rank2, false);
  solver.compute(rank2, 1e-6, false);
  int matched = 0;
  for (Eigen::Index i = 0; i < dense.eigenvalues().size(); ++i) {
    const cplx v = dense.eigenvalues()(i);
    if (std::abs(v) < 1e-6) continue;
    for (Eigen::Index j = 0; j < solver.eigenvalues().size(); ++j)
      if (std::abs(solver.eigenvalues()(j) - v) <= 1e-9 * std::abs(v)) ++matched;
  }
  EXPECT_EQ(matched, 2);
  // A target that is exactly an eigenvalue: inverse iteration's LU is singular; the answer
  // is still that eigenvalue.
  const Eigen::MatrixXcd diagonal = Eigen::VectorXcd::LinSpaced(40, 1.0, 40.0).asDiagonal();
  const auto [exact, vector] = solver.nearest(diagonal, cplx(17.0, 0.0), true);
  EXPECT_NEAR(std::abs(exact - cplx(17.0, 0.0)), 0.0, 1e-12);
  EXPECT_NEAR(std::abs(vector(16)), 1.0, 1e-12);
}

// The critical depth, chatter frequency and bifurcation with the eigenvalues from Arnoldi's
// method equal those with every eigenvalue from the dense solver: milling with even and
// uneven pitch, low immersion, four modes, up and down, and vibration-assisted turning.
struct MultiFrequencyCase {
  std::string name;
  DelayedSystem system;
  double depth_max_m;
};

std::vector<MultiFrequencyCase> multi_frequency_cases() {
  using Case = MultiFrequencyCase;
  std::vector<Case> cases;
  for (double rpm : {4000.0, 7000.0, 13000.0})
    cases.push_back({"four modes " + std::to_string(rpm),
                     milling_system(testing::four_mode_milling(), rpm), 30e-3});
  for (double rpm : {9000.0, 15000.0})
    cases.push_back({"four modes up a/D 0.2 " + std::to_string(rpm),
                     milling_system(testing::four_mode_milling(0.2, false), rpm), 30e-3});
  for (double rpm : {20000.0, 29600.0})
    cases.push_back({"one tooth " + std::to_string(rpm),
                     milling_system(one_tooth_low_immersion(), rpm), 30e-3});
  for (double rpm : {5000.0, 8000.0})
    cases.push_back(
        {"uneven pitch " + std::to_string(rpm), milling_system(uneven_pitch(), rpm), 1e-3});
  for (double rpm : {10000.0, 15000.0})
    cases.push_back({"flip a/D 0.05 " + std::to_string(rpm),
                     milling_system(testing::insperger_benchmark(0.05, false), rpm), 10e-3});
  TurningProcess vat = testing::table2_vibration();
  vat.vibration->duty_cycle = 0.2;
  for (double rpm : {600.0, 2000.0})
    cases.push_back(
        {"vibration-assisted turning " + std::to_string(rpm), turning_system(vat, rpm), 100e-3});
  return cases;
}

// The default multi-frequency answer and that of `variant` (the options changed one way) on
// every case: same depth, chatter frequency and bifurcation, nothing unresolved.
void expect_variant_agrees(const std::vector<MultiFrequencyCase>& cases,
                           void (*variant)(MultiFrequencyOptions&)) {
  for (const MultiFrequencyCase& c : cases) {
    MultiFrequencyOptions o;
    o.depth_max_m = c.depth_max_m;
    o.harmonics = c.system.more_delays.empty() ? 5 : 20;
    const CriticalDepth ours = multi_frequency_critical_depth(c.system, o);
    variant(o);
    const CriticalDepth other = multi_frequency_critical_depth(c.system, o);
    ASSERT_EQ(ours.found, other.found) << c.name;
    ASSERT_TRUE(other.found) << c.name << ": nothing to compare";
    EXPECT_NEAR(ours.depth_m, other.depth_m, 1e-9 * other.depth_m) << c.name;
    EXPECT_NEAR(ours.chatter_hz, other.chatter_hz, 1e-6 * other.chatter_hz) << c.name;
    EXPECT_EQ(ours.bifurcation, other.bifurcation) << c.name;
    EXPECT_EQ(ours.unresolved, 0) << c.name;
  }
}

TEST(LargeEigenvalues, MultiFrequencyDepthIsTheDenseSolversOne) {
  expect_variant_agrees(multi_frequency_cases(),
                        [](MultiFrequencyOptions& o) { o.dense_eigenvalues = true; });
}

// The frequency samples that widen away from the resonances (default) find the critical
// depth, chatter frequency and bifurcation of the former equal steps of the sharpest mode's
// quarter half-bandwidth, on the same cuts and on two edges: a mode 50 times sharper than
// the others (ζ = 0.001) and a stiff mode far above the tooth frequency.
TEST(LargeEigenvalues, WideningFrequencyStepsGiveTheEqualStepsDepth) {
  std::vector<MultiFrequencyCase> cases = multi_frequency_cases();
  MillingProcess sharp = testing::four_mode_milling();
  sharp.modal.modes.front().damping_ratio = 0.001;
  for (double rpm : {5000.0, 11000.0})
    cases.push_back({"a sharp mode " + std::to_string(rpm), milling_system(sharp, rpm), 30e-3});
  MillingProcess high = testing::four_mode_milling();
  high.modal.modes.back().natural_rad_s = units::hz_to_rad_per_s(6000.0);
  cases.push_back({"a mode at 6 kHz", milling_system(high, 6000.0), 30e-3});
  expect_variant_agrees(cases, [](MultiFrequencyOptions& o) { o.uniform_step = true; });
}

}  // namespace
}  // namespace cutdyn
