// Turning stability: lobe tracing by the closed form, the reduced full discretization and the
// multi-frequency method, each against the straightforward method measured in the same run
// (the dense textbook full-discretization transition matrix). docs/benchmarks.md.
//
// Every benchmark stores its wall-clock time per iteration and its figures in `g_results`;
// main() prints the Google Benchmark table and then a summary with the ratios.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/stability/full_discretization.hpp"
#include "cutdyn/stability/lobes.hpp"
#include "cutdyn/stability/multi_frequency.hpp"
#include "cutdyn/stability/tlusty.hpp"
#include "cutdyn/stability/turning.hpp"
#include "support/reference_cases.hpp"

namespace cutdyn {
namespace {

using namespace bench;

constexpr double kRpmMin = 500.0;
constexpr double kRpmMax = 5000.0;
constexpr int kSpeeds = 200;
constexpr double kDepthLimit = 0.03;    // m
constexpr int kGridDepths = 100;        // depth rows of the MATLAB-style grid
constexpr int kGridStepsPerDelay = 40;  // the textbook scripts' m
constexpr double kVibrationHz = 20000.0;
constexpr int kHarmonics = 5;

LobesOptions lobe_grid(int threads) {
  LobesOptions o;
  o.rpm_min = kRpmMin;
  o.rpm_max = kRpmMax;
  o.rpm_steps = kSpeeds;
  o.threads = threads;
  return o;
}

LobePoint to_point(double rpm, const TurningBoundary& b) {
  return LobePoint{rpm, b.boundary, b.duty_cycle, b.lobe};
}

LobesReport turning_lobes(const TurningProcess& model, const TurningStabilityOptions& o,
                          int threads) {
  return trace_lobes(
      [&](double rpm) { return to_point(rpm, turning_critical_depth(model, rpm, o)); },
      lobe_grid(threads));
}

// ---- 1. conventional lobes: closed form vs the MATLAB-style grid -----------------------

TurningStabilityOptions closed_form_options() {
  TurningStabilityOptions o;
  o.method = TurningMethod::kClosedForm;
  o.depth_max_m = kDepthLimit;
  return o;
}

// The closed-form critical depth at `rpm` (the averaged one for a vibration-assisted model):
// the reference each method is compared with at its own speeds, since the lobes' refinement
// adds speeds where each method's lobes change and two reports' points differ in number.
double closed_form_depth(const TurningProcess& model, double rpm) {
  return turning_critical_depth(model, rpm, closed_form_options()).boundary.depth_m;
}

// The published scripts' method at one speed: the dense transition matrix with m = 40 steps
// per delay at every depth of a uniform grid; the boundary is the first unstable row.
LobePoint grid_column(const TurningProcess& model, double rpm) {
  const DelayedSystem s = turning_system(model, rpm);
  FdOptions o;
  o.steps_per_period = kGridStepsPerDelay;
  const FdGrid grid = fd_grid(s, o);
  return first_unstable_row(
      rpm, [&](double w) { return fd_spectral_radius(s, grid, w); }, kDepthLimit, kGridDepths);
}

void BM_ClosedFormLobes(benchmark::State& state) {
  const TurningProcess model = testing::table2_conventional();
  const TurningStabilityOptions o = closed_form_options();
  const int threads = threads_arg(state);
  LobesReport report;
  Result& r = timed(state, threads_key("closed_form", state),
                    [&] { report = turning_lobes(model, o, threads); });
  double min_depth = kDepthLimit;
  for (const LobePoint& p : report.points) min_depth = std::min(min_depth, p.boundary.depth_m);
  r.figures["threads"] = threads;
  r.figures["min_depth_mm"] = 1e3 * min_depth;
  state.counters["threads"] = threads;
  state.counters["us_per_speed"] = 1e6 * r.seconds / kSpeeds;
  state.counters["min_depth_mm"] = 1e3 * min_depth;
  state.counters["evals"] = static_cast<double>(report.evaluations);
}

void BM_DenseGridSubset(benchmark::State& state) {
  const TurningProcess model = testing::table2_conventional();
  const std::vector<double> speeds{500.0, 2000.0, 3500.0, 5000.0};
  Result& r = timed(state, "grid_subset", [&] {
    for (double rpm : speeds) benchmark::DoNotOptimize(grid_column(model, rpm));
  });
  const double per_speed = r.seconds / static_cast<double>(speeds.size());
  r.figures["speeds"] = static_cast<double>(speeds.size());
  r.figures["s_per_speed"] = per_speed;
  state.counters["speeds"] = static_cast<double>(speeds.size());
  state.counters["ms_per_speed"] = 1e3 * per_speed;
  state.counters["evals"] = static_cast<double>(speeds.size()) * kGridDepths;
}

void BM_DenseGridFull(benchmark::State& state) {
  const TurningProcess model = testing::table2_conventional();
  const int threads = threads_arg(state);
  LobesReport report;
  Result& r = timed(state, threads_key("grid_full", state), [&] {
    report = trace_lobes([&](double rpm) { return grid_column(model, rpm); }, lobe_grid(threads));
  });
  // Accuracy of the grid's boundary against the exact one (outside the timing): speeds at
  // which it is more than one depth row away from the closed form at the same speed.
  const double row = kDepthLimit / kGridDepths;
  int off = 0;
  double worst = 0.0;
  for (const LobePoint& p : report.points) {
    const double e = std::abs(p.boundary.depth_m - closed_form_depth(model, p.rpm));
    worst = std::max(worst, e);
    if (e > row) ++off;
  }
  const FdOptions fo{.steps_per_period = kGridStepsPerDelay};
  const DelayedSystem s = turning_system(model, kRpmMax);
  const auto dim = static_cast<double>(fd_transition_matrix(s, fd_grid(s, fo), 0.0).rows());
  r.figures["threads"] = threads;
  r.figures["speeds_off"] = off;
  r.figures["points"] = static_cast<double>(report.points.size());
  r.figures["worst_mm"] = 1e3 * worst;
  r.figures["dim"] = dim;
  state.counters["threads"] = threads;
  state.counters["ms_per_speed"] = 1e3 * r.seconds / kSpeeds;
  state.counters["dense_dim"] = dim;
  state.counters["speeds_off_gt_1_row"] = off;
  state.counters["worst_err_mm"] = 1e3 * worst;
}

// ---- 2. vibration-assisted lobes at 20 kHz ---------------------------------------------

void BM_VibrationLobes(benchmark::State& state, TurningMethod method) {
  const TurningProcess model = testing::table2_vibration(kVibrationHz);
  TurningStabilityOptions o;
  o.method = method;
  o.depth_max_m = kDepthLimit;
  o.harmonics = kHarmonics;
  const int threads = threads_arg(state);
  LobesReport report;
  const std::string prefix = method == TurningMethod::kMultiFrequency ? "vib_mf" : "vib_fd";
  Result& r =
      timed(state, threads_key(prefix, state), [&] { report = turning_lobes(model, o, threads); });
  // Deviation from the averaged closed form (Kt -> r·Kt), exact for f >> fn, at each point's
  // own speed.
  double worst = 0.0;
  int found = 0;
  for (const LobePoint& p : report.points) {
    const double a = closed_form_depth(model, p.rpm);
    worst = std::max(worst, std::abs(p.boundary.depth_m - a) / a);
    found += p.boundary.found ? 1 : 0;
  }
  r.figures["threads"] = threads;
  r.figures["worst_vs_averaged"] = worst;
  state.counters["threads"] = threads;
  state.counters["ms_per_speed"] = 1e3 * r.seconds / kSpeeds;
  state.counters["found"] = found;
  state.counters["max_dev_vs_avg_pct"] = 1e2 * worst;
}

// ---- 3. the kinematic duty cycle by the multi-frequency method --------------------------
//
// The `turning-ultrasonic-speed` example: 20 kHz, 20 µm, a 40 mm workpiece (the duty cycle
// from the cutting speed, 0.25 at 200 rpm to 1 at 2000 rpm), 200 speeds 200–2000 rpm, depth
// limit 40 mm, all threads. Against the method before 2026-12-02 at two speeds, one thread: its
// window (the shortest stretch between any two jumps, t = 0 counted as one: 49 harmonics at
// 200 rpm for a contact of a quarter period) and every eigenvalue from the dense solver.
TurningProcess kinematic_example() {
  TurningProcess m = testing::table2_conventional();
  VibrationAssist v;
  v.frequency_hz = kVibrationHz;
  v.amplitude_m = 20e-6;
  v.workpiece_diameter_m = 0.04;
  m.vibration = v;
  return m;
}

// The window the method took before 2026-12-02 (see above), P >= 5.
int harmonics_before(const DelayedSystem& s) {
  if (s.H.constant) return 0;
  const double T = s.H.period_s;
  std::vector<double> b{0.0, T};
  for (const DelayTerm& t : s.delay_terms())
    b.insert(b.end(), t.H.breakpoints_s.begin(), t.H.breakpoints_s.end());
  std::sort(b.begin(), b.end());
  double shortest = 1.0;
  for (std::size_t i = 0; i + 1 < b.size(); ++i)
    if ((b[i + 1] - b[i]) / T > 1e-9) shortest = std::min(shortest, (b[i + 1] - b[i]) / T);
  const double omega = units::kTwoPi / T;
  return std::max(kHarmonics, static_cast<int>(std::ceil(response_band_rad_s(s) / omega) +
                                               std::ceil(1.5 / shortest)));
}

void BM_KinematicLobes(benchmark::State& state) {
  const TurningProcess model = kinematic_example();
  TurningStabilityOptions o;
  o.method = TurningMethod::kMultiFrequency;
  o.depth_max_m = 0.04;
  LobesOptions grid;
  grid.rpm_min = 200.0;
  grid.rpm_max = 2000.0;
  grid.rpm_steps = kSpeeds;
  grid.threads = 0;
  LobesReport report;
  Result& r = timed(state, "kinematic_mf", [&] {
    report = trace_lobes(
        [&](double rpm) { return to_point(rpm, turning_critical_depth(model, rpm, o)); }, grid);
  });
  r.figures["speeds"] = static_cast<double>(report.points.size());
}

void BM_KinematicTwoSpeeds(benchmark::State& state) {
  const bool before = state.range(0) != 0;
  const TurningProcess model = kinematic_example();
  double depth = 0.0;
  Result& r = timed(state, before ? "kinematic_before" : "kinematic_now", [&] {
    for (double rpm : {200.0, 500.0}) {
      const DelayedSystem s = turning_system(model, rpm);
      MultiFrequencyOptions mf;
      mf.depth_max_m = 0.04;
      mf.harmonics = kHarmonics;
      if (before) {
        mf.harmonics = harmonics_before(s);
        mf.exact_harmonics = true;
        mf.dense_eigenvalues = true;
      }
      depth += multi_frequency_critical_depth(s, mf).depth_m;
    }
  });
  r.figures["depth_sum"] = depth / static_cast<double>(state.iterations());
}

// Size of the problem each form solves at one speed.
struct Sizes {
  double dense_dim = 0;    // d + r·L, from the library's own transition matrix
  double reduced_dim = 0;  // 2r × (steps in contact)
  double steps = 0;        // grid steps per vibration period
};

Sizes problem_sizes(const DelayedSystem& s, const FdOptions& o) {
  const FdGrid grid = fd_grid(s, o);
  Sizes z;
  z.steps = grid.steps();
  z.dense_dim = static_cast<double>(fd_transition_matrix(s, grid, 0.0).rows());
  int active = 0;
  for (int j = 0; j < grid.steps(); ++j) {
    const auto k = static_cast<std::size_t>(j);
    if (s.H.mean(grid.nodes_s[k], grid.nodes_s[k + 1]).norm() > 0.0) ++active;
  }
  z.reduced_dim = 2.0 * s.outputs() * active;
  return z;
}

std::string speed_key(const std::string& prefix, const benchmark::State& state) {
  return prefix + "/" + std::to_string(state.range(0));
}

void record_boundary(benchmark::State& state, Result& r, const CriticalDepth& b, const Sizes& z) {
  r.figures["depth_mm"] = 1e3 * b.depth_m;
  r.figures["chatter_hz"] = b.chatter_hz;
  r.figures["evals"] = static_cast<double>(b.evaluations);
  r.figures["dense_dim"] = z.dense_dim;
  r.figures["reduced_dim"] = z.reduced_dim;
  state.counters["depth_mm"] = 1e3 * b.depth_m;
  state.counters["chatter_hz"] = b.chatter_hz;
  state.counters["evals"] = static_cast<double>(b.evaluations);
  state.counters["dense_dim"] = z.dense_dim;
  state.counters["reduced_dim"] = z.reduced_dim;
}

// One speed, reduced full discretization (the default method).
void BM_VibrationReducedAtSpeed(benchmark::State& state) {
  const auto rpm = static_cast<double>(state.range(0));
  const DelayedSystem s = turning_system(testing::table2_vibration(kVibrationHz), rpm);
  const FdOptions o{.depth_max_m = kDepthLimit};
  CriticalDepth b;
  Result& r = timed(state, speed_key("reduced", state), [&] { b = fd_critical_depth(s, o); });
  record_boundary(state, r, b, problem_sizes(s, o));
}

// One speed, the same discretization with the dense transition matrix: coarse scan of the
// spectral radius, then Brent to 1e-6 (fd_critical_depth_dense's defaults, as used by
// TurningMethod::kFullDiscretizationDense).
void BM_VibrationDenseAtSpeed(benchmark::State& state) {
  const auto rpm = static_cast<double>(state.range(0));
  const DelayedSystem s = turning_system(testing::table2_vibration(kVibrationHz), rpm);
  const FdOptions o{.depth_max_m = kDepthLimit};
  CriticalDepth b;
  Result& r = timed(state, speed_key("dense", state), [&] { b = fd_critical_depth_dense(s, o); });
  record_boundary(state, r, b, problem_sizes(s, o));
  state.counters["s_per_eval"] = r.seconds / static_cast<double>(b.evaluations + 1);
}

// ---- 3. one dense spectral radius at a larger size -------------------------------------

// A single evaluation of the dense method's unit of work (build Φ, all its eigenvalues) at
// the reduced method's critical depth; a critical depth needs some 25 of them.
void BM_DenseSpectralRadius(benchmark::State& state) {
  const auto rpm = static_cast<double>(state.range(0));
  const DelayedSystem s = turning_system(testing::table2_vibration(kVibrationHz), rpm);
  const FdOptions o{.depth_max_m = kDepthLimit};
  const FdGrid grid = fd_grid(s, o);
  const double w = fd_critical_depth(s, o).depth_m;
  double rho = 0.0;
  Result& r =
      timed(state, speed_key("dense_rho", state), [&] { rho = fd_spectral_radius(s, grid, w); });
  const Sizes z = problem_sizes(s, o);
  r.figures["dense_dim"] = z.dense_dim;
  r.figures["rho"] = rho;
  state.counters["dense_dim"] = z.dense_dim;
  state.counters["rho_at_reduced_depth"] = rho;
}

// Registration. Real time throughout: the lobe tracers run on OpenMP threads.
constexpr auto kMs = benchmark::kMillisecond;

BENCHMARK(BM_ClosedFormLobes)->ArgName("threads")->Arg(1)->Arg(0)->Unit(kMs)->UseRealTime();
BENCHMARK(BM_DenseGridSubset)->Unit(kMs)->UseRealTime();
BENCHMARK(BM_DenseGridFull)
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(0)
    ->Iterations(1)
    ->Unit(kMs)
    ->UseRealTime();
BENCHMARK(BM_KinematicLobes)->Iterations(1)->Unit(kMs)->UseRealTime();
BENCHMARK(BM_KinematicTwoSpeeds)
    ->ArgName("before")
    ->Arg(0)
    ->Arg(1)
    ->Iterations(1)
    ->Unit(kMs)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_VibrationLobes, reduced_fd, TurningMethod::kFullDiscretization)
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(0)
    ->Unit(kMs)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_VibrationLobes, multi_frequency, TurningMethod::kMultiFrequency)
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(0)
    ->Unit(kMs)
    ->UseRealTime();
BENCHMARK(BM_VibrationReducedAtSpeed)
    ->ArgName("rpm")
    ->Arg(5000)
    ->Arg(2500)
    ->Arg(1650)
    ->Unit(kMs)
    ->UseRealTime();
BENCHMARK(BM_VibrationDenseAtSpeed)
    ->ArgName("rpm")
    ->Arg(5000)
    ->Arg(2500)
    ->Iterations(1)
    ->Unit(kMs)
    ->UseRealTime();
BENCHMARK(BM_DenseSpectralRadius)
    ->ArgName("rpm")
    ->Arg(1650)
    ->Iterations(1)
    ->Unit(kMs)
    ->UseRealTime();

// ---- summary ---------------------------------------------------------------------------

void print_summary() {
  const int n = all_threads();
  std::printf(
      "\n==== cutdyn turning stability: summary (wall clock, this run; %d threads = all) "
      "====\n",
      n);

  std::printf(
      "\n1. Conventional lobes, table 2 (228.8 Hz, 2.26e8 N/m, zeta 0.01, Kt 850 N/mm^2),\n"
      "   %d speeds %.0f-%.0f rpm, depth limit %.0f mm\n",
      kSpeeds, kRpmMin, kRpmMax, 1e3 * kDepthLimit);
  const auto cf1 = result("closed_form/1"), cfn = result("closed_form/all");
  const auto sub = result("grid_subset"), g1 = result("grid_full/1"), gn = result("grid_full/all");
  line("closed form (trace_lobes), 1 thread", cf1);
  line("closed form (trace_lobes), all threads", cfn);
  line("dense FD grid 200 x 100, m = 40, whole grid, 1 thread", g1);
  line("dense FD grid 200 x 100, m = 40, whole grid, all threads", gn);
  if (sub) {
    const double per_speed = sub->figures.at("s_per_speed");
    std::printf("  %-58s %12s\n", "dense FD grid, subset 4 x 100: per speed",
                seconds_text(per_speed).c_str());
    std::printf("  %-58s %12s\n", "  -> 200 speeds extrapolated, 1 thread",
                seconds_text(per_speed * kSpeeds).c_str());
  }
  ratio("ratio grid/closed form, whole grid measured, 1 thread", g1, 1.0, cf1, 1.0);
  ratio("ratio grid/closed form, whole grid measured, all threads", gn, 1.0, cfn, 1.0);
  ratio("ratio grid/closed form, extrapolated from subset, 1 thread", sub,
        static_cast<double>(kSpeeds) / 4.0, cf1, 1.0);
  if (g1) {
    std::printf(
        "  grid: dense matrix %.0f x %.0f; %.0f of %.0f speeds (the grid's and the refinement's) "
        "more than one depth row (%.1f mm) off the closed form, worst %.1f mm\n",
        g1->figures.at("dim"), g1->figures.at("dim"), g1->figures.at("speeds_off"),
        g1->figures.at("points"),
        1e3 * kDepthLimit / kGridDepths, g1->figures.at("worst_mm"));
  }

  std::printf(
      "\n2. Vibration-assisted lobes, f = %.0f kHz, duty cycle %.1f, %d speeds %.0f-%.0f "
      "rpm\n",
      kVibrationHz / 1e3, testing::kTable2DutyCycle, kSpeeds, kRpmMin, kRpmMax);
  const auto fd1 = result("vib_fd/1"), fdn = result("vib_fd/all");
  const auto mf1 = result("vib_mf/1"), mfn = result("vib_mf/all");
  line("reduced FD lobes, 1 thread", fd1);
  line("reduced FD lobes, all threads", fdn);
  line("  per speed, 1 thread", fd1, kSpeeds);
  line("multi-frequency (P = 5) lobes, 1 thread", mf1);
  line("multi-frequency (P = 5) lobes, all threads", mfn);
  line("  per speed, 1 thread", mf1, kSpeeds);
  if (fd1 && mf1) {
    std::printf(
        "  largest deviation from the averaged closed form: reduced FD %.2f %%, "
        "multi-frequency %.2f %%\n",
        1e2 * fd1->figures.at("worst_vs_averaged"), 1e2 * mf1->figures.at("worst_vs_averaged"));
  }
  const auto kin = result("kinematic_mf"), kin_now = result("kinematic_now"),
             kin_before = result("kinematic_before");
  std::printf(
      "\n3. Kinematic duty cycle (20 kHz, 20 um, 40 mm workpiece), multi-frequency, 200-2000 "
      "rpm\n");
  if (kin)
    std::printf("  %-58s %12s  (%.0f speeds)\n", "lobes, 200 speeds + refinement, all threads",
                seconds_text(kin->seconds).c_str(), kin->figures.at("speeds"));
  line("200 and 500 rpm, 1 thread", kin_now);
  line("200 and 500 rpm, the method before 2026-12-02", kin_before);
  if (kin_now && kin_before)
    std::printf(
        "  %-58s %11.1fx  (depths equal to %.1e)\n", "ratio before / now",
        kin_before->seconds / kin_now->seconds,
        std::abs(kin_before->figures.at("depth_sum") / kin_now->figures.at("depth_sum") - 1.0));
  const auto red5 = result("reduced/5000"), den5 = result("dense/5000");
  line("reduced FD, one speed, 5000 rpm", red5);
  line("dense FD (Brent to 1e-6), one speed, 5000 rpm", den5);
  ratio("ratio dense/reduced at 5000 rpm, measured", den5, 1.0, red5, 1.0);
  ratio("ratio dense at 5000 rpm / reduced lobes per speed, 1 thread", den5, 1.0, fd1,
        1.0 / kSpeeds);
  if (den5 && red5) {
    std::printf(
        "  at 5000 rpm: dense matrix %.0f x %.0f (%.0f spectral radii), reduced matrix "
        "%.0f x %.0f (%.0f evaluations);\n  critical depth dense %.6f mm, reduced %.6f mm "
        "(rel. diff %.1e)\n",
        den5->figures.at("dense_dim"), den5->figures.at("dense_dim"), den5->figures.at("evals"),
        red5->figures.at("reduced_dim"), red5->figures.at("reduced_dim"), red5->figures.at("evals"),
        den5->figures.at("depth_mm"), red5->figures.at("depth_mm"),
        std::abs(den5->figures.at("depth_mm") - red5->figures.at("depth_mm")) /
            red5->figures.at("depth_mm"));
  }

  std::printf("\n3. Structured vs dense at the largest size run whole (20 kHz, 2500 rpm)\n");
  const auto red25 = result("reduced/2500"), den25 = result("dense/2500");
  line("reduced FD critical depth, 2500 rpm", red25);
  line("dense FD critical depth (Brent to 1e-6), 2500 rpm", den25);
  ratio("ratio dense/reduced at 2500 rpm, measured", den25, 1.0, red25, 1.0);
  if (den25 && red25) {
    const double dim = den25->figures.at("dense_dim");
    std::printf(
        "  dense matrix %.0f x %.0f, %.0f spectral radii (%s each); critical depth dense "
        "%.6f mm, reduced %.6f mm (rel. diff %.1e);\n  chatter dense %.2f Hz, reduced "
        "%.2f Hz\n",
        dim, dim, den25->figures.at("evals"),
        seconds_text(den25->seconds / (den25->figures.at("evals") + 1)).c_str(),
        den25->figures.at("depth_mm"), red25->figures.at("depth_mm"),
        std::abs(den25->figures.at("depth_mm") - red25->figures.at("depth_mm")) /
            red25->figures.at("depth_mm"),
        den25->figures.at("chatter_hz"), red25->figures.at("chatter_hz"));
  }
  const auto red16 = result("reduced/1650"), rho16 = result("dense_rho/1650");
  line("one dense spectral radius, 1650 rpm", rho16);
  line("reduced FD critical depth, 1650 rpm", red16);
  ratio("ratio (one dense radius)/(whole reduced depth), lower bound", rho16, 1.0, red16, 1.0);
  if (rho16) {
    std::printf("  at 1650 rpm: dense matrix %.0f x %.0f\n", rho16->figures.at("dense_dim"),
                rho16->figures.at("dense_dim"));
  }
  if (den25 && fd1) {
    // Dense lobes over the whole range, estimated: time per spectral radius scaled by D^3
    // from the 2500 rpm case, with its number of spectral radii per speed.
    const double dim = den25->figures.at("dense_dim");
    const double evals = den25->figures.at("evals") + 1;
    const double per_eval = den25->seconds / evals;
    double total = 0.0;
    for (double rpm : lobe_grid(1).speeds_rpm()) {
      const DelayedSystem s = turning_system(testing::table2_vibration(kVibrationHz), rpm);
      const FdGrid grid = fd_grid(s, FdOptions{});
      const double d = 2.0 + s.delay_s / grid.period_s * grid.steps();  // d + r·τ/h
      total += evals * per_eval * std::pow(d / dim, 3.0);
    }
    std::printf(
        "  dense FD lobes, %d speeds, estimated by D^3 scaling (not run): %s; "
        "ratio to reduced lobes (1 thread) ~%.0fx\n",
        kSpeeds, seconds_text(total).c_str(), total / fd1->seconds);
  }
  std::printf("\n");
}

}  // namespace
}  // namespace cutdyn

int main(int argc, char** argv) {
  return cutdyn::bench::run_benchmarks(argc, argv, cutdyn::print_summary);
}
