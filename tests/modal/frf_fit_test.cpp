// Modal fitting (docs/models/modal-fitting.md §7): synthetic receptances of known modes, with
// and without 1 % complex Gaussian noise (fixed seeds), fitted with the number of modes given
// and chosen automatically; bands that cut modes away; bad input; flat and pure-noise tables.
#include "cutdyn/modal/frf_fit.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "cutdyn/core/error.hpp"

namespace cutdyn {
namespace {

using cd = std::complex<double>;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

Mode mode(double f_hz, double zeta, double k, Direction d = Direction::kX) {
  return Mode{d, kTwoPi * f_hz, zeta, k};
}

// 0…3000 Hz by 2 Hz, as an impact test on a tool would give.
std::vector<double> grid() { return linear_frequencies(0.0, 3000.0, 1501); }

// G·(1 + ε), ε complex Gaussian with real and imaginary parts of standard deviation `level`.
MeasuredFrf with_noise(MeasuredFrf frf, double level, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, level);
  for (cd& g : frf.receptance_m_per_n) g *= 1.0 + cd(n(rng), n(rng));
  return frf;
}

const ModalModel kTwoModes{{mode(500, 0.02, 2e7), mode(1200, 0.05, 5e7)}};
// Two modes 10 % apart (800 and 880 Hz), damping from 0.01 to 0.08.
const ModalModel kFourModes{
    {mode(300, 0.03, 3e7), mode(800, 0.01, 4e7), mode(880, 0.04, 5e7), mode(2000, 0.08, 2e7)}};

struct Tolerance {
  double frequency, damping, stiffness;  // relative
};
constexpr Tolerance kNoisy{0.005, 0.05, 0.03};

// The fit's modes match `expected` (sorted by frequency) one to one within `tol`.
void expect_modes(const FrfFit& fit, const std::vector<Mode>& expected, Tolerance tol,
                  const std::string& what) {
  ASSERT_EQ(fit.modes.size(), expected.size()) << what;
  ASSERT_EQ(fit.model.modes.size(), expected.size()) << what;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const Mode& e = expected[i];
    const FittedMode& m = fit.modes[i];
    const std::string at = what + ", mode " + std::to_string(e.natural_rad_s / kTwoPi) + " Hz";
    EXPECT_NEAR(m.natural_rad_s / e.natural_rad_s, 1.0, tol.frequency) << at;
    EXPECT_NEAR(m.natural_hz * kTwoPi / e.natural_rad_s, 1.0, tol.frequency) << at;
    EXPECT_NEAR(m.damping_ratio / e.damping_ratio, 1.0, tol.damping) << at;
    EXPECT_NEAR(m.stiffness_n_per_m / e.stiffness_n_per_m, 1.0, tol.stiffness) << at;
    const Mode& out = fit.model.modes[i];
    EXPECT_EQ(out.direction, fit.direction) << at;
    EXPECT_DOUBLE_EQ(out.natural_rad_s, m.natural_rad_s) << at;
    EXPECT_DOUBLE_EQ(out.damping_ratio, m.damping_ratio) << at;
    EXPECT_DOUBLE_EQ(out.stiffness_n_per_m, m.stiffness_n_per_m) << at;
  }
}

bool has_warning(const FrfFit& fit, const std::string& text) {
  return std::any_of(fit.warnings.begin(), fit.warnings.end(),
                     [&](const std::string& w) { return w.find(text) != std::string::npos; });
}

bool all_finite(const FrfFit& fit) {
  bool ok = std::isfinite(fit.rms_relative_error);
  for (const FittedMode& m : fit.modes)
    ok = ok && std::isfinite(m.natural_hz) && std::isfinite(m.damping_ratio) &&
         std::isfinite(m.stiffness_n_per_m) && std::isfinite(m.residue.real()) &&
         std::isfinite(m.residue.imag()) && std::isfinite(m.contribution);
  return ok;
}

std::vector<std::string> problems_of(const MeasuredFrf& frf, const FrfFitOptions& options) {
  try {
    fit_modes(frf, Direction::kX, options);
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where(), "fit");
    return e.problems();
  }
  ADD_FAILURE() << "no InvalidInput";
  return {};
}

// ---- exact data -------------------------------------------------------------------------

TEST(FrfFit, NoiseFreeModesAreRecoveredToRoundOff) {
  for (const ModalModel* model : {&kTwoModes, &kFourModes}) {
    const MeasuredFrf frf = sample_frf(*model, Direction::kX, grid());
    for (int modes : {0, static_cast<int>(model->modes.size())}) {
      const FrfFit fit = fit_modes(frf, Direction::kX, FrfFitOptions{.modes = modes});
      const std::string what =
          std::to_string(model->modes.size()) + " modes, asked " + std::to_string(modes);
      EXPECT_EQ(fit.automatic, modes == 0) << what;
      expect_modes(fit, model->modes, {1e-6, 1e-6, 1e-6}, what);
      EXPECT_LT(fit.rms_relative_error, 1e-9) << what;
      EXPECT_TRUE(fit.converged) << what;
      EXPECT_TRUE(fit.warnings.empty()) << what << ": " << fit.warnings.front();
      for (const FittedMode& m : fit.modes) {
        EXPECT_LT(std::abs(m.residue_phase_deg), 1e-4) << what;
        // A = −i·ωn²/(2·k·ωd) for a real mode (docs §1).
        const double wd = m.natural_rad_s * std::sqrt(1 - m.damping_ratio * m.damping_ratio);
        EXPECT_NEAR(
            -m.residue.imag() * 2 * m.stiffness_n_per_m * wd / (m.natural_rad_s * m.natural_rad_s),
            1.0, 1e-9);
      }
      // The whole table was fitted; no lower residual with a band from 0 Hz.
      EXPECT_EQ(fit.points, 1501);
      EXPECT_EQ(fit.lo_hz, 0.0);
      EXPECT_EQ(fit.hi_hz, 3000.0);
      EXPECT_FALSE(fit.residuals.lower_used);
      EXPECT_TRUE(fit.residuals.upper_used);
    }
  }
}

// ---- 1 % noise ----------------------------------------------------------------------------

TEST(FrfFit, TwoModesWithNoiseGivenCountAndAutomatic) {
  const MeasuredFrf exact = sample_frf(kTwoModes, Direction::kX, grid());
  for (unsigned seed : {1u, 2u, 3u, 4u, 5u}) {
    const MeasuredFrf frf = with_noise(exact, 0.01, seed);
    for (int modes : {0, 2}) {
      const FrfFit fit = fit_modes(frf, Direction::kX, FrfFitOptions{.modes = modes});
      const std::string what = "seed " + std::to_string(seed) + ", asked " + std::to_string(modes);
      expect_modes(fit, kTwoModes.modes, kNoisy, what);
      // The residual is the noise: sqrt(2)·1 % RMS.
      EXPECT_NEAR(fit.rms_relative_error, 0.01 * std::sqrt(2.0), 0.002) << what;
      EXPECT_FALSE(has_warning(fit, "poor fit")) << what;
    }
  }
}

TEST(FrfFit, FourModesWithCloseModesAndLightToHeavyDamping) {
  const MeasuredFrf exact = sample_frf(kFourModes, Direction::kX, grid());
  for (unsigned seed : {11u, 12u, 13u, 14u, 15u}) {
    const MeasuredFrf frf = with_noise(exact, 0.01, seed);
    for (int modes : {0, 4}) {
      const FrfFit fit = fit_modes(frf, Direction::kX, FrfFitOptions{.modes = modes});
      expect_modes(fit, kFourModes.modes, kNoisy,
                   "seed " + std::to_string(seed) + ", asked " + std::to_string(modes));
    }
  }
}

TEST(FrfFit, StronglyOverlappingPairIsSeparated) {
  // 800 Hz at ζ = 0.01 under the skirt of 880 Hz at ζ = 0.08 (half-power width 141 Hz).
  const ModalModel pair{{mode(800, 0.01, 4e7), mode(880, 0.08, 5e7)}};
  const MeasuredFrf exact = sample_frf(pair, Direction::kX, grid());
  for (unsigned seed : {21u, 22u, 23u}) {
    const FrfFit fit = fit_modes(with_noise(exact, 0.01, seed), Direction::kX);
    expect_modes(fit, pair.modes, kNoisy, "seed " + std::to_string(seed));
  }
}

TEST(FrfFit, FittedFrfIsCloserToTheTruthThanTheNoisyData) {
  const MeasuredFrf exact = sample_frf(kFourModes, Direction::kX, grid());
  const MeasuredFrf noisy = with_noise(exact, 0.01, 7);
  const FrfFit fit = fit_modes(noisy, Direction::kX);
  const MeasuredFrf back = fitted_frf(fit, exact.frequency_hz);
  EXPECT_TRUE(back.validate().empty());
  double data_error = 0.0, fit_error = 0.0;
  for (std::size_t i = 0; i < exact.frequency_hz.size(); ++i) {
    const double scale = std::norm(exact.receptance_m_per_n[i]);
    data_error += std::norm(noisy.receptance_m_per_n[i] - exact.receptance_m_per_n[i]) / scale;
    fit_error += std::norm(back.receptance_m_per_n[i] - exact.receptance_m_per_n[i]) / scale;
  }
  const double n = static_cast<double>(exact.frequency_hz.size());
  EXPECT_NEAR(std::sqrt(data_error / n), 0.01 * std::sqrt(2.0), 0.001);
  // 16 real-mode parameters and 3 residual terms against 3002 noisy numbers: the fit averages
  // the noise away (its error is near 1.4 %·sqrt(19/3002) ≈ 0.1 %).
  EXPECT_LT(std::sqrt(fit_error / n), 0.003) << std::sqrt(fit_error / n);
}

// ---- bands --------------------------------------------------------------------------------

TEST(FrfFit, BandCuttingTheLowestModeAwayUsesTheLowerResidual) {
  const MeasuredFrf exact = sample_frf(kFourModes, Direction::kX, grid());
  const std::vector<Mode> inside(kFourModes.modes.begin() + 1, kFourModes.modes.end());
  for (unsigned seed : {31u, 32u, 33u}) {
    for (int modes : {0, 3}) {
      const FrfFit fit = fit_modes(with_noise(exact, 0.01, seed), Direction::kX,
                                   FrfFitOptions{.modes = modes, .lo_hz = 500.0});
      expect_modes(fit, inside, kNoisy, "500…3000 Hz, seed " + std::to_string(seed));
      EXPECT_EQ(fit.lo_hz, 500.0);
      EXPECT_EQ(fit.points, 1251);
      EXPECT_TRUE(fit.residuals.lower_used);
      EXPECT_TRUE(fit.residuals.upper_used);
      // The 300 Hz mode seen from above: −(ωn²/k)/ω² to first order, a positive L2.
      EXPECT_GT(fit.residuals.l2_per_kg, 0.0);
    }
  }
}

TEST(FrfFit, BandCuttingTheHighestModeAwayUsesTheUpperResidual) {
  const MeasuredFrf exact = sample_frf(kFourModes, Direction::kX, grid());
  const std::vector<Mode> inside(kFourModes.modes.begin(), kFourModes.modes.end() - 1);
  for (unsigned seed : {41u, 42u, 43u}) {
    for (int modes : {0, 3}) {
      const FrfFit fit = fit_modes(with_noise(exact, 0.01, seed), Direction::kX,
                                   FrfFitOptions{.modes = modes, .hi_hz = 1200.0});
      expect_modes(fit, inside, kNoisy, "0…1200 Hz, seed " + std::to_string(seed));
      EXPECT_FALSE(fit.residuals.lower_used);
      EXPECT_TRUE(fit.residuals.upper_used);
      // The 2000 Hz mode seen from below: its static flexibility 1/k = 5e-8 m/N to first order.
      EXPECT_NEAR(fit.residuals.u0_m_per_n / (1.0 / 2e7), 1.0, 0.1);
    }
  }
}

TEST(FrfFit, ResidualsApplyInsideTheBandOnly) {
  const MeasuredFrf exact = sample_frf(kFourModes, Direction::kX, grid());
  const FrfFit fit = fit_modes(exact, Direction::kX, FrfFitOptions{.lo_hz = 500.0});
  ASSERT_TRUE(fit.residuals.lower_used);
  const MeasuredFrf back = fitted_frf(fit, {0.0, 100.0, 499.0, 800.0, 2000.0});
  ModalModel modes_only = fit.model;  // real modes: the fitted residues are real to 0.5°
  for (std::size_t i = 0; i < 3; ++i) {
    const cd g = back.receptance_m_per_n[i];
    const cd m = frf(modes_only, Direction::kX, kTwoPi * back.frequency_hz[i]);
    EXPECT_LT(std::abs(g - m), 0.02 * std::abs(m)) << back.frequency_hz[i];
  }
  for (std::size_t i = 3; i < 5; ++i) {  // at resonances: the whole fitted model
    const cd truth = frf(kFourModes, Direction::kX, kTwoPi * back.frequency_hz[i]);
    EXPECT_LT(std::abs(back.receptance_m_per_n[i] - truth), 1e-2 * std::abs(truth));
  }
}

TEST(FrfFit, BandReachingBeyondTheTableIsClippedWithAWarning) {
  const MeasuredFrf frf = sample_frf(kTwoModes, Direction::kX, linear_frequencies(100, 3000, 1451));
  const FrfFit fit = fit_modes(frf, Direction::kX, FrfFitOptions{.lo_hz = 0.0, .hi_hz = 5000.0});
  EXPECT_EQ(fit.lo_hz, 100.0);
  EXPECT_EQ(fit.hi_hz, 3000.0);
  EXPECT_TRUE(has_warning(fit, "beyond the table")) << fit.warnings.size();
  expect_modes(fit, kTwoModes.modes, {1e-6, 1e-6, 1e-6}, "clipped band");
}

// ---- what the result says -----------------------------------------------------------------

TEST(FrfFit, StabilisationDiagramShowsEachModeAsStablePoles) {
  const FrfFit fit =
      fit_modes(with_noise(sample_frf(kFourModes, Direction::kX, grid()), 0.01, 3), Direction::kX);
  ASSERT_FALSE(fit.stabilisation.empty());
  int max_order = 0;
  for (const StabilisationPoint& p : fit.stabilisation) {
    EXPECT_GT(p.damping_ratio, 0.0);
    EXPECT_LT(p.damping_ratio, 0.5);
    EXPECT_GE(p.natural_hz, fit.lo_hz);
    EXPECT_LE(p.natural_hz, fit.hi_hz);
    max_order = std::max(max_order, p.order);
  }
  EXPECT_EQ(max_order, 48);  // 4 × max_modes
  for (const Mode& m : kFourModes.modes) {
    const double f = m.natural_rad_s / kTwoPi;
    const auto stable = std::count_if(fit.stabilisation.begin(), fit.stabilisation.end(),
                                      [&](const StabilisationPoint& p) {
                                        return p.stable && std::abs(p.natural_hz - f) < 0.01 * f;
                                      });
    EXPECT_GE(stable, 14) << f << " Hz";  // the automatic choice needs 5 (48 / 10)
  }
}

TEST(FrfFit, ComplexResidueIsKeptInTheModelWithItsPhase) {
  // A non-proportionally damped mode: residue A = |A|·(−i)·e^(i·20°).
  const double wn = kTwoPi * 900.0, zeta = 0.03, k = 4e7;
  const double wd = wn * std::sqrt(1 - zeta * zeta);
  const cd pole{-zeta * wn, wd};
  const cd a = wn * wn / (2 * k * wd) * cd(0, -1) * std::polar(1.0, 20.0 * std::numbers::pi / 180);
  MeasuredFrf frf;
  frf.frequency_hz = grid();
  for (double f : frf.frequency_hz) {
    const cd s{0, kTwoPi * f};
    frf.receptance_m_per_n.push_back(a / (s - pole) + std::conj(a) / (s - std::conj(pole)));
  }
  const FrfFit fit = fit_modes(frf, Direction::kY);
  ASSERT_EQ(fit.modes.size(), 1u);
  EXPECT_NEAR(fit.modes[0].residue_phase_deg, 20.0, 1e-6);
  EXPECT_NEAR(fit.modes[0].stiffness_n_per_m / k, 1.0, 1e-6);  // from |A|
  EXPECT_NEAR(fit.modes[0].natural_hz, 900.0, 1e-6);
  // A note (the model keeps the phase, nothing is approximated), not a warning.
  EXPECT_FALSE(has_warning(fit, "complex residue")) << fit.warnings.size();
  ASSERT_EQ(fit.notes.size(), 1u);
  EXPECT_NE(fit.notes[0].find("complex residue (20°"), std::string::npos) << fit.notes[0];
  ASSERT_EQ(fit.model.modes.size(), 1u);
  EXPECT_EQ(fit.model.modes[0].direction, Direction::kY);
  EXPECT_NEAR(fit.model.modes[0].residue_phase_rad, 20.0 * std::numbers::pi / 180, 1e-8);
  // The model every method uses is the table: the modes alone reproduce it to rounding (the
  // same fit with the phase dropped, a real mode, misses it by about sin 20° = 34 %).
  EXPECT_LT(fit.model_rms_relative_error, 1e-8);
  ModalModel real = fit.model;
  real.modes[0].residue_phase_rad = 0.0;
  double sum = 0.0;
  for (std::size_t i = 0; i < frf.frequency_hz.size(); ++i) {
    const cd g = frf.receptance_m_per_n[i];
    sum += std::norm((cutdyn::frf(real, Direction::kY, kTwoPi * frf.frequency_hz[i]) - g) / g);
  }
  EXPECT_GT(std::sqrt(sum / static_cast<double>(frf.frequency_hz.size())), 0.2);
}

TEST(FrfFit, TheModesAloneMissingTheTableAreWarned) {
  // A 2000 Hz mode (ζ = 0.08) cut away by a band 0…1200 Hz: the fit absorbs it in its residual
  // terms, the modes alone (what the time-domain methods use) do not. Two modes in the band.
  const ModalModel truth{{Mode{Direction::kX, kTwoPi * 500.0, 0.02, 2e7},
                          Mode{Direction::kX, kTwoPi * 900.0, 0.03, 3e7},
                          Mode{Direction::kX, kTwoPi * 2000.0, 0.08, 4e6}}};
  const MeasuredFrf frf = sample_frf(truth, Direction::kX, linear_frequencies(0.0, 3000.0, 1501));
  FrfFitOptions o;
  o.hi_hz = 1200.0;
  const FrfFit fit = fit_modes(frf, Direction::kX, o);
  ASSERT_EQ(fit.modes.size(), 2u);
  EXPECT_LT(fit.rms_relative_error, 0.02);
  EXPECT_GT(fit.model_rms_relative_error, 0.05);
  EXPECT_TRUE(has_warning(fit, "the modes alone reproduce the table to"));
  // Over the whole table the same structure needs no such warning.
  const FrfFit whole = fit_modes(frf, Direction::kX);
  EXPECT_LT(whole.model_rms_relative_error, 1e-6);
  EXPECT_FALSE(has_warning(whole, "the modes alone"));
}

TEST(FrfFit, NegativeStiffnessModeIsDropped) {
  // A cross receptance: the 1200 Hz mode enters with a negative sign. Without it the fit
  // misses part of the data: the 500 Hz mode moves and the fit is poor, which is said.
  MeasuredFrf frf = sample_frf(ModalModel{{kTwoModes.modes[0]}}, Direction::kX, grid());
  const MeasuredFrf second = sample_frf(ModalModel{{kTwoModes.modes[1]}}, Direction::kX, grid());
  for (std::size_t i = 0; i < frf.frequency_hz.size(); ++i)
    frf.receptance_m_per_n[i] -= second.receptance_m_per_n[i];
  const FrfFit fit = fit_modes(frf, Direction::kX);
  ASSERT_EQ(fit.modes.size(), 1u);
  EXPECT_NEAR(fit.modes[0].natural_hz, 500.0, 25.0);
  EXPECT_TRUE(has_warning(fit, "pole at 1200.0 Hz: negative stiffness"));
  EXPECT_TRUE(has_warning(fit, "poor fit"));
  EXPECT_TRUE(fit.model.validate().empty());
  // Asked for two modes, one of which is a negative stiffness: refused, saying why.
  const auto problems = problems_of(frf, {.modes = 2});
  ASSERT_EQ(problems.size(), 2u);
  EXPECT_NE(problems[0].find("modes = 2: the band 0…3000 Hz holds 1 distinct"), std::string::npos);
  EXPECT_NE(problems[1].find("pole at 1200.0 Hz: negative stiffness"), std::string::npos);
}

TEST(FrfFit, ModeAtTheBandsEdgeIsWarned) {
  const ModalModel model{{mode(500, 0.02, 2e7), mode(2950, 0.03, 5e7)}};
  const FrfFit fit = fit_modes(sample_frf(model, Direction::kX, grid()), Direction::kX);
  ASSERT_EQ(fit.modes.size(), 2u);
  EXPECT_TRUE(has_warning(fit, "mode at 2950.0 Hz: its half-power band")) << fit.warnings.size();
  EXPECT_FALSE(has_warning(fit, "mode at 500.0 Hz"));
}

TEST(FrfFit, ContributionsRankTheModes) {
  // The 500 Hz mode dominates its neighbourhood; a mode ten times stiffer contributes less.
  const ModalModel model{{mode(500, 0.02, 2e7), mode(1500, 0.02, 2e8)}};
  const FrfFit fit = fit_modes(sample_frf(model, Direction::kX, grid()), Direction::kX);
  ASSERT_EQ(fit.modes.size(), 2u);
  EXPECT_GT(fit.modes[0].contribution, fit.modes[1].contribution);
  for (const FittedMode& m : fit.modes) EXPECT_GT(m.contribution, 0.1);
}

// ---- flat, noise, bad input ---------------------------------------------------------------

TEST(FrfFit, FlatOrPureNoiseTableGivesNoModeAndNoNaN) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  MeasuredFrf flat, noise;
  flat.frequency_hz = noise.frequency_hz = grid();
  for (std::size_t i = 0; i < flat.frequency_hz.size(); ++i) {
    flat.receptance_m_per_n.push_back(cd(1e-7, 0) * (1.0 + 0.01 * cd(n(rng), n(rng))));
    noise.receptance_m_per_n.push_back(1e-8 * cd(n(rng), n(rng)));
  }
  for (const MeasuredFrf* frf : {&flat, &noise}) {
    const FrfFit fit = fit_modes(*frf, Direction::kX);
    EXPECT_TRUE(fit.modes.empty());
    EXPECT_TRUE(fit.model.modes.empty());
    EXPECT_TRUE(has_warning(fit, "no mode found"));
    EXPECT_TRUE(all_finite(fit));
    // Asked for 3 modes, the fit finds none it can keep: refused, with the poles it dropped.
    const auto problems = problems_of(*frf, {.modes = 3});
    ASSERT_FALSE(problems.empty());
    EXPECT_NE(problems[0].find("modes = 3: the band 0…3000 Hz holds"), std::string::npos)
        << problems[0];
  }
  const FrfFit fit = fit_modes(flat, Direction::kX);
  EXPECT_NEAR(fit.residuals.u0_m_per_n, 1e-7, 1e-9);  // the flexibility is the residual
}


void expect_problem(const std::vector<std::string>& problems, const std::string& text) {
  const bool found = std::any_of(problems.begin(), problems.end(), [&](const std::string& p) {
    return p.find(text) != std::string::npos;
  });
  EXPECT_TRUE(found) << text << " not in: " << (problems.empty() ? "" : problems.front());
}

TEST(FrfFit, BadInputIsRefusedNamingWhatIsWrong) {
  const MeasuredFrf frf = sample_frf(kTwoModes, Direction::kX, grid());
  // 1000…1010 Hz holds 6 points.
  expect_problem(problems_of(frf, {.lo_hz = 1000.0, .hi_hz = 1010.0}),
                 "band 1000…1010 Hz: holds 6 of the table's points");
  expect_problem(problems_of(frf, {.lo_hz = 4000.0, .hi_hz = 5000.0}),
                 "band 4000…5000 Hz: holds 0 of the table's points (0…3000 Hz)");
  // 1000…1100 Hz: 51 points, at most 12 modes.
  expect_problem(problems_of(frf, {.modes = 13, .lo_hz = 1000.0, .hi_hz = 1100.0}),
                 "modes = 13: more than a quarter of the 51 points");
  expect_problem(problems_of(frf, {.modes = -1}), "modes = -1");
  expect_problem(problems_of(frf, {.max_modes = 0}), "max_modes = 0");
  expect_problem(problems_of(frf, {.lo_hz = 2000.0, .hi_hz = 1000.0}), "band.hi_hz = 1000 Hz");
  expect_problem(problems_of(frf, {.lo_hz = -5.0}), "band.lo_hz = -5 Hz");
  expect_problem(problems_of(frf, {.hi_hz = std::nan("")}), "band.hi_hz = nan");

  MeasuredFrf bad = frf;
  bad.receptance_m_per_n[7] = cd(std::nan(""), 0.0);
  expect_problem(problems_of(bad, {}), "frf.receptance_m_per_n[7] at 14 Hz: must be finite");
  MeasuredFrf zero = frf;
  for (cd& g : zero.receptance_m_per_n) g = 0.0;
  expect_problem(problems_of(zero, {}), "zero at every point");

  EXPECT_THROW(fitted_frf(fit_modes(frf, Direction::kX), {10.0, 5.0}), InvalidInput);
  EXPECT_THROW(fitted_frf(fit_modes(frf, Direction::kX), {-1.0}), InvalidInput);
}

}  // namespace
}  // namespace cutdyn
