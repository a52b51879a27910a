// Identification of milling cutting coefficients from mean forces (forces/identify.hpp;
// docs/models/identification.md, "What the tests show").
#include "cutdyn/forces/identify.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/simulate/milling_simulation.hpp"
#include "cutdyn/stability/milling.hpp"

namespace cutdyn {
namespace {

std::string joined(const std::vector<std::string>& lines) {
  std::string s;
  for (const std::string& l : lines) s += "\n  " + l;
  return s;
}

using ::testing::HasSubstr;
using units::kPi;
using units::kTwoPi;

// Kt 600, Kr 200, Ka 120 N/mm²; Kte 20, Kre 25, Kae 10 N/mm.
CuttingCoefficients true_coefficients() {
  CuttingCoefficients k;
  k.kt_pa = 600e6;
  k.kr_pa = 200e6;
  k.ka_pa = 120e6;
  k.kte_n_per_m = 20e3;
  k.kre_n_per_m = 25e3;
  k.kae_n_per_m = 10e3;
  return k;
}

struct Window {
  const char* name;
  double entry, exit;
};

// Immersions 0.1, 0.25, 0.5, 1 up and down, and partial windows that touch neither edge.
std::vector<Window> windows() {
  std::vector<Window> list;
  for (double immersion : {0.1, 0.25, 0.5, 1.0})
    for (bool down : {true, false}) {
      const EngagementWindow w = engagement_window(immersion, down);
      list.push_back({down ? "down" : "up", w.entry_rad, w.exit_rad});
    }
  list.push_back({"partial", 0.3, 1.2});
  list.push_back({"partial", 1.0, 2.5});
  list.push_back({"partial", 2.0, 2.9});
  return list;
}

std::string describe(const Window& w) {
  return std::string(w.name) + " [" + std::to_string(w.entry) + ", " + std::to_string(w.exit) + "]";
}

// Instantaneous force of all teeth at spindle angle ψ (tooth j at ψ + 2πj/z), straight teeth.
Eigen::Vector3d instantaneous_force(const IdentifyCut& cut, const CuttingCoefficients& k, double c,
                                    double a, double psi) {
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  for (int j = 0; j < cut.teeth; ++j) {
    const double phi = std::fmod(psi + kTwoPi * j / cut.teeth, kTwoPi);
    if (phi <= cut.entry_rad || phi >= cut.exit_rad) continue;
    const double h = c * std::sin(phi);
    const double ft = k.kt_pa * a * h + k.kte_n_per_m * a;
    const double fr = k.kr_pa * a * h + k.kre_n_per_m * a;
    const double fa = k.ka_pa * a * h + k.kae_n_per_m * a;
    f += Eigen::Vector3d(-ft * std::cos(phi) - fr * std::sin(phi),
                         ft * std::sin(phi) - fr * std::cos(phi), fa);
  }
  return f;
}

// What a rule with nodes h apart can miss at the window's edges: the force jumps there by one
// tooth's force, and a sum over nodes misplaces each jump by at most h/2. Over a revolution, z
// teeth: z·(h/2)·(|F(φst)| + |F(φex)|)/2π, F one tooth's force at the edge.
double edge_bound(const IdentifyCut& cut, const CuttingCoefficients& k, double c, double a,
                  double h) {
  const IdentifyCut one{1, cut.entry_rad, cut.exit_rad};
  const double inside = 1e-12;
  const double jumps = instantaneous_force(one, k, c, a, cut.entry_rad + inside).norm() +
                       instantaneous_force(one, k, c, a, cut.exit_rad - inside).norm();
  return cut.teeth * 0.5 * h * jumps / kTwoPi;
}

TEST(IdentifyClosedForm, MeanForceIsTheInstantaneousForceAveragedOverARevolution) {
  // Second method: the total force of z teeth sampled at 400 000 spindle angles of one
  // revolution (midpoint rule), within edge_bound (the smooth part's O(h²) error is 1e-10 of
  // it), which is 1e-5 to 1e-4 of the force here.
  const CuttingCoefficients k = true_coefficients();
  const double c = 0.1e-3, a = 2e-3;
  for (const Window& w : windows())
    for (int z : {1, 2, 3, 5}) {
      const IdentifyCut cut{z, w.entry, w.exit};
      const int n = 400000;
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (int i = 0; i < n; ++i) sum += instantaneous_force(cut, k, c, a, kTwoPi * (i + 0.5) / n);
      const Eigen::Vector3d numeric = sum / n;
      const Eigen::Vector3d closed = mean_milling_force(cut, k, c, a);
      const double bound = edge_bound(cut, k, c, a, kTwoPi / n);
      EXPECT_LT(bound, 1e-4 * numeric.norm());
      EXPECT_LT((closed - numeric).norm(), bound * (1.0 + 1e-6))
          << describe(w) << " z " << z << ": closed " << closed.transpose() << " numeric "
          << numeric.transpose();
    }
}

TEST(IdentifyClosedForm, AgreesWithAltintasPrintedForm) {
  // [Altintas2012, ch. 2]: F̄x = (z·a·c/8π)·[Kt·cos2φ − Kr·(2φ − sin2φ)] + (z·a/2π)·[−Kte·sinφ +
  // Kre·cosφ], F̄y = (z·a·c/8π)·[Kt·(2φ − sin2φ) + Kr·cos2φ] − (z·a/2π)·[Kte·cosφ + Kre·sinφ],
  // F̄z = (z·a/2π)·[−Ka·c·cosφ + Kae·φ], each [·] taken from φst to φex.
  const CuttingCoefficients k = true_coefficients();
  const double c = 0.07e-3, a = 3e-3;
  for (const Window& w : windows()) {
    const IdentifyCut cut{3, w.entry, w.exit};
    const auto span = [&](auto f) { return f(w.exit) - f(w.entry); };
    const double z = 3;
    const double fx = z * a * c / (8 * kPi) * span([&](double p) {
                        return k.kt_pa * std::cos(2 * p) - k.kr_pa * (2 * p - std::sin(2 * p));
                      }) +
                      z * a / kTwoPi * span([&](double p) {
                        return -k.kte_n_per_m * std::sin(p) + k.kre_n_per_m * std::cos(p);
                      });
    const double fy = z * a * c / (8 * kPi) * span([&](double p) {
                        return k.kt_pa * (2 * p - std::sin(2 * p)) + k.kr_pa * std::cos(2 * p);
                      }) -
                      z * a / kTwoPi * span([&](double p) {
                        return k.kte_n_per_m * std::cos(p) + k.kre_n_per_m * std::sin(p);
                      });
    const double fz = z * a / kTwoPi * span([&](double p) {
                        return -k.ka_pa * c * std::cos(p) + k.kae_n_per_m * p;
                      });
    const Eigen::Vector3d closed = mean_milling_force(cut, k, c, a);
    EXPECT_NEAR(closed.x(), fx, 1e-12 * std::abs(fy) + 1e-12) << describe(w);
    EXPECT_NEAR(closed.y(), fy, 1e-12 * std::abs(fy)) << describe(w);
    EXPECT_NEAR(closed.z(), fz, 1e-12 * std::abs(fz)) << describe(w);
  }
}

TEST(IdentifyClosedForm, WindowMatricesAreScaledRotations) {
  // A = [[a, b], [−b, a]]: AᵀA = det·I, so the x and y equations never confuse Kt with Kr;
  // det → 0 only as the window closes.
  for (const Window& w : windows()) {
    const WindowIntegrals wi = window_integrals(w.entry, w.exit);
    for (const Eigen::Matrix2d& m : {wi.chip_matrix(), wi.edge_matrix()}) {
      const Eigen::Matrix2d mtm = m.transpose() * m;
      EXPECT_NEAR(mtm(0, 1), 0.0, 1e-14) << describe(w);
      EXPECT_NEAR(mtm(0, 0), m.determinant(), 1e-14) << describe(w);
      EXPECT_NEAR(mtm(1, 1), m.determinant(), 1e-14) << describe(w);
    }
  }
  const WindowIntegrals slot = window_integrals(0.0, kPi);
  EXPECT_NEAR(std::sqrt(slot.chip_matrix().determinant()), kPi / 2, 1e-15);
  EXPECT_NEAR(std::sqrt(slot.edge_matrix().determinant()), 2.0, 1e-15);
}

// ---- the simulation's forces ----------------------------------------------------------

MillingCut rigid_cut(const IdentifyCut& cut, const CuttingCoefficients& k, double c, double a,
                     double helix_deg) {
  MillingCut m;
  m.process.tool.teeth = cut.teeth;
  m.process.tool.diameter_m = 0.02;
  m.process.tool.helix_rad = units::deg_to_rad(helix_deg);
  m.process.engagement.entry_rad = cut.entry_rad;
  m.process.engagement.exit_rad = cut.exit_rad;
  m.spindle_rad_s = units::rpm_to_rad_per_s(3000.0);
  m.feed_per_tooth_m = c;
  m.width_m = a;
  m.process.cutting = MechanisticForceLaw{k.kt_pa, k.kr_pa, k.kte_n_per_m, k.kre_n_per_m};
  m.regenerative = false;
  return m;
}

MillingSimulationOptions fine_run() {
  MillingSimulationOptions o;
  o.steps_per_tooth = 2048;
  o.revolutions = 3;
  o.summary_revolutions = 2;
  o.max_recorded_samples = 1 << 20;  // no thinning
  return o;
}

ForceSeries series_of(const MillingSimulationResult& r, double c, double a) {
  ForceSeries s;
  s.time_s = r.time_s;
  s.fx_n = r.fx_n;
  s.fy_n = r.fy_n;
  s.rpm = 3000.0;
  s.feed_per_tooth_m = c;
  s.depth_m = a;
  s.label = "simulation";
  return s;
}

TEST(IdentifyClosedForm, AgreesWithTheSimulationStraightAndHelical) {
  // The simulation's mean force (node forces averaged over 2 revolutions at 2048 steps per
  // tooth) against the closed form, for straight teeth and a 30° helix (a 5 mm deep flute of a
  // 20 mm cutter lags by 0.29 rad: 188 slices): the helix moves each slice's window but not its
  // mean. The node sum is a rectangle rule: within edge_bound at the simulation's step
  // (0.05–0.2 % of the force here; every slice is such a sum with 1/N of the force).
  const CuttingCoefficients k = true_coefficients();
  const double c = 0.08e-3, a = 5e-3;
  for (const Window& w : windows()) {
    const IdentifyCut cut{2, w.entry, w.exit};
    const Eigen::Vector3d closed = mean_milling_force(cut, k, c, a);
    CuttingCoefficients planar = k;  // the simulation has no axial force
    planar.ka_pa = planar.kae_n_per_m = 0.0;
    const double bound = edge_bound(cut, planar, c, a, kTwoPi / (2 * fine_run().steps_per_tooth));
    for (double helix : {0.0, 30.0}) {
      const MillingSimulationResult r =
          simulate_milling(rigid_cut(cut, k, c, a, helix), fine_run());
      const Eigen::Vector2d simulated(r.mean_fx_n, r.mean_fy_n);
      EXPECT_LT((simulated - closed.head<2>()).norm(), bound) << describe(w) << " helix " << helix;
      // The traces' mean over whole revolutions (trapezoids, from the end): the same sum.
      const MeanForce m = mean_over_revolutions(series_of(r, c, a));
      EXPECT_EQ(m.revolutions, 2);
      EXPECT_NEAR(m.fx_n, r.mean_fx_n, 1e-9 * closed.norm()) << describe(w) << " helix " << helix;
      EXPECT_NEAR(m.fy_n, r.mean_fy_n, 1e-9 * closed.norm()) << describe(w) << " helix " << helix;
      if (std::getenv("CUTDYN_IDENTIFY_VERBOSE"))
        std::printf("%s helix %.0f: simulated − closed %.3g N, bound %.3g N, force %.4g N\n",
                    describe(w).c_str(), helix, (simulated - closed.head<2>()).norm(), bound,
                    closed.head<2>().norm());
    }
  }
}

// ---- identification -------------------------------------------------------------------

const std::vector<double> kFeedsMm = {0.02, 0.05, 0.08, 0.11, 0.14, 0.17, 0.2};

// Portable normal deviates (Box–Muller on mt19937_64: the same numbers on every platform).
class Noise {
 public:
  explicit Noise(std::uint64_t seed) : engine_(seed) {}
  double uniform() { return (static_cast<double>(engine_() >> 11) + 0.5) * 0x1.0p-53; }
  double normal() {
    const double u1 = uniform(), u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(kTwoPi * u2);
  }

 private:
  std::mt19937_64 engine_;
};

// Closed-form samples at kFeedsMm and depth 2 mm, with normal noise of standard deviation
// `noise` × the sample's resultant planar force on each component (0: exact).
std::vector<MeanForce> samples_of(const IdentifyCut& cut, const CuttingCoefficients& k,
                                  double noise, std::uint64_t seed, bool axial) {
  Noise rng(seed);
  std::vector<MeanForce> out;
  for (double feed_mm : kFeedsMm) {
    MeanForce m;
    m.feed_per_tooth_m = units::mm_to_m(feed_mm);
    m.depth_m = 2e-3;
    const Eigen::Vector3d f = mean_milling_force(cut, k, m.feed_per_tooth_m, m.depth_m);
    const double sigma = noise * f.head<2>().norm();
    m.fx_n = f.x() + sigma * rng.normal();
    m.fy_n = f.y() + sigma * rng.normal();
    if (axial) m.fz_n = f.z() + sigma * rng.normal();
    m.label = "feed " + std::to_string(feed_mm);
    out.push_back(m);
  }
  return out;
}

struct Estimates {
  std::vector<const char*> names;
  std::vector<IdentifiedCoefficient> fitted;
  std::vector<double> truth;
};

Estimates estimates(const CoefficientFit& f, const CuttingCoefficients& k) {
  Estimates e{{"Kt", "Kr", "Kte", "Kre"},
              {f.kt, f.kr, f.kte, f.kre},
              {k.kt_pa, k.kr_pa, k.kte_n_per_m, k.kre_n_per_m}};
  if (f.ka) {
    e.names.insert(e.names.end(), {"Ka", "Kae"});
    e.fitted.insert(e.fitted.end(), {*f.ka, *f.kae});
    e.truth.insert(e.truth.end(), {k.ka_pa, k.kae_n_per_m});
  }
  return e;
}

TEST(Identify, RecoversExactCoefficientsFromExactMeanForces) {
  const CuttingCoefficients k = true_coefficients();
  for (const Window& w : windows())
    for (int z : {2, 4}) {
      const IdentifyCut cut{z, w.entry, w.exit};
      const CoefficientFit f = identify_coefficients(cut, samples_of(cut, k, 0.0, 1, true));
      const Estimates e = estimates(f, k);
      ASSERT_EQ(e.fitted.size(), 6u);
      for (std::size_t i = 0; i < e.fitted.size(); ++i) {
        EXPECT_NEAR(e.fitted[i].value, e.truth[i], 1e-9 * e.truth[i]) << describe(w) << e.names[i];
        EXPECT_TRUE(e.fitted[i].uncertainty_known);
        EXPECT_LT(e.fitted[i].std_error, 1e-9 * e.truth[i]);
      }
      EXPECT_EQ(f.degrees_of_freedom, 5);
      EXPECT_GT(f.r_squared_y, 1.0 - 1e-12);
      for (const SampleResidual& r : f.residuals) EXPECT_LT(std::abs(r.fx_n), 1e-9);
      EXPECT_EQ(f.residuals.size(), kFeedsMm.size());
      EXPECT_TRUE(f.warnings.empty()) << describe(w) << joined(f.warnings);
    }
}

// The fit is linear in the forces: its weights are the changes of the estimates under a unit
// change of one force. weights[j][3·i + q]: estimate j (Estimates order), sample i, component
// q = x, y, z.
std::vector<std::vector<double>> fit_weights(const IdentifyCut& cut,
                                             const std::vector<MeanForce>& samples) {
  const auto values = [&](const std::vector<MeanForce>& s) {
    const Estimates e = estimates(identify_coefficients(cut, s), CuttingCoefficients{});
    std::vector<double> v;
    for (const IdentifiedCoefficient& c : e.fitted) v.push_back(c.value);
    return v;
  };
  const std::vector<double> base = values(samples);
  std::vector<std::vector<double>> w(base.size(), std::vector<double>(3 * samples.size(), 0.0));
  for (std::size_t i = 0; i < samples.size(); ++i)
    for (std::size_t q = 0; q < 3; ++q) {
      if (q == 2 && !samples[i].fz_n) continue;
      std::vector<MeanForce> moved = samples;
      double& f = q == 0 ? moved[i].fx_n : q == 1 ? moved[i].fy_n : *moved[i].fz_n;
      f += 1.0;
      const std::vector<double> after = values(moved);
      for (std::size_t j = 0; j < base.size(); ++j) w[j][3 * i + q] = after[j] - base[j];
    }
  return w;
}

// The standard deviation of each estimate that the noise of samples_of implies:
// sd² = Σ weight²·σ².
std::vector<double> predicted_sd(const IdentifyCut& cut, const std::vector<MeanForce>& exact,
                                 double noise) {
  const std::vector<std::vector<double>> w = fit_weights(cut, exact);
  std::vector<double> sd;
  for (const std::vector<double>& row : w) {
    double var = 0.0;
    for (std::size_t i = 0; i < exact.size(); ++i) {
      const double sigma = noise * std::hypot(exact[i].fx_n, exact[i].fy_n);
      for (std::size_t q = 0; q < 3; ++q) var += row[3 * i + q] * row[3 * i + q] * sigma * sigma;
    }
    sd.push_back(std::sqrt(var));
  }
  return sd;
}

TEST(Identify, RecoversKnownCoefficientsFromNoisyMeanForces) {
  // 1 % and 2 % noise, seed 7, up and down milling at four immersions and partial windows:
  // every estimate within 4 predicted standard deviations of the truth (a miss has odds of
  // 6e-5 per estimate), the reported standard error within 1/5 to 3 times the predicted one
  // (5 degrees of freedom: s/σ below 1/5 has odds of 6e-4), and the truth inside the reported 95 %
  // interval for at least 90 % of the estimates.
  const CuttingCoefficients k = true_coefficients();
  int inside = 0, total = 0;
  for (double noise : {0.01, 0.02})
    for (const Window& w : windows()) {
      const IdentifyCut cut{2, w.entry, w.exit};
      const std::vector<double> sd = predicted_sd(cut, samples_of(cut, k, 0.0, 0, true), noise);
      const CoefficientFit f = identify_coefficients(cut, samples_of(cut, k, noise, 7, true));
      const Estimates e = estimates(f, k);
      for (std::size_t i = 0; i < e.fitted.size(); ++i) {
        const IdentifiedCoefficient& c = e.fitted[i];
        EXPECT_NEAR(c.value, e.truth[i], 4.0 * sd[i])
            << describe(w) << " noise " << noise << " " << e.names[i];
        EXPECT_GT(c.std_error, sd[i] / 5.0) << describe(w) << " " << e.names[i];
        EXPECT_LT(c.std_error, sd[i] * 3.0) << describe(w) << " " << e.names[i];
        inside += (c.ci95_low <= e.truth[i] && e.truth[i] <= c.ci95_high) ? 1 : 0;
        ++total;
      }
      // Slotting with 1 % noise pins Kt to a fraction of a percent.
      if (noise == 0.01 && w.entry == 0.0 && w.exit == kPi) {
        EXPECT_NEAR(f.kt.value, k.kt_pa, 0.01 * k.kt_pa);
      }
    }
  EXPECT_GE(inside, 0.9 * total) << inside << " of " << total;
}

TEST(Identify, ConfidenceIntervalsCoverTheTruthAtTheirStatedRate) {
  // 50 seeds per window at 1 % noise: the fraction of 95 % intervals holding the true value,
  // per coefficient, must be at least 0.85 (binomial sd at 0.95 over 50 runs: 0.03), and the
  // intervals must not buy it by being wide: the mean reported standard error within 0.75–1.35
  // of the one the noise implies (predicted_sd). The noise is proportional to the force
  // (heteroscedastic), which ordinary least squares assumes away: its pooled s² overstates the
  // noise of the small feeds, on which the intercepts lean, so the edge coefficients' errors
  // come out up to 30 % wide (measured 1.02–1.30) and the cutting ones' 0.79–0.93 of the truth.
  const CuttingCoefficients k = true_coefficients();
  const char* names[] = {"Kt", "Kr", "Kte", "Kre", "Ka", "Kae"};
  for (const Window& w : windows()) {
    const IdentifyCut cut{2, w.entry, w.exit};
    const std::vector<double> sd = predicted_sd(cut, samples_of(cut, k, 0.0, 0, true), 0.01);
    std::vector<int> inside(6, 0);
    std::vector<double> se_sum(6, 0.0);
    const int seeds = 50;
    for (int seed = 1; seed <= seeds; ++seed) {
      const CoefficientFit f = identify_coefficients(
          cut, samples_of(cut, k, 0.01, static_cast<std::uint64_t>(1000 + seed), true));
      const Estimates e = estimates(f, k);
      for (std::size_t i = 0; i < e.fitted.size(); ++i) {
        inside[i] += (e.fitted[i].ci95_low <= e.truth[i] && e.truth[i] <= e.fitted[i].ci95_high);
        se_sum[i] += e.fitted[i].std_error;
      }
    }
    for (std::size_t i = 0; i < 6; ++i) {
      const double coverage = static_cast<double>(inside[i]) / seeds;
      const double se_ratio = se_sum[i] / seeds / sd[i];
      EXPECT_GE(coverage, 0.85) << describe(w) << " " << names[i];
      EXPECT_GT(se_ratio, 0.75) << describe(w) << " " << names[i];
      EXPECT_LT(se_ratio, 1.35) << describe(w) << " " << names[i];
      if (std::getenv("CUTDYN_IDENTIFY_VERBOSE"))
        std::printf("%s %s coverage %.2f se/sd %.3f\n", describe(w).c_str(), names[i], coverage,
                    se_ratio);
    }
  }
}

TEST(Identify, RecoversTheSimulationsCoefficients) {
  // Force records of the rigid simulation (no regeneration) at five feeds, averaged over whole
  // revolutions from their traces, straight and 30° helical teeth: the coefficients put into
  // the simulation come back within what the mean forces' edge error (edge_bound at the
  // simulation's step, per sample and component) can move them through the fit's weights, a
  // worst case of 0.1–3 % (the errors measured are at most 0.16 %). (The axial force is not
  // simulated.)
  const CuttingCoefficients k = true_coefficients();
  CuttingCoefficients planar = k;
  planar.ka_pa = planar.kae_n_per_m = 0.0;
  const std::vector<Window> cases = {{"slot", 0.0, kPi},
                                     {"down 0.25", engagement_window(0.25, true).entry_rad, kPi},
                                     {"up 0.5", 0.0, engagement_window(0.5, false).exit_rad},
                                     {"partial", 1.0, 2.5}};
  const double h = kTwoPi / (2 * fine_run().steps_per_tooth);
  for (const Window& w : cases)
    for (double helix : {0.0, 30.0}) {
      const IdentifyCut cut{2, w.entry, w.exit};
      std::vector<ForceSeries> records;
      std::vector<double> bounds;
      for (double feed_mm : {0.04, 0.07, 0.1, 0.13, 0.16}) {
        const double c = units::mm_to_m(feed_mm), a = 3e-3;
        records.push_back(
            series_of(simulate_milling(rigid_cut(cut, k, c, a, helix), fine_run()), c, a));
        bounds.push_back(edge_bound(cut, planar, c, a, h));
      }
      const std::vector<MeanForce> samples = mean_forces(records);
      const CoefficientFit f = identify_coefficients(cut, samples);
      const Estimates e = estimates(f, k);
      const std::vector<std::vector<double>> weights = fit_weights(cut, samples);
      for (std::size_t j = 0; j < e.fitted.size(); ++j) {
        double tolerance = 0.0;
        for (std::size_t i = 0; i < samples.size(); ++i)
          tolerance += (std::abs(weights[j][3 * i]) + std::abs(weights[j][3 * i + 1])) * bounds[i];
        EXPECT_NEAR(e.fitted[j].value, e.truth[j], tolerance)
            << w.name << " helix " << helix << " " << e.names[j];
        EXPECT_LT(tolerance, 0.03 * e.truth[j]) << w.name << " " << e.names[j];
        if (std::getenv("CUTDYN_IDENTIFY_VERBOSE"))
          std::printf("%s helix %.0f %s: error %.3g %%, tolerance %.3g %%\n", w.name, helix,
                      e.names[j], 100 * (e.fitted[j].value - e.truth[j]) / e.truth[j],
                      100 * tolerance / e.truth[j]);
      }
      EXPECT_FALSE(f.ka.has_value());
    }
}

// ---- warnings and refusals -------------------------------------------------------------

bool has_warning(const CoefficientFit& f, const std::string& text) {
  for (const std::string& w : f.warnings)
    if (w.find(text) != std::string::npos) return true;
  return false;
}

TEST(Identify, WarnsOfANarrowWindowNamingTheCoefficients) {
  // a/D = 0.01 up-milling: φex = 11.5°, the chip matrix's gain is 1.3 % of slotting's, the edge
  // matrix's 10 %.
  const CuttingCoefficients k = true_coefficients();
  const EngagementWindow w = engagement_window(0.01, false);
  const IdentifyCut cut{2, w.entry_rad, w.exit_rad};
  const CoefficientFit f = identify_coefficients(cut, samples_of(cut, k, 0.01, 3, false));
  EXPECT_NEAR(f.chip_gain_ratio, 0.0127, 1e-4);
  EXPECT_NEAR(f.edge_gain_ratio, 0.1, 1e-9);
  EXPECT_TRUE(has_warning(f, "narrow window: the chip matrix's gain")) << f.warnings.size();
  EXPECT_TRUE(has_warning(f, "Kt, Kr carry"));
  EXPECT_FALSE(has_warning(f, "Kte, Kre carry"));
  // And a window of 4°: both.
  const CoefficientFit g = identify_coefficients(
      IdentifyCut{2, 1.5, 1.57}, samples_of(IdentifyCut{2, 1.5, 1.57}, k, 0.0, 3, false));
  EXPECT_TRUE(has_warning(g, "Kt, Kr carry"));
  EXPECT_TRUE(has_warning(g, "Kte, Kre carry"));
  // Slotting and half immersion: none.
  EXPECT_GT(identify_coefficients(IdentifyCut{2, 0, kPi}, samples_of({2, 0, kPi}, k, 0, 3, false))
                .chip_gain_ratio,
            0.999);
}

TEST(Identify, WarnsOfUndeterminedNegativeAndPoorlyFittedCoefficients) {
  const IdentifyCut cut{2, 0.0, kPi};
  CuttingCoefficients k = true_coefficients();
  // 30 % noise: the intervals of the small edge coefficients include zero.
  CoefficientFit f = identify_coefficients(cut, samples_of(cut, k, 0.3, 5, false));
  bool any = false;
  const std::vector<std::pair<std::string, IdentifiedCoefficient>> named = {
      {"Kt", f.kt}, {"Kr", f.kr}, {"Kte", f.kte}, {"Kre", f.kre}};
  for (const auto& [name, c] : named) {
    EXPECT_EQ(has_warning(f, name + " is not determined"), !c.determined()) << name;
    any = any || !c.determined();
  }
  EXPECT_TRUE(any);
  EXPECT_TRUE(has_warning(f, "poor fit"));
  // A negative edge coefficient (exact data): warned, by name.
  k.kre_n_per_m = -5e3;
  f = identify_coefficients(cut, samples_of(cut, k, 0.0, 5, false));
  EXPECT_NEAR(f.kre.value, -5e3, 1e-6);
  EXPECT_TRUE(has_warning(f, "Kre = -5 N/mm is negative"));
  // One bad sample among exact ones: a poor fit.
  std::vector<MeanForce> s = samples_of(cut, true_coefficients(), 0.0, 5, false);
  s[3].fy_n *= 1.5;
  f = identify_coefficients(cut, s);
  EXPECT_TRUE(has_warning(f, "poor fit"));
  EXPECT_GT(std::abs(f.residuals[3].fy_n), 3.0 * std::abs(f.residuals[0].fy_n));
}

TEST(Identify, WarnsOfFewOrCloseFeeds) {
  const IdentifyCut cut{2, 0.0, kPi};
  const CuttingCoefficients k = true_coefficients();
  std::vector<MeanForce> all = samples_of(cut, k, 0.0, 1, false);
  // Two samples at two feeds: exact, but no degrees of freedom.
  CoefficientFit f = identify_coefficients(cut, {all[0], all[6]});
  EXPECT_NEAR(f.kt.value, k.kt_pa, 1e-9 * k.kt_pa);
  EXPECT_FALSE(f.kt.uncertainty_known);
  EXPECT_EQ(f.degrees_of_freedom, 0);
  EXPECT_TRUE(has_warning(f, "only 2 distinct feeds"));
  EXPECT_TRUE(has_warning(f, "no residual degrees of freedom"));
  // Repeats at two feeds: degrees of freedom, still only two feeds.
  f = identify_coefficients(cut, {all[0], all[0], all[6], all[6]});
  EXPECT_TRUE(f.kt.uncertainty_known);
  EXPECT_TRUE(has_warning(f, "only 2 distinct feeds"));
  EXPECT_FALSE(has_warning(f, "no residual degrees of freedom"));
  // Feeds 0.17 and 0.2 mm and one between: they span 15 % of the largest.
  f = identify_coefficients(cut, {all[5], all[6], samples_of(cut, k, 0, 1, false)[5]});
  EXPECT_TRUE(has_warning(f, "only 2 distinct feeds"));
  MeanForce mid = all[5];
  mid.feed_per_tooth_m = 0.185e-3;
  const Eigen::Vector3d fm = mean_milling_force(cut, k, mid.feed_per_tooth_m, mid.depth_m);
  mid.fx_n = fm.x();
  mid.fy_n = fm.y();
  f = identify_coefficients(cut, {all[5], mid, all[6]});
  EXPECT_TRUE(has_warning(f, "the feeds span only 15 %")) << f.warnings.size();
}

TEST(Identify, DepthsMayDiffer) {
  // F̄/a is fitted: samples at 1, 2 and 4 mm give the same coefficients.
  const IdentifyCut cut{3, engagement_window(0.5, true).entry_rad, kPi};
  const CuttingCoefficients k = true_coefficients();
  std::vector<MeanForce> s = samples_of(cut, k, 0.0, 1, true);
  for (std::size_t i = 0; i < s.size(); ++i) {
    s[i].depth_m = 1e-3 * static_cast<double>(1 << (i % 3));
    const Eigen::Vector3d f = mean_milling_force(cut, k, s[i].feed_per_tooth_m, s[i].depth_m);
    s[i].fx_n = f.x();
    s[i].fy_n = f.y();
    s[i].fz_n = f.z();
  }
  const CoefficientFit fit = identify_coefficients(cut, s);
  EXPECT_NEAR(fit.kt.value, k.kt_pa, 1e-9 * k.kt_pa);
  EXPECT_NEAR(fit.kre.value, k.kre_n_per_m, 1e-9 * k.kre_n_per_m);
  EXPECT_NEAR(fit.ka->value, k.ka_pa, 1e-9 * k.ka_pa);
  EXPECT_NEAR(fit.kae->value, k.kae_n_per_m, 1e-9 * k.kae_n_per_m);
}

std::vector<std::string> problems_of(const IdentifyCut& cut, const std::vector<MeanForce>& s) {
  try {
    identify_coefficients(cut, s);
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where(), "identify");
    return e.problems();
  }
  ADD_FAILURE() << "accepted";
  return {};
}

TEST(Identify, RefusesBadInput) {
  using ::testing::ElementsAre;
  const IdentifyCut slot{2, 0.0, kPi};
  const std::vector<MeanForce> good = samples_of(slot, true_coefficients(), 0.0, 1, false);
  // Fewer than two distinct feeds.
  EXPECT_THAT(problems_of(slot, {}), ElementsAre(HasSubstr("need at least 2 distinct feeds")));
  EXPECT_THAT(problems_of(slot, {good[2], good[2], good[2]}),
              ElementsAre(HasSubstr("3 sample(s) at 1 distinct feed(s)")));
  // The window.
  EXPECT_THAT(problems_of({2, -0.1, kPi}, good),
              ElementsAre("cut.entry_rad = -0.1 rad: must be in [0, π]"));
  EXPECT_THAT(problems_of({2, 0.0, 3.2}, good),
              ElementsAre("cut.exit_rad = 3.2 rad: must be in [0, π]"));
  EXPECT_THAT(problems_of({2, 1.0, 1.0}, good),
              ElementsAre(HasSubstr("the entry must come before the exit")));
  EXPECT_THAT(problems_of({0, 0.0, kPi}, good), ElementsAre(HasSubstr("cut.teeth = 0")));
  EXPECT_THAT(problems_of({2, std::nan(""), kPi}, good),
              ElementsAre("cut.entry_rad = nan rad: must be a finite number"));
  // Samples: named by index and label, every problem listed.
  std::vector<MeanForce> bad = good;
  bad[1].feed_per_tooth_m = 0.0;
  bad[2].depth_m = -1e-3;
  bad[3].fy_n = std::nan("");
  bad[4].fz_n = 10.0;
  EXPECT_THAT(
      problems_of(slot, bad),
      ElementsAre("samples[1] (feed 0.050000): feed_per_tooth_m = 0 m: must be positive",
                  "samples[2] (feed 0.080000): depth_m = -0.001 m: must be positive",
                  "samples[3] (feed 0.110000): fy_n = nan N: must be a finite number",
                  HasSubstr("samples[4] (feed 0.140000): fz_n given but not for samples[0]")));
}

// ---- mean over whole revolutions --------------------------------------------------------

ForceSeries synthetic_series(double revolutions, int per_rev, double rpm) {
  ForceSeries s;
  const double period = 60.0 / rpm;
  const int n = static_cast<int>(std::lround(revolutions * per_rev));
  for (int i = 0; i <= n; ++i) {
    const double t = 0.013 + period * i / per_rev;
    s.time_s.push_back(t);
    // A mean, harmonics of the revolution and of the tooth period, and a slow drift.
    const double phase = kTwoPi * (t - 0.013) / period;
    s.fx_n.push_back(10.0 + 4.0 * std::sin(phase) + 2.0 * std::cos(3.0 * phase) + 100.0 * t);
    s.fy_n.push_back(-5.0 + 3.0 * std::sin(2.0 * phase + 0.4));
    s.fz_n.push_back(1.0);
  }
  s.rpm = rpm;
  s.feed_per_tooth_m = 0.1e-3;
  s.depth_m = 2e-3;
  s.label = "synthetic";
  return s;
}

TEST(MeanOverRevolutions, AveragesTheLastWholeRevolutions) {
  // 3.4 revolutions at 3000 rpm, 100 samples each: the last 3 revolutions (the record's end),
  // where the harmonics average out to rounding and the drift 100·t averages to its value at
  // the middle of those 3 revolutions (the trapezoidal rule is exact for it). From the start it
  // would be 100·(0.013 + 0.03) = 4.3 N, from the end 100·(0.013 + 0.068 − 0.03) = 5.1 N.
  const ForceSeries s = synthetic_series(3.4, 100, 3000.0);
  const MeanForce m = mean_over_revolutions(s);
  EXPECT_EQ(m.revolutions, 3);
  const double t_end = s.time_s.back(), middle = t_end - 0.03;
  EXPECT_NEAR(m.fx_n, 10.0 + 100.0 * middle, 1e-9);
  EXPECT_NEAR(m.fy_n, -5.0, 1e-12);
  EXPECT_NEAR(*m.fz_n, 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(m.feed_per_tooth_m, 0.1e-3);
  EXPECT_EQ(m.label, "synthetic");
  // Exactly two revolutions of samples: both used.
  EXPECT_EQ(mean_over_revolutions(synthetic_series(2.0, 64, 3000.0)).revolutions, 2);
  // Uneven sampling: the trapezoids still give the mean of the linear drift exactly.
  ForceSeries u = synthetic_series(2.5, 50, 3000.0);
  for (std::size_t i = 1; i + 1 < u.time_s.size(); i += 2) u.time_s[i] += 0.1 * 0.02 / 50;
  for (std::size_t i = 0; i < u.time_s.size(); ++i) u.fx_n[i] = 100.0 * u.time_s[i];
  EXPECT_NEAR(mean_over_revolutions(u).fx_n, 100.0 * (u.time_s.back() - 0.02), 1e-9);
}

std::vector<std::string> series_problems(const ForceSeries& s) {
  try {
    mean_over_revolutions(s);
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where(), s.label);
    return e.problems();
  }
  ADD_FAILURE() << "accepted";
  return {};
}

TEST(MeanOverRevolutions, RefusesShortOrBrokenRecords) {
  using ::testing::ElementsAre;
  ForceSeries s = synthetic_series(0.9, 100, 3000.0);
  EXPECT_THAT(series_problems(s), ElementsAre(HasSubstr("less than one revolution (0.02 s at "
                                                        "3000 rpm)")));
  s = synthetic_series(2.0, 10, 3000.0);
  s.time_s[4] = s.time_s[3];
  EXPECT_THAT(series_problems(s), ElementsAre(HasSubstr("time_s[4] = ")));
  s = synthetic_series(2.0, 10, 3000.0);
  s.fy_n.pop_back();
  s.rpm = 0.0;
  EXPECT_THAT(series_problems(s),
              ElementsAre("rpm = 0 rpm: must be positive", "fy_n: 20 values for 21 times"));
  s = synthetic_series(2.0, 10, 3000.0);
  s.fx_n[7] = std::numeric_limits<double>::infinity();
  s.depth_m = 0.0;
  EXPECT_THAT(series_problems(s), ElementsAre("depth_m = 0 m: must be positive",
                                              "fx_n[7] = inf N: must be a finite number"));
  // Several records: every record's problems, named.
  ForceSeries a = synthetic_series(0.5, 10, 3000.0), b = synthetic_series(2, 10, 3000.0);
  a.label = "a.csv";
  b.label = "b.csv";
  b.feed_per_tooth_m = -1.0;
  try {
    mean_forces({a, b});
    ADD_FAILURE() << "accepted";
  } catch (const InvalidInput& e) {
    EXPECT_THAT(e.problems(), ElementsAre(HasSubstr("a.csv: time_s spans"),
                                          "b.csv: feed_per_tooth_m = -1 m: must be positive"));
  }
}

// Found by fuzz_force_file (docs/fuzzing.md): a speed of 1e32 rpm (a force file's
// `# rpm = ...`) made the count of whole revolutions 1e28, converted to int regardless
// (undefined; -2147483648 on x86-64, a negative averaging length).
TEST(MeanOverRevolutions, FuzzMoreRevolutionsThanAnIntHoldsAreRefused) {
  using ::testing::ElementsAre;
  ForceSeries s = synthetic_series(2.0, 10, 3000.0);
  s.rpm = 1e32;
  EXPECT_THAT(series_problems(s), ElementsAre(HasSubstr("s, more than 1e9 revolutions")));
  s.rpm = 3000.0;
  s.time_s.back() = 1e10;
  EXPECT_THAT(series_problems(s), ElementsAre(HasSubstr("more than 1e9 revolutions (0.02 s at "
                                                        "3000 rpm): is the speed or the time")));
}

TEST(StudentT, QuantilesMatchTheTables) {
  // Exact: ν = 1 is Cauchy (t = tan(π(p − ½))), ν = 2 has t = A·√2/√(1 − A²), A = 2p − 1.
  EXPECT_NEAR(student_t_quantile(0.75, 1), 1.0, 1e-12);
  EXPECT_NEAR(student_t_quantile(0.975, 1), std::tan(kPi * 0.475), 1e-9);
  const double a = 0.95;
  EXPECT_NEAR(student_t_quantile(0.975, 2), a * std::sqrt(2.0) / std::sqrt(1 - a * a), 1e-12);
  // Printed tables (4 decimals), and the normal limit.
  EXPECT_NEAR(student_t_quantile(0.975, 3), 3.1824, 5e-5);
  EXPECT_NEAR(student_t_quantile(0.975, 5), 2.5706, 5e-5);
  EXPECT_NEAR(student_t_quantile(0.975, 10), 2.2281, 5e-5);
  EXPECT_NEAR(student_t_quantile(0.975, 30), 2.0423, 5e-5);
  EXPECT_NEAR(student_t_quantile(0.95, 7), 1.8946, 5e-5);
  EXPECT_NEAR(student_t_quantile(0.975, 100000), 1.95996, 5e-5);
  EXPECT_NEAR(student_t_quantile(0.025, 5), -2.5706, 5e-5);
  EXPECT_EQ(student_t_quantile(0.5, 4), 0.0);
}

}  // namespace
}  // namespace cutdyn
