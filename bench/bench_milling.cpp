// Milling stability: the Insperger–Stépán slotting lobes at full-discretization
// accuracy, as `cutdyn lobes` computes them, against the straightforward method of the
// published MATLAB scripts — a 200 speed × 100 depth grid with the dense transition matrix's
// eigenvalues at every point — measured in the same run. docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "bench_support.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/stability/full_discretization.hpp"
#include "cutdyn/stability/lobes.hpp"
#include "cutdyn/stability/milling.hpp"
#include "support/reference_cases.hpp"

namespace cutdyn {
namespace {

using namespace bench;

constexpr double kRpmMin = 5000.0;
constexpr double kRpmMax = 25000.0;
constexpr int kSpeeds = 200;
constexpr double kDepthLimit = 1e-3;       // m, as the embedded example
constexpr int kGridDepths = 100;           // depth rows of the MATLAB-style grid
constexpr int kScriptStepsPerPeriod = 40;  // m of the published scripts
constexpr int kSampleEvery = 20;           // speeds sampled for the converged dense grid

const MillingProcess& model() {
  static const MillingProcess m = testing::insperger_benchmark(1.0);
  return m;
}

LobesOptions lobe_grid(int threads, bool refine = true) {
  LobesOptions o;
  o.refine = refine;
  o.rpm_min = kRpmMin;
  o.rpm_max = kRpmMax;
  o.rpm_steps = kSpeeds;
  o.threads = threads;
  return o;
}

// What `cutdyn lobes` runs for the embedded milling example.
MillingStabilityOptions cli_options() {
  MillingStabilityOptions o;
  o.method = MillingMethod::kFullDiscretization;
  o.depth_max_m = kDepthLimit;
  o.rel_tol = 1e-3;
  o.coarse_steps = 16;
  return o;
}

// `cutdyn lobes` (trace_milling_lobes): warm = each speed's depth search started from its
// neighbours' depths (the default); !warm = every speed searched on its own (coarse scan of
// 16 depths, then Brent), the way before 2026-11-24, kept callable for this comparison.
LobesReport fd_lobes(const MillingStabilityOptions& o, int threads, bool refine = true,
                     bool warm = true) {
  MillingStabilityOptions with = o;
  with.warm_start = warm;
  return trace_milling_lobes(model(), with, lobe_grid(threads, refine));
}

// The lobes of the last timed run of each variant, for the comparison in the summary.
std::map<std::string, std::vector<LobePoint>>& traced() {
  static std::map<std::string, std::vector<LobePoint>> points;
  return points;
}

// Largest relative difference of the critical depth between two traced lobes over the speeds
// both have (all of them without refinement), and how many speeds that is.
std::pair<double, int> largest_difference(const std::vector<LobePoint>& a,
                                          const std::vector<LobePoint>& b) {
  double worst = 0.0;
  int common = 0;
  std::size_t j = 0;
  for (const LobePoint& p : a) {
    while (j < b.size() && b[j].rpm < p.rpm) ++j;
    if (j == b.size() || b[j].rpm != p.rpm) continue;
    ++common;
    worst = std::max(worst, std::abs(p.boundary.depth_m - b[j].boundary.depth_m) /
                                p.boundary.depth_m);
  }
  return {worst, common};
}

// The straightforward method at one speed: the dense transition matrix on the grid `fd` and
// its eigenvalues at every depth row; the boundary is the first unstable row.
LobePoint grid_column(double rpm, const FdOptions& fd, int rows, int row_stride = 1) {
  const DelayedSystem s = milling_system(model(), rpm);
  const FdGrid grid = fd_grid(s, fd);
  return first_unstable_row(
      rpm, [&](double w) { return fd_spectral_radius(s, grid, w); }, kDepthLimit, rows, row_stride);
}

// ---- 1. the lobes as `cutdyn lobes` computes them --------------------------------------

// The discretization of `cutdyn lobes` until 2026-11-24: linear interpolation (order 1) on
// steps of 1/64 of the structural period, as accurate as today's quadratic one on 1/32 on
// the slotting example (docs/models/milling-stability.md).
MillingStabilityOptions linear_options() {
  MillingStabilityOptions o = cli_options();
  o.fd.order = 1;
  o.fd.max_step_fraction = 1.0 / 64.0;
  return o;
}

// range(0): threads (0 = all); range(1): 1 = with the adaptive refinement; range(2): 1 = warm
// start (today's default), 0 = every speed on its own (the former way); range(3): the
// interpolation order, 2 = today's default, 1 = the linear interpolation on twice the steps;
// range(4): 1 = the flip crossings below each answer (today's default), 0 = without them (as
// until 2026-11-29: an island between two points of the depth grid could be stepped over);
// range(5): 1 = the step from the cut and its convergence check (today's default), 0 = the
// structure's step alone, unchecked (as until 2026-11-29).
void BM_MillingLobes(benchmark::State& state) {
  const int threads = threads_arg(state);
  const bool refine = state.range(1) != 0, warm = state.range(2) != 0;
  const bool linear = state.range(3) == 1, crossings = state.range(4) != 0;
  const bool checked = state.range(5) != 0;
  const std::string key = std::string(refine ? "fd_lobes" : "fd_lobes_uniform") +
                          (warm ? "" : "_old") + (linear ? "_linear" : "") +
                          (crossings ? "" : "_nocross") + (checked ? "" : "_unchecked") +
                          (state.range(0) == 1 ? "/1" : "/all");
  MillingStabilityOptions options = linear ? linear_options() : cli_options();
  options.fd.flip_crossings = crossings;
  if (!checked) {
    options.fd.window_steps = 0;
    options.fd.refinements = 0;
  }
  LobesReport report;
  Result& r = timed(state, key, [&] { report = fd_lobes(options, threads, refine, warm); });
  traced()[key] = report.points;
  r.figures["threads"] = threads;
  r.figures["speeds"] = static_cast<double>(report.points.size());
  r.figures["per_speed_s"] = r.seconds / static_cast<double>(report.points.size());
  r.figures["evals_per_speed"] =
      static_cast<double>(report.evaluations) / static_cast<double>(report.points.size());
  // The finest spacing the adaptive tracing reached (around cusps).
  double finest = kRpmMax - kRpmMin;
  for (std::size_t i = 1; i < report.points.size(); ++i)
    finest = std::min(finest, report.points[i].rpm - report.points[i - 1].rpm);
  r.figures["finest_rpm"] = finest;
  state.counters["speeds"] = r.figures["speeds"];
  state.counters["threads"] = threads;
  state.counters["ms_per_speed"] = 1e3 * r.figures["per_speed_s"];
  state.counters["radii_per_speed"] = r.figures["evals_per_speed"];
}

// Multi-frequency against full discretization on the four-mode case of the tests (modes of
// 480–1500 Hz in x and y, a/D 0.5 down, 2 teeth, depth limit 30 mm), 24 speeds 4000–16 000
// rpm: the cost of the window that covers every mode, and how far the two agree.
void BM_FourModeMethods(benchmark::State& state) {
  const auto method = static_cast<MillingMethod>(state.range(0));
  // Multi-frequency variants: 0 the default, 1 every eigenvalue dense (before 2026-12-02),
  // 2 the frequency samples at the sharpest mode's equal steps (before 2026-12-02 evening).
  const auto variant = state.range(1);
  const MillingProcess m = testing::four_mode_milling(0.5, true);
  MillingStabilityOptions o;
  o.method = method;
  o.depth_max_m = 0.03;
  o.dense_eigenvalues = variant == 1;
  o.uniform_frequency_step = variant == 2;
  LobesOptions grid;
  grid.rpm_min = 4000.0;
  grid.rpm_max = 16000.0;
  grid.rpm_steps = 24;
  grid.refine = false;
  grid.threads = 0;
  LobesReport report;
  const char* const variants[] = {"four_mode_mf", "four_mode_mf_dense", "four_mode_mf_uniform"};
  const std::string key = method == MillingMethod::kMultiFrequency
                              ? variants[std::clamp<std::int64_t>(variant, 0, 2)]
                              : "four_mode_fd";
  Result& r = timed(state, key, [&] {
    report = trace_lobes(
        [&](double rpm) {
          const MillingBoundary b = milling_critical_depth(m, rpm, o);
          return LobePoint{rpm, b.boundary, 1.0, b.lobe};
        },
        grid);
  });
  static std::vector<double> fd_depths;
  if (method == MillingMethod::kFullDiscretization) {
    fd_depths.clear();
    for (const LobePoint& p : report.points) fd_depths.push_back(p.boundary.depth_m);
  } else if (fd_depths.size() == report.points.size()) {
    double worst = 0.0;
    for (std::size_t i = 0; i < fd_depths.size(); ++i)
      worst = std::max(worst,
                       std::abs(report.points[i].boundary.depth_m - fd_depths[i]) / fd_depths[i]);
    r.figures["worst_rel"] = worst;
    state.counters["worst_rel_vs_fd_pct"] = 1e2 * worst;
  }
  state.counters["ms_per_speed"] = 1e3 * r.seconds / grid.rpm_steps;
}

// The `milling-variable-pitch` example (4 teeth 70/110/70/110°, 30° helix, a/D 0.5 down, the
// Insperger–Stépán structure, depth limit 1 mm) by the multi-frequency method: 49 speeds
// 4000–12 000 rpm with the refinement (as `cutdyn lobes` runs it), all threads; and the cost
// per speed with the eigenvalues from Arnoldi's method (default) and from the dense solver (as
// before 2026-12-02) at three speeds, one thread, same run.
MillingProcess variable_pitch_example() {
  MillingProcess m = testing::insperger_benchmark(0.5, true, true);
  m.tool.teeth = 4;
  m.tool.diameter_m = 0.02;
  m.tool.helix_rad = units::deg_to_rad(30.0);
  for (double d : {70.0, 110.0, 70.0, 110.0}) m.tool.pitch_rad.push_back(units::deg_to_rad(d));
  return m;
}

void BM_VariablePitchMultiFrequency(benchmark::State& state) {
  const MillingProcess m = variable_pitch_example();
  MillingStabilityOptions o;
  o.method = MillingMethod::kMultiFrequency;
  o.depth_max_m = 1e-3;
  LobesOptions grid;
  grid.rpm_min = 4000.0;
  grid.rpm_max = 12000.0;
  grid.rpm_steps = 49;
  grid.threads = 0;
  LobesReport report;
  Result& r = timed(state, "pitch_mf_lobes", [&] { report = trace_milling_lobes(m, o, grid); });
  r.figures["speeds"] = static_cast<double>(report.points.size());
  state.counters["speeds"] = static_cast<double>(report.points.size());
}

void BM_VariablePitchPerSpeed(benchmark::State& state) {
  const bool dense = state.range(0) != 0;
  const MillingProcess m = variable_pitch_example();
  MillingStabilityOptions o;
  o.method = MillingMethod::kMultiFrequency;
  o.depth_max_m = 1e-3;
  o.dense_eigenvalues = dense;
  double depth = 0.0;
  Result& r = timed(state, dense ? "pitch_mf_dense" : "pitch_mf_arnoldi", [&] {
    for (double rpm : {5000.0, 8000.0, 11000.0})
      depth += milling_critical_depth(m, rpm, o).boundary.depth_m;
  });
  r.figures["depth_sum"] = depth / static_cast<double>(state.iterations());
  state.counters["ms_per_speed"] = 1e3 * r.seconds / 3.0;
}

// Accuracy of those lobes (not timed for the ratio): against the full discretization with
// half the step and the depth to 1e-6, at every 10th speed.
void BM_MillingLobesAccuracy(benchmark::State& state) {
  MillingStabilityOptions fine = cli_options();
  fine.fd.max_step_fraction *= 0.5;
  fine.rel_tol = 1e-6;
  LobesReport report, reference;
  LobesOptions every10 = lobe_grid(0, false);
  Result& r = timed(state, "accuracy", [&] {
    report = fd_lobes(cli_options(), 0, false);  // the same 200 speeds, without refinement
    reference = trace_lobes(
        [&](double rpm) {
          return LobePoint{rpm, milling_critical_depth(model(), rpm, fine).boundary, 1.0, 0};
        },
        every10);
  });
  double worst = 0.0, worst_rpm = 0.0;
  for (std::size_t i = 0; i < report.points.size(); i += 10) {
    const double ref = reference.points[i].boundary.depth_m;
    const double e = std::abs(report.points[i].boundary.depth_m - ref) / ref;
    if (e > worst) {
      worst = e;
      worst_rpm = report.points[i].rpm;
    }
  }
  r.figures["worst_rel"] = worst;
  r.figures["worst_rpm"] = worst_rpm;
  state.counters["worst_rel_err_pct"] = 1e2 * worst;
}

// ---- 2. the straightforward method ----------------------------------------------------

// At the same discretization as the lobes (quadratic, 1/32 of the structural period): every 20th
// speed, every 25th depth row — the cost of a point is that of one dense eigenvalue problem,
// which depends on the speed (matrix size) but not on the depth. The whole 200 × 100 grid
// would take hours: it is extrapolated from the sample.
void BM_DenseGridConvergedSample(benchmark::State& state) {
  const std::vector<double> speeds = lobe_grid(1).speeds_rpm();
  double points = 0.0, sampled_speeds = 0.0;
  Result& r = timed(state, "grid_converged_sample", [&] {
    points = sampled_speeds = 0.0;
    for (std::size_t i = 0; i < speeds.size(); i += kSampleEvery) {
      const LobePoint p = grid_column(speeds[i], cli_options().fd, kGridDepths, 25);
      points += static_cast<double>(p.boundary.evaluations);
      sampled_speeds += 1.0;
    }
  });
  // Per point, averaged over the sampled speeds (the grid's speeds are uniform, so the
  // sample's mean stands for the whole range).
  const double per_point = r.seconds / points;
  r.figures["per_point_s"] = per_point;
  r.figures["points"] = points;
  r.figures["grid_estimate_s"] = per_point * kSpeeds * kGridDepths;
  const DelayedSystem s5 = milling_system(model(), kRpmMin), s25 = milling_system(model(), kRpmMax);
  r.figures["dim_low"] =
      static_cast<double>(fd_transition_matrix(s5, fd_grid(s5, cli_options().fd), 0.0).rows());
  r.figures["dim_high"] =
      static_cast<double>(fd_transition_matrix(s25, fd_grid(s25, cli_options().fd), 0.0).rows());
  state.counters["ms_per_point"] = 1e3 * per_point;
  state.counters["points"] = points;
  state.counters["grid_estimate_s"] = r.figures["grid_estimate_s"];
}

// As the published scripts run it: m = 40 steps per tooth period, the whole grid, measured.
void BM_DenseGridScripts(benchmark::State& state) {
  const int threads = threads_arg(state);
  FdOptions fd;
  fd.steps_per_period = kScriptStepsPerPeriod;
  LobesReport report;
  Result& r = timed(state, threads_key("grid_scripts", state), [&] {
    report = trace_lobes([&](double rpm) { return grid_column(rpm, fd, kGridDepths); },
                         lobe_grid(threads, false));  // the scripts' uniform grid
  });
  // Its accuracy against the converged lobes (outside the timing).
  MillingStabilityOptions ref = cli_options();
  ref.rel_tol = 1e-5;
  const LobesReport exact = fd_lobes(ref, threads, false, false);
  double worst = 0.0;
  for (std::size_t i = 0; i < report.points.size(); ++i) {
    const double e = std::abs(report.points[i].boundary.depth_m - exact.points[i].boundary.depth_m);
    worst = std::max(worst, e / exact.points[i].boundary.depth_m);
  }
  const DelayedSystem s = milling_system(model(), kRpmMin);
  r.figures["threads"] = threads;
  r.figures["worst_rel"] = worst;
  r.figures["dim"] = static_cast<double>(fd_transition_matrix(s, fd_grid(s, fd), 0.0).rows());
  state.counters["threads"] = threads;
  state.counters["worst_rel_err_pct"] = 1e2 * worst;
  state.counters["dense_dim"] = r.figures["dim"];
}

constexpr auto kMs = benchmark::kMillisecond;

// Old and new alternate, so that a change of load on a shared machine touches both alike.
BENCHMARK(BM_MillingLobes)
    ->ArgNames({"threads", "refine", "warm", "order", "crossings", "checked"})
    ->Args({1, 0, 1, 1, 1, 1})
    ->Args({1, 0, 1, 2, 1, 1})
    ->Args({0, 0, 1, 1, 1, 1})
    ->Args({0, 0, 1, 2, 1, 1})
    ->Args({1, 0, 0, 2, 1, 1})
    ->Args({0, 0, 0, 2, 1, 1})
    ->Args({1, 0, 1, 2, 0, 1})
    ->Args({0, 0, 1, 2, 0, 1})
    ->Args({1, 0, 1, 2, 1, 0})
    ->Args({0, 0, 1, 2, 1, 0})
    ->Args({1, 1, 0, 2, 1, 1})
    ->Args({1, 1, 1, 2, 1, 1})
    ->Args({0, 1, 0, 2, 1, 1})
    ->Args({0, 1, 1, 2, 1, 1})
    ->Unit(kMs)
    ->UseRealTime();
BENCHMARK(BM_FourModeMethods)
    ->ArgNames({"method", "variant"})
    ->Args({static_cast<int>(MillingMethod::kFullDiscretization), 0})
    ->Args({static_cast<int>(MillingMethod::kMultiFrequency), 0})
    ->Args({static_cast<int>(MillingMethod::kMultiFrequency), 2})
    ->Args({static_cast<int>(MillingMethod::kMultiFrequency), 1})
    ->Iterations(1)
    ->Unit(kMs)
    ->UseRealTime();
BENCHMARK(BM_VariablePitchMultiFrequency)->Iterations(1)->Unit(kMs)->UseRealTime();
BENCHMARK(BM_VariablePitchPerSpeed)
    ->ArgName("dense")
    ->Arg(0)
    ->Arg(1)
    ->Iterations(1)
    ->Unit(kMs)
    ->UseRealTime();
BENCHMARK(BM_MillingLobesAccuracy)->Iterations(1)->Unit(kMs)->UseRealTime();
BENCHMARK(BM_DenseGridConvergedSample)->Iterations(1)->Unit(kMs)->UseRealTime();
BENCHMARK(BM_DenseGridScripts)->ArgName("threads")->Arg(0)->Iterations(1)->Unit(kMs)->UseRealTime();

// ---- summary ---------------------------------------------------------------------------

void print_summary() {
  std::printf(
      "\n==== cutdyn milling stability: summary (wall clock, this run; %d threads = all) ====\n",
      all_threads());
  std::printf(
      "\nInsperger-Stepan slotting benchmark (2 teeth, 922 Hz x and y, zeta 0.011, Kt 600, Kr 200 "
      "N/mm^2),\n%d speeds %.0f-%.0f rpm, depth limit %.0f mm\n",
      kSpeeds, kRpmMin, kRpmMax, 1e3 * kDepthLimit);
  const auto l1 = result("fd_lobes/1"), ln = result("fd_lobes/all"), acc = result("accuracy");
  const auto sample = result("grid_converged_sample"), scripts = result("grid_scripts/all");
  line("full-discretization lobes (cutdyn lobes), 1 thread", l1);
  line("full-discretization lobes (cutdyn lobes), all threads", ln);
  if (l1)
    std::printf("  %-58s %12.1f\n", "  spectral radii per speed",
                l1->figures.at("evals_per_speed"));
  if (acc)
    std::printf("  %-58s %11.3f %%  (at %.0f rpm)\n",
                "  largest error vs half step, depth to 1e-6 (every 10th)",
                1e2 * acc->figures.at("worst_rel"), acc->figures.at("worst_rpm"));
  if (sample) {
    std::printf("  %-58s %12s  (%.0f points, matrices %.0f-%.0f rows)\n",
                "dense grid, same steps: per point (sampled)",
                seconds_text(sample->figures.at("per_point_s")).c_str(),
                sample->figures.at("points"), sample->figures.at("dim_high"),
                sample->figures.at("dim_low"));
    std::printf("  %-58s %12s\n", "  -> 200 x 100 grid, extrapolated, 1 thread",
                seconds_text(sample->figures.at("grid_estimate_s")).c_str());
  }
  line("dense grid as the scripts run it (m = 40), measured, all threads", scripts);
  if (scripts)
    std::printf("  %-58s %11.1f %%  (matrix %.0f rows)\n", "  its largest error vs converged lobes",
                1e2 * scripts->figures.at("worst_rel"), scripts->figures.at("dim"));
  if (sample && l1)
    std::printf("  %-58s %11.0fx\n", "ratio grid (same steps, extrapolated) / lobes, 1 thread",
                sample->figures.at("grid_estimate_s") / l1->seconds);
  if (sample && ln)
    std::printf("  %-58s %11.0fx\n",
                "ratio grid (same steps, extrap., / threads) / lobes, all thr.",
                sample->figures.at("grid_estimate_s") / all_threads() / ln->seconds);
  ratio("ratio grid (m = 40, measured) / lobes, all threads", scripts, 1.0, ln, 1.0);
  const auto uniform = result("fd_lobes_uniform/all");
  std::printf("\nAdaptive tracing (cusps and pockets) against a uniform grid as fine:\n");
  line("uniform grid, 200 speeds, all threads", uniform);
  if (ln && uniform) {
    const double finest = ln->figures.at("finest_rpm");
    const double speeds = (kRpmMax - kRpmMin) / finest + 1.0;
    const double uniform_s = uniform->figures.at("per_speed_s") * speeds;
    std::printf("  %-58s %12.0f  (finest spacing %.2f rpm)\n", "adaptive lobes: speeds evaluated",
                ln->figures.at("speeds"), finest);
    std::printf("  %-58s %12s  (%.0f speeds)\n", "uniform grid as fine, extrapolated, all thr.",
                seconds_text(uniform_s).c_str(), speeds);
    std::printf("  %-58s %11.0fx\n", "ratio uniform (as fine, extrap.) / adaptive, all thr.",
                uniform_s / ln->seconds);
  }
  std::printf(
      "\nWarm-started depth search (default) against every speed searched on its own (former "
      "way),\nsame run; depth difference over the speeds both have:\n");
  for (const char* grid : {"fd_lobes_uniform", "fd_lobes"}) {
    for (const char* threads : {"/1", "/all"}) {
      const std::string fresh = std::string(grid) + threads;
      const std::string old = std::string(grid) + "_old" + threads;
      const auto a = result(old), b = result(fresh);
      if (!a || !b) continue;
      const auto [worst, common] = largest_difference(traced()[old], traced()[fresh]);
      std::printf("  %s, %s:\n", grid[8] == '_' ? "200 speeds, no refinement" : "with refinement",
                  threads[1] == '1' ? "1 thread" : "all threads");
      std::printf("    %-56s %9.2f ms  (%.0f speeds, %.2f radii per speed)\n", "former way",
                  1e3 * a->seconds, a->figures.at("speeds"), a->figures.at("evals_per_speed"));
      std::printf("    %-56s %9.2f ms  (%.0f speeds, %.2f radii per speed)\n", "warm start",
                  1e3 * b->seconds, b->figures.at("speeds"), b->figures.at("evals_per_speed"));
      std::printf("    %-56s %11.2fx\n", "ratio former / warm", a->seconds / b->seconds);
      std::printf("    %-56s %11.4f %%  (%d speeds compared)\n",
                  "largest relative depth difference", 1e2 * worst, common);
    }
  }
  // The default 200-speed lobes against a variant (key suffix) run alternately with them.
  const auto against_default = [&](const char* title, const char* suffix, const char* before,
                                   const char* now) {
    std::printf("%s", title);
    for (const char* threads : {"/1", "/all"}) {
      const std::string fresh = std::string("fd_lobes_uniform") + threads;
      const std::string other = std::string("fd_lobes_uniform") + suffix + threads;
      const auto a = result(other), b = result(fresh);
      if (!a || !b) continue;
      const auto [worst, common] = largest_difference(traced()[other], traced()[fresh]);
      std::printf("  %s:\n", threads[1] == '1' ? "1 thread" : "all threads");
      std::printf("    %-56s %9.2f ms  (%.2f radii per speed)\n", before, 1e3 * a->seconds,
                  a->figures.at("evals_per_speed"));
      std::printf("    %-56s %9.2f ms  (%.2f radii per speed)\n", now, 1e3 * b->seconds,
                  b->figures.at("evals_per_speed"));
      std::printf("    %-56s %11.2fx\n", "ratio default / other", b->seconds / a->seconds);
      std::printf("    %-56s %11.4f %%  (%d speeds compared)\n",
                  "largest relative depth difference", 1e2 * worst, common);
    }
  };
  against_default(
      "\nQuadratic interpolation on 1/32 of the structural period (default) against the linear "
      "one on 1/64\n(the default until 2026-11-24), warm start, 200 speeds, same run:\n",
      "_linear", "linear, 1/64", "quadratic, 1/32 (default)");
  against_default(
      "\nFlip crossings below each answer (default, unstable islands) against none (until "
      "2026-11-29),\nwarm start, 200 speeds, same run:\n",
      "_nocross", "without", "with (default)");
  against_default(
      "\nThe step from the cut and its convergence check on half the step (default) against the "
      "structure's\nstep alone, unchecked (until 2026-11-29), warm start, 200 speeds, same run:\n",
      "_unchecked", "structure's step, unchecked", "from the cut, checked (default)");
  const auto fd4 = result("four_mode_fd"), mf4 = result("four_mode_mf");
  std::printf(
      "\nFour-mode case (480-1500 Hz), a/D 0.5 down, 24 speeds 4000-16000 rpm, all threads:\n");
  const auto mf4_dense = result("four_mode_mf_dense");
  const auto mf4_uniform = result("four_mode_mf_uniform");
  line("full discretization", fd4);
  line("multi-frequency (window covering every mode)", mf4);
  line("multi-frequency, equal frequency steps (before 2026-12-02 evening)", mf4_uniform);
  line("multi-frequency, every eigenvalue dense (before 2026-12-02)", mf4_dense);
  if (mf4 && fd4)
    std::printf("  %-58s %11.2fx\n", "ratio multi-frequency / full discretization",
                mf4->seconds / fd4->seconds);
  if (mf4_uniform && fd4)
    std::printf("  %-58s %11.2fx\n", "ratio equal steps / full discretization",
                mf4_uniform->seconds / fd4->seconds);
  if (mf4 && mf4_uniform)
    std::printf("  %-58s %11.2fx\n", "ratio equal / widening frequency steps",
                mf4_uniform->seconds / mf4->seconds);
  if (mf4 && mf4_dense)
    std::printf("  %-58s %11.2fx\n", "ratio dense / Arnoldi eigenvalues",
                mf4_dense->seconds / mf4->seconds);
  if (mf4 && mf4->figures.count("worst_rel"))
    std::printf("  %-58s %11.3f %%\n", "  largest difference multi-frequency vs full discr.",
                1e2 * mf4->figures.at("worst_rel"));
  const auto pitch = result("pitch_mf_lobes"), arnoldi = result("pitch_mf_arnoldi"),
             dense = result("pitch_mf_dense");
  std::printf(
      "\nVariable-pitch example (70/110 deg, 30 deg helix, a/D 0.5), multi-frequency method:\n");
  if (pitch)
    std::printf("  %-58s %12s  (%.0f speeds)\n", "49 speeds + refinement, all threads",
                seconds_text(pitch->seconds).c_str(), pitch->figures.at("speeds"));
  line("per speed (5000, 8000, 11000 rpm), Arnoldi, 1 thread", arnoldi, 3.0);
  line("per speed, every eigenvalue dense (before 2026-12-02)", dense, 3.0);
  if (arnoldi && dense)
    std::printf("  %-58s %11.2fx  (depths equal to %.1e)\n", "ratio dense / Arnoldi",
                dense->seconds / arnoldi->seconds,
                std::abs(dense->figures.at("depth_sum") / arnoldi->figures.at("depth_sum") - 1.0));
  std::printf("\n");
}

}  // namespace
}  // namespace cutdyn

int main(int argc, char** argv) {
  return cutdyn::bench::run_benchmarks(argc, argv, cutdyn::print_summary);
}
