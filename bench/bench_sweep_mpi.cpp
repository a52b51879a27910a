// `cutdyn sweep` on MPI ranks (docs/scaling.md): 40 variants of the milling default (damping
// of the first mode × teeth × Kt; full discretization, 200 speeds with refinement each), run
// by `mpirun -n 1` and `mpirun -n 2`, each rank on one thread (--threads 1), so that what is
// measured is the sharing between ranks. The requirement: 2 ranks ≥ 1.6× faster than 1 on 2
// cores. Also the files are compared: they must be identical.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "bench_support.hpp"

namespace cutdyn {
namespace {

using namespace bench;

const std::string kVariants =
    " sweep --vary 'modes[0].damping_ratio=0.006:0.002:0.024' --vary tool.teeth=2:1:3"
    " --vary cutting.kt_n_per_mm2=500:200:700 --method full-discretization --threads 1";

std::string out_file(int ranks) {
  return (std::filesystem::temp_directory_path() / ("cutdyn-bench-sweep-" + std::to_string(ranks) +
                                                    ".csv"))
      .string();
}

void BM_SweepRanks(benchmark::State& state) {
  const int ranks = static_cast<int>(state.range(0));
  const std::string command = std::string("OMPI_ALLOW_RUN_AS_ROOT=1 "
                                          "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 ") +
                              CUTDYN_MPIEXEC + " --oversubscribe -n " + std::to_string(ranks) +
                              " " + CUTDYN_BINARY + kVariants + " --out " + out_file(ranks) +
                              " > /dev/null 2>&1";
  Result& r = timed(state, "ranks_" + std::to_string(ranks), [&] {
    if (std::system(command.c_str()) != 0) state.SkipWithError("the sweep failed");
  });
  state.counters["ranks"] = ranks;
  state.counters["variants"] = 40;
  r.figures["ranks"] = ranks;
}
BENCHMARK(BM_SweepRanks)->Arg(1)->Arg(2)->Iterations(3)->Unit(benchmark::kSecond)->UseRealTime();

void print_summary() {
  const auto one = result("ranks_1"), two = result("ranks_2");
  if (!one || !two) return;
  std::ifstream a(out_file(1)), b(out_file(2));
  std::stringstream sa, sb;
  sa << a.rdbuf();
  sb << b.rdbuf();
  std::printf("\n==== cutdyn sweep on MPI ranks: 40 variants, full discretization, 1 thread per rank\n");
  std::printf("  mpirun -n 1: %.2f s\n  mpirun -n 2: %.2f s\n  speed-up 2 ranks / 1 rank: %.2fx "
              "(requirement >= 1.6x: %s)\n  files identical: %s\n",
              one->seconds, two->seconds, one->seconds / two->seconds,
              one->seconds / two->seconds >= 1.6 ? "met" : "NOT met",
              sa.str() == sb.str() && !sa.str().empty() ? "yes" : "NO");
}

}  // namespace
}  // namespace cutdyn

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  cutdyn::print_summary();
  benchmark::Shutdown();
  return 0;
}
