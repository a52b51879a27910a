// Milling lobes from a measured FRF pair (examples/frf/tool_x.csv and tool_y.csv: 2951 points
// each), 1400 speeds, zero-order, as `cutdyn lobes` computes them for a case with [[frf]]: the
// files read, modes fitted, the tables interpolated at every chatter frequency of the scan.
// Against the straightforward way of the literature [Altintas1995]: sweep the chatter
// frequency over the table's points, one 2×2 eigenvalue problem per point, each giving one
// (speed, depth) point per lobe, and take the lowest lobe at each speed of the grid by
// interpolation. Both are timed in the same run; their depths are compared. docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <limits>
#include <vector>

#include "bench_support.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/io/frf_file.hpp"
#include "cutdyn/modal/frf_fit.hpp"
#include "cutdyn/stability/lobes.hpp"
#include "cutdyn/stability/milling.hpp"
#include "support/textbook_zero_order.hpp"

namespace cutdyn {
namespace {

using namespace bench;

constexpr double kRpmMin = 4000.0, kRpmMax = 20000.0;
constexpr int kSpeeds = 1400;
constexpr double kDepthLimit = 3e-3;

// The process of examples/frf/milling-measured.toml: 4 teeth, slotting, down, Kt 1500 N/mm²,
// Kr 450 N/mm², the FRFs read from the files and fitted.
MillingProcess measured_process() {
  const std::string dir = std::string(CUTDYN_SOURCE_DIR) + "/examples/frf/";
  MillingProcess p;
  p.tool.teeth = 4;
  p.tool.diameter_m = 0.02;
  p.cutting.kt_pa = 1500e6;
  p.cutting.kr_pa = 450e6;
  p.measured.emplace();
  p.measured->xx = read_frf(dir + "tool_x.csv");
  p.measured->yy = read_frf(dir + "tool_y.csv");
  for (Direction d : {Direction::kX, Direction::kY}) {
    const FrfFit fit = fit_modes(*p.measured->direct(d), d);
    p.measured->fitted.modes.insert(p.measured->fitted.modes.end(), fit.model.modes.begin(),
                                    fit.model.modes.end());
  }
  return p;
}

// `speeds` speeds from kRpmMin to kRpmMax by `method`, one thread, no refinement.
LobesReport lobes_by(const MillingProcess& p, MillingMethod method, int speeds) {
  MillingStabilityOptions o;
  o.method = method;
  o.depth_max_m = kDepthLimit;
  LobesOptions grid;
  grid.rpm_min = kRpmMin;
  grid.rpm_max = kRpmMax;
  grid.rpm_steps = speeds;
  grid.refine = false;
  grid.threads = 1;
  return trace_lobes(
      [&](double rpm) {
        const MillingBoundary b = milling_critical_depth(p, rpm, o);
        return LobePoint{rpm, b.boundary, 1.0, b.lobe};
      },
      grid);
}

LobesReport cutdyn_lobes(const MillingProcess& p) {
  return lobes_by(p, MillingMethod::kZeroOrder, kSpeeds);
}

std::vector<double> speeds() {
  std::vector<double> r(kSpeeds);
  for (int i = 0; i < kSpeeds; ++i) r[i] = kRpmMin + (kRpmMax - kRpmMin) * i / (kSpeeds - 1);
  return r;
}

void BM_CutdynFromFiles(benchmark::State& state) {
  timed(state, "files", [] { benchmark::DoNotOptimize(cutdyn_lobes(measured_process())); });
}

void BM_CutdynLobesOnly(benchmark::State& state) {
  const MillingProcess p = measured_process();
  Result& r = timed(state, "lobes", [&] { benchmark::DoNotOptimize(cutdyn_lobes(p)); });
  // Agreement with the textbook sweep where both found a boundary below the limit (the
  // sweep's interpolation across a cusp is the sweep's error, not the scan's).
  const LobesReport ours = cutdyn_lobes(p);
  const std::vector<double> theirs = testing::textbook_zero_order_lobes(p, speeds());
  std::vector<double> diff;
  for (std::size_t n = 0; n < ours.points.size() && n < theirs.size(); ++n) {
    const LobePoint& q = ours.points[n];
    if (q.boundary.found && theirs[n] < kDepthLimit)
      diff.push_back(std::abs(q.boundary.depth_m / theirs[n] - 1.0));
  }
  std::sort(diff.begin(), diff.end());
  r.figures["compared"] = static_cast<double>(diff.size());
  r.figures["median_pct"] = diff.empty() ? 0.0 : 100.0 * diff[diff.size() / 2];
  r.figures["p95_pct"] = diff.empty() ? 0.0 : 100.0 * diff[diff.size() * 95 / 100];
}

void BM_TextbookSweep(benchmark::State& state) {
  const MillingProcess p = measured_process();
  const std::vector<double> rpm = speeds();
  timed(state, "textbook",
        [&] { benchmark::DoNotOptimize(testing::textbook_zero_order_lobes(p, rpm)); });
}

// Full discretization on the modes fitted to the pair: the state space of the modes with their
// complex residues (what every time-domain method uses since 2026-11-28) against the same modes
// as real modes (the phases dropped, what it used before), 100 speeds each.
LobesReport fd_lobes(const MillingProcess& p) {
  return lobes_by(p, MillingMethod::kFullDiscretization, 100);
}

void BM_FullDiscretizationComplexModes(benchmark::State& state) {
  const MillingProcess p = measured_process();
  timed(state, "fd complex", [&] { benchmark::DoNotOptimize(fd_lobes(p)); });
}

void BM_FullDiscretizationRealModes(benchmark::State& state) {
  MillingProcess p = measured_process();
  for (Mode& m : p.measured->fitted.modes) m.residue_phase_rad = 0.0;
  timed(state, "fd real", [&] { benchmark::DoNotOptimize(fd_lobes(p)); });
}

BENCHMARK(BM_CutdynFromFiles)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_FullDiscretizationComplexModes)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_FullDiscretizationRealModes)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_CutdynLobesOnly)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_TextbookSweep)->Unit(benchmark::kMillisecond)->UseRealTime();

void print_summary() {
  std::printf(
      "\n==== cutdyn lobes from a measured FRF pair: summary (wall clock, 1 thread) ====\n\n");
  const auto files = result("files"), lobes = result("lobes"), textbook = result("textbook");
  bench::line("read 2 files + fit modes + zero-order lobes, 1400 speeds", files);
  bench::line("zero-order lobes alone, 1400 speeds", lobes);
  bench::line("textbook chatter-frequency sweep, 1400 speeds", textbook);
  if (lobes && textbook)
    std::printf("  %-58s %11.2fx\n", "ratio cutdyn lobes / textbook sweep (time)",
                lobes->seconds / textbook->seconds);
  const auto fd_complex = result("fd complex"), fd_real = result("fd real");
  bench::line("full discretization, complex-residue modes, 100 speeds", fd_complex);
  bench::line("full discretization, the same as real modes, 100 speeds", fd_real);
  if (fd_complex && fd_real)
    std::printf("  %-58s %11.2fx\n", "ratio complex / real modes (time)",
                fd_complex->seconds / fd_real->seconds);
  if (lobes)
    std::printf("  %-58s %.0f speeds: median %.3f %%, 95th percentile %.2f %%\n",
                "depth difference from the textbook sweep", lobes->figures.at("compared"),
                lobes->figures.at("median_pct"), lobes->figures.at("p95_pct"));
  std::printf("\n");
}

}  // namespace
}  // namespace cutdyn

int main(int argc, char** argv) {
  return cutdyn::bench::run_benchmarks(argc, argv, cutdyn::print_summary);
}
