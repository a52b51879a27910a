// Modal fitting of a measured receptance: time and accuracy of fit_modes (LSCF diagram,
// automatic number of modes, Levenberg–Marquardt refinement) against the straightforward way
// — peak picking with the half-power bandwidth, a mode per local maximum of |G|:
// fn at the maximum, ζ = (f2 − f1)/(2·fn) between the points where |G| falls to max/√2,
// k = 1/(2·ζ·|G|max) [Ewins2000, ch. 4]. Case: four modes 300, 800, 880, 2000 Hz (ζ 0.03,
// 0.01, 0.04, 0.08), 0…3000 Hz by 2 Hz, 1 % complex Gaussian noise (seed 1), as in
// tests/modal/frf_fit_test.cpp.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "bench_support.hpp"
#include "cutdyn/modal/frf_fit.hpp"

namespace cutdyn {
namespace {

using bench::Result;
using bench::result;
using bench::timed;

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr auto kMs = benchmark::kMillisecond;

const ModalModel& truth() {
  static const ModalModel m{{Mode{Direction::kX, kTwoPi * 300, 0.03, 3e7},
                             Mode{Direction::kX, kTwoPi * 800, 0.01, 4e7},
                             Mode{Direction::kX, kTwoPi * 880, 0.04, 5e7},
                             Mode{Direction::kX, kTwoPi * 2000, 0.08, 2e7}}};
  return m;
}

const MeasuredFrf& data() {
  static const MeasuredFrf frf = [] {
    MeasuredFrf f = sample_frf(truth(), Direction::kX, linear_frequencies(0, 3000, 1501));
    std::mt19937_64 rng(1);
    std::normal_distribution<double> n(0.0, 0.01);
    for (auto& g : f.receptance_m_per_n) g *= 1.0 + std::complex<double>(n(rng), n(rng));
    return f;
  }();
  return frf;
}

// Peak picking: a mode at each point whose |G| is the largest within ±25 points (±50 Hz).
std::vector<Mode> peak_picking(const MeasuredFrf& frf) {
  const auto& g = frf.receptance_m_per_n;
  const auto& f = frf.frequency_hz;
  const int n = static_cast<int>(g.size()), half = 25;
  std::vector<Mode> modes;
  for (int i = 1; i + 1 < n; ++i) {
    const double peak = std::abs(g[i]);
    bool top = true;
    for (int j = std::max(0, i - half); j <= std::min(n - 1, i + half) && top; ++j)
      top = j == i || std::abs(g[j]) < peak;
    if (!top) continue;
    int lo = i, hi = i;
    while (lo > 0 && std::abs(g[lo]) > peak / std::sqrt(2.0)) --lo;
    while (hi + 1 < n && std::abs(g[hi]) > peak / std::sqrt(2.0)) ++hi;
    const double zeta = (f[hi] - f[lo]) / (2.0 * f[i]);
    modes.push_back(Mode{Direction::kX, kTwoPi * f[i], zeta, 1.0 / (2.0 * zeta * peak)});
  }
  return modes;
}

// Largest relative errors of ωn, ζ and k, each true mode against the nearest one found.
void record_errors(Result& out, const std::vector<Mode>& found) {
  double ef = 0.0, ez = 0.0, ek = 0.0;
  for (const Mode& t : truth().modes) {
    const auto it = std::min_element(found.begin(), found.end(), [&](const Mode& a, const Mode& b) {
      return std::abs(a.natural_rad_s - t.natural_rad_s) <
             std::abs(b.natural_rad_s - t.natural_rad_s);
    });
    if (it == found.end()) continue;
    ef = std::max(ef, std::abs(it->natural_rad_s / t.natural_rad_s - 1.0));
    ez = std::max(ez, std::abs(it->damping_ratio / t.damping_ratio - 1.0));
    ek = std::max(ek, std::abs(it->stiffness_n_per_m / t.stiffness_n_per_m - 1.0));
  }
  out.figures["modes"] = static_cast<double>(found.size());
  out.figures["err_f_pct"] = 100.0 * ef;
  out.figures["err_zeta_pct"] = 100.0 * ez;
  out.figures["err_k_pct"] = 100.0 * ek;
}

void BM_FitModesAutomatic(benchmark::State& state) {
  FrfFit fit;
  Result& out = timed(state, "fit", [&] {
    fit = fit_modes(data(), Direction::kX);
    benchmark::DoNotOptimize(fit);
  });
  record_errors(out, fit.model.modes);
  for (const auto& [name, value] : out.figures) state.counters[name] = value;
}

void BM_PeakPicking(benchmark::State& state) {
  std::vector<Mode> modes;
  Result& out = timed(state, "peaks", [&] {
    modes = peak_picking(data());
    benchmark::DoNotOptimize(modes);
  });
  record_errors(out, modes);
  for (const auto& [name, value] : out.figures) state.counters[name] = value;
}

BENCHMARK(BM_FitModesAutomatic)->Unit(kMs)->UseRealTime();
BENCHMARK(BM_PeakPicking)->Unit(kMs)->UseRealTime();

void errors_line(const char* what, const std::optional<Result>& r) {
  if (!r) {
    std::printf("  %-58s (not run)\n", what);
    return;
  }
  std::printf("  %-58s %2.0f modes, f %.3f %%, zeta %.1f %%, k %.1f %%\n", what,
              r->figures.at("modes"), r->figures.at("err_f_pct"), r->figures.at("err_zeta_pct"),
              r->figures.at("err_k_pct"));
}

void print_summary() {
  std::printf("\n==== cutdyn modal fit: summary (wall clock, one thread) ====\n\n");
  const auto fit = result("fit"), peaks = result("peaks");
  bench::line("fit_modes, automatic (LSCF diagram + refinement)", fit);
  bench::line("peak picking, half-power bandwidth", peaks);
  bench::ratio("ratio fit / peak picking (time)", fit, 1.0, peaks, 1.0);
  errors_line("largest errors, fit_modes", fit);
  errors_line("largest errors, peak picking", peaks);
  if (fit && peaks)
    std::printf("  %-58s %11.0fx\n", "ratio peak picking / fit (largest k error)",
                peaks->figures.at("err_k_pct") / fit->figures.at("err_k_pct"));
  std::printf("\n");
}

}  // namespace
}  // namespace cutdyn

int main(int argc, char** argv) {
  return cutdyn::bench::run_benchmarks(argc, argv, cutdyn::print_summary);
}
