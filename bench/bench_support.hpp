// Shared by the benchmark programs: wall-clock results kept for the summary each program
// prints after the Google Benchmark table, and the summary's formatting.
#pragma once

#include <benchmark/benchmark.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <optional>
#include <string>

#include "cutdyn/stability/lobes.hpp"

namespace cutdyn::bench {

using Clock = std::chrono::steady_clock;

// ---- results shared with the summary ----------------------------------------------------

struct Result {
  double seconds = 0.0;  // wall clock per iteration
  std::map<std::string, double> figures;
};
inline std::map<std::string, Result> g_results;

inline std::optional<Result> result(const std::string& key) {
  const auto it = g_results.find(key);
  if (it == g_results.end()) return std::nullopt;
  return it->second;
}

// Runs `body` once per benchmark iteration and records the mean wall-clock time under `key`.
template <typename Body>
Result& timed(benchmark::State& state, const std::string& key, Body body) {
  const auto start = Clock::now();
  for (auto _ : state) body();
  const double total = std::chrono::duration<double>(Clock::now() - start).count();
  Result& r = g_results[key];
  r.seconds =
      total / static_cast<double>(std::max<benchmark::IterationCount>(1, state.iterations()));
  r.figures.clear();
  return r;
}

inline int all_threads() { return omp_get_max_threads(); }

inline int threads_arg(const benchmark::State& state) {
  const int t = static_cast<int>(state.range(0));
  return t > 0 ? t : all_threads();
}

inline std::string threads_key(const std::string& prefix, const benchmark::State& state) {
  return prefix + (state.range(0) == 1 ? "/1" : "/all");
}

// The published scripts' boundary at one speed: the spectral radius `rho_at(w)` at every
// `stride`-th of `rows` equal depth rows of (0, depth_max] — all of them, as the scripts do —
// and the boundary at the first row with ρ >= 1 (depth_max if none).
template <typename Radius>
LobePoint first_unstable_row(double rpm, Radius rho_at, double depth_max, int rows,
                             int stride = 1) {
  LobePoint p;
  p.rpm = rpm;
  p.boundary.depth_m = depth_max;
  for (int i = 1; i <= rows; i += stride) {
    const double w = depth_max * i / rows;
    const double rho = rho_at(w);
    ++p.boundary.evaluations;
    if (rho >= 1.0 && !p.boundary.found) {
      p.boundary.found = true;
      p.boundary.depth_m = w;
    }
  }
  return p;
}

inline std::string seconds_text(double s) {
  char buf[32];
  if (s >= 3600.0)
    std::snprintf(buf, sizeof buf, "%.1f h", s / 3600.0);
  else if (s >= 1.0)
    std::snprintf(buf, sizeof buf, "%.2f s", s);
  else if (s >= 1e-3)
    std::snprintf(buf, sizeof buf, "%.2f ms", 1e3 * s);
  else
    std::snprintf(buf, sizeof buf, "%.1f us", 1e6 * s);
  return buf;
}

inline void line(const char* what, const std::optional<Result>& r, double divisor = 1.0,
                 const char* unit = "") {
  if (!r) {
    std::printf("  %-58s (not run)\n", what);
    return;
  }
  std::printf("  %-58s %12s%s\n", what, seconds_text(r->seconds / divisor).c_str(), unit);
}

inline void ratio(const char* what, const std::optional<Result>& slow, double slow_scale,
                  const std::optional<Result>& fast, double fast_scale) {
  if (!slow || !fast) {
    std::printf("  %-58s (not run)\n", what);
    return;
  }
  std::printf("  %-58s %11.0fx\n", what, slow->seconds * slow_scale / (fast->seconds * fast_scale));
}

// main() of a benchmark program: the Google Benchmark run, then the program's summary.
template <typename Summary>
int run_benchmarks(int argc, char** argv, Summary print_summary) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  print_summary();
  benchmark::Shutdown();
  return 0;
}

}  // namespace cutdyn::bench
