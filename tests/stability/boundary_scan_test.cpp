#include "cutdyn/stability/detail/boundary_scan.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <limits>
#include <stdexcept>
#include <string>

#include "cutdyn/core/units.hpp"
#include "cutdyn/stability/milling.hpp"
#include "support/reference_cases.hpp"

namespace cutdyn {
namespace {

using cplx = std::complex<double>;

// The scan solves a 2×2 K in closed form and larger ones by the general Schur iteration. The
// same K bordered by a third row and column that add an eigenvalue far below the scan's
// threshold (so it can never be followed) must give the same boundary points: θ, depth and
// eigenvector (up to its phase) agree to rounding.
void expect_closed_form_matches_general(const MatrixFunction& k2, const BoundaryScanOptions& o,
                                        const std::string& name, double tolerance = 1e-9) {
  const MatrixFunction k3 = [&](double theta, Eigen::MatrixXcd& k) {
    Eigen::MatrixXcd small;
    const bool any = k2(theta, small);
    k = Eigen::MatrixXcd::Zero(3, 3);
    k.topLeftCorner(2, 2) = small;
    k(2, 2) = cplx(1e-6 * o.min_eigenvalue, 1e-7 * o.min_eigenvalue);
    return any;
  };
  const BoundaryScanReport a = scan_boundary(k2, o), b = scan_boundary(k3, o);
  ASSERT_EQ(a.points.size(), b.points.size()) << name;
  ASSERT_FALSE(a.points.empty()) << name;
  EXPECT_EQ(a.unresolved, b.unresolved) << name;
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    const BoundaryPoint &p = a.points[i], &q = b.points[i];
    EXPECT_NEAR(p.theta, q.theta, tolerance * std::abs(q.theta) + 1e-12) << name << " point " << i;
    EXPECT_NEAR(p.depth, q.depth, tolerance * q.depth) << name << " point " << i;
    ASSERT_EQ(p.eigenvector.size(), 2) << name;
    // |v2ᴴ·v3| = 1 for the same unit vector up to phase; v3's third entry is 0.
    const cplx overlap = p.eigenvector.dot(q.eigenvector.head(2));
    EXPECT_NEAR(std::abs(overlap), 1.0, 10.0 * tolerance) << name << " point " << i;
    EXPECT_NEAR(p.eigenvector.norm(), 1.0, 1e-12) << name;
    EXPECT_LT(std::abs(q.eigenvector(2)), 10.0 * tolerance) << name;
    // The eigenpair of the closed form satisfies K·v = λ·v.
    Eigen::MatrixXcd k;
    k2(p.theta, k);
    EXPECT_LT((k * p.eigenvector - p.eigenvalue * p.eigenvector).norm(),
              1e-9 * std::abs(p.eigenvalue))
        << name;
  }
}

// Zero-order milling: K(ω) = G(ω)·H0·(e^(−iωτ) − 1) of the four-mode reference cutter
// (up-milling), at speeds across the lobes and immersions from slotting to a narrow window.
TEST(BoundaryScan, ClosedForm2x2MatchesTheGeneralSolverOnMillingCases) {
  for (double immersion : {1.0, 0.5, 0.1}) {
    for (double rpm : {3000.0, 9000.0, 21000.0}) {
      const MillingProcess p = testing::four_mode_milling(immersion, /*down_milling=*/false);
      const DelayedSystem s = milling_system(p, rpm, 0.0);
      const Eigen::MatrixXcd h0 = s.H.fourier(0);
      const MatrixFunction k2 = [&](double w, Eigen::MatrixXcd& k) {
        k = s.frequency_response(w) * h0 * (std::polar(1.0, -w * s.delay_s) - 1.0);
        return true;
      };
      BoundaryScanOptions o;
      o.theta_min = 0.0;
      o.theta_max = units::hz_to_rad_per_s(3000.0);
      o.theta_step = 20.0;
      o.min_eigenvalue = 1.0 / 0.05;  // depths up to 50 mm
      o.refine_factor = std::numeric_limits<double>::infinity();
      expect_closed_form_matches_general(
          k2, o, "a/D " + std::to_string(immersion) + " at " + std::to_string(rpm) + " rpm");
    }
  }
}

// Edges of the closed form: eigenvalues 12 orders of magnitude apart (one direction at a
// resonance, the other stiff: det/λ1 keeps the small one accurate), and two eigenvalues
// within 1e-6 of each other (a nearly defective K, whose eigenvalues rounding moves by about
// sqrt(ε)·|K| in either solver: agreement to 1e-7 is all it allows). The eigenvalue followed
// grows along the scan so that no two boundary points share a depth.
TEST(BoundaryScan, ClosedForm2x2MatchesTheGeneralSolverAtItsEdges) {
  const Eigen::Matrix2cd rotate =
      (Eigen::Matrix2cd() << cplx(0.6, 0.1), cplx(-0.3, 0.5), cplx(0.2, -0.4), cplx(0.9, 0.2))
          .finished();
  const MatrixFunction spread = [&](double t, Eigen::MatrixXcd& k) {
    Eigen::Matrix2cd d = Eigen::Matrix2cd::Zero();
    d(0, 0) = 1e6 * std::polar(1.0 + 0.1 * t, 2.0 * t);
    d(1, 1) = 1e-6 * std::polar(1.0, -t);
    k = rotate * d * rotate.inverse();
    return true;
  };
  BoundaryScanOptions o;
  o.theta_min = 0.1;  // not at a crossing: there the sign of a rounded imaginary part decides
  o.theta_max = 10.0;
  o.theta_step = 0.01;
  o.min_eigenvalue = 1e4;
  o.refine_factor = std::numeric_limits<double>::infinity();
  expect_closed_form_matches_general(spread, o, "eigenvalues 1e12 apart");

  const MatrixFunction close = [&](double t, Eigen::MatrixXcd& k) {
    const cplx lambda = 100.0 * std::polar(1.0 + 0.1 * t, 3.0 * t);
    k.resize(2, 2);
    k << lambda, cplx(1.0, 0.0), cplx(1e-12, 0.0), lambda + cplx(1e-6, 0.0);
    k = rotate * k * rotate.inverse();
    return true;
  };
  o.min_eigenvalue = 10.0;
  expect_closed_form_matches_general(close, o, "eigenvalues 1e-6 apart", 1e-7);
}

// Steps that widen away from the resonances (step_at) find the same boundary points as equal
// steps of the sharpest mode's quarter half-bandwidth, with fewer samples: zero-order K of the
// four-mode cutter, up and down, three immersions and speeds, every crossing refined. A
// step_at that is not positive is a programming error, not a hang.
TEST(BoundaryScan, StepsThatWidenAwayFromTheResonancesFindTheSamePoints) {
  for (bool down : {false, true}) {
    for (double immersion : {1.0, 0.5, 0.1}) {
      for (double rpm : {3000.0, 9000.0, 21000.0}) {
        const std::string name = std::string(down ? "down" : "up") + " a/D " +
                                 std::to_string(immersion) + " at " + std::to_string(rpm) + " rpm";
        const DelayedSystem s = milling_system(testing::four_mode_milling(immersion, down), rpm);
        const Eigen::MatrixXcd h0 = s.H.fourier(0);
        const MatrixFunction k = [&](double w, Eigen::MatrixXcd& m) {
          m = s.frequency_response(w) * h0 * (std::polar(1.0, -w * s.delay_s) - 1.0);
          return true;
        };
        const Eigen::VectorXcd poles = s.A0.eigenvalues();
        double sharpest = std::numeric_limits<double>::infinity();
        for (Eigen::Index i = 0; i < poles.size(); ++i)
          sharpest = std::min(sharpest, -poles(i).real());
        BoundaryScanOptions o;
        o.theta_min = 0.0;
        o.theta_max = units::hz_to_rad_per_s(3000.0);
        o.min_eigenvalue = 1.0 / 0.05;
        o.refine_factor = std::numeric_limits<double>::infinity();
        const double delay_step = units::kTwoPi / (16.0 * s.delay_s);
        o.theta_step = std::min(delay_step, 0.25 * sharpest);
        const BoundaryScanReport equal = scan_boundary(k, o);
        o.theta_step = delay_step;
        o.step_at = [&](double w) {
          double d = std::numeric_limits<double>::infinity();
          for (Eigen::Index i = 0; i < poles.size(); ++i)
            d = std::min(d, std::abs(cplx(0.0, w) - poles(i)));
          return 0.25 * d;
        };
        const BoundaryScanReport widening = scan_boundary(k, o);
        ASSERT_FALSE(equal.points.empty()) << name;
        ASSERT_EQ(widening.points.size(), equal.points.size()) << name;
        for (std::size_t i = 0; i < equal.points.size(); ++i) {
          EXPECT_NEAR(widening.points[i].depth, equal.points[i].depth, 1e-9 * equal.points[i].depth)
              << name << " point " << i;
          EXPECT_NEAR(widening.points[i].theta, equal.points[i].theta, 1e-9 * equal.points[i].theta)
              << name << " point " << i;
        }
        EXPECT_EQ(widening.unresolved, 0) << name;
        EXPECT_LT(widening.evaluations, equal.evaluations) << name;
      }
    }
  }
  BoundaryScanOptions o;
  o.theta_max = 1.0;
  o.theta_step = 0.1;
  o.min_eigenvalue = 1.0;
  o.step_at = [](double) { return 0.0; };
  const MatrixFunction one = [](double, Eigen::MatrixXcd& m) {
    m = Eigen::MatrixXcd::Identity(1, 1);
    return true;
  };
  EXPECT_THROW(scan_boundary(one, o), std::logic_error);
}

}  // namespace
}  // namespace cutdyn
