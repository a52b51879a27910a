// Oxley's machining theory with Johnson–Cook flow stress: solutions per second of the nested
// root-finding solver, against the straightforward way — the exhaustive grid search of the
// published implementations (δ 0.005…0.2 by 0.005, C0 1…10 by 0.1, φ 5…45° by 0.1°: for
// each δ and C0 the φ of least |τ_int − k_chip|, for each δ the C0 of least |σ_N − σ'_N|,
// then the δ of least Fc). Case: AISI 1045, 200 m/min, 0.15 mm, 1.6 mm, rake −7°.
#include <cmath>
#include <cstdio>
#include <limits>

#include "bench_support.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/forces/oxley.hpp"

namespace cutdyn {
namespace {

using bench::Result;
using bench::result;
using bench::timed;

constexpr auto kMs = benchmark::kMillisecond;

const OrthogonalCut kCut{200.0 / 60.0, 0.15e-3, 1.6e-3, units::deg_to_rad(-7.0), 20.0};
const WorkMaterial& material() { return *find_material("AISI1045"); }

struct GridAnswer {
  double fc_n = 0.0, phi_rad = 0.0, c0 = 0.0, delta = 0.0;
};

GridAnswer grid_search() {
  GridAnswer best;
  best.fc_n = std::numeric_limits<double>::infinity();
  for (int id = 1; id <= 40; ++id) {
    const double delta = 0.005 * id;
    double best_g = std::numeric_limits<double>::infinity(), phi_at = 0.0, c0_at = 0.0;
    for (int ic = 0; ic <= 90; ++ic) {
      const double c0 = 1.0 + 0.1 * ic;
      double best_f = std::numeric_limits<double>::infinity(), phi_best = 0.0;
      for (int ip = 0; ip <= 400; ++ip) {
        const double phi = units::deg_to_rad(5.0 + 0.1 * ip);
        const OxleyState s = oxley_state(material(), kCut, phi, c0, delta);
        if (!s.admissible) continue;
        const double f = std::abs(s.interface_shear_stress_pa - s.chip_flow_stress_pa);
        if (f < best_f) {
          best_f = f;
          phi_best = phi;
        }
      }
      if (!std::isfinite(best_f)) continue;
      const OxleyState s = oxley_state(material(), kCut, phi_best, c0, delta);
      const double g = std::abs(s.interface_normal_stress_pa - s.normal_stress_b_pa);
      if (g < best_g) {
        best_g = g;
        phi_at = phi_best;
        c0_at = c0;
      }
    }
    if (!std::isfinite(best_g)) continue;
    const OxleyState s = oxley_state(material(), kCut, phi_at, c0_at, delta);
    if (s.cutting_force_n < best.fc_n) best = {s.cutting_force_n, phi_at, c0_at, delta};
  }
  return best;
}

void BM_OxleyNestedSolver(benchmark::State& state) {
  OxleyResult r;
  Result& out = timed(state, "nested", [&] {
    r = oxley_orthogonal(material(), kCut);
    benchmark::DoNotOptimize(r);
  });
  out.figures["fc_n"] = r.state.cutting_force_n;
  out.figures["phi_deg"] = units::rad_to_deg(r.state.phi_rad);
  out.figures["evaluations"] = r.evaluations;
}

void BM_OxleyGridSearch(benchmark::State& state) {
  GridAnswer g;
  Result& out = timed(state, "grid", [&] {
    g = grid_search();
    benchmark::DoNotOptimize(g);
  });
  out.figures["fc_n"] = g.fc_n;
  out.figures["phi_deg"] = units::rad_to_deg(g.phi_rad);
}

BENCHMARK(BM_OxleyNestedSolver)->Unit(kMs)->UseRealTime();
BENCHMARK(BM_OxleyGridSearch)->Unit(kMs)->UseRealTime()->Iterations(2);

void print_summary() {
  std::printf("\n==== cutdyn Oxley + Johnson–Cook: summary (wall clock, one thread) ====\n\n");
  const auto nested = result("nested"), grid = result("grid");
  bench::line("one solution, nested root finding (cutdyn)", nested);
  bench::line("one solution, exhaustive grid (published scripts' way)", grid);
  if (nested) {
    std::printf("  %-58s %10.0f /s\n", "solutions per second (cutdyn)", 1.0 / nested->seconds);
    std::printf("  %-58s %12.0f\n", "state evaluations per solution (cutdyn)",
                nested->figures.at("evaluations"));
  }
  if (grid) std::printf("  %-58s %12d\n", "state evaluations per solution (grid)", 40 * 91 * 402);
  bench::ratio("ratio grid / cutdyn (time)", grid, 1.0, nested, 1.0);
  if (nested && grid) {
    std::printf("  %-58s %8.2f / %.2f N\n", "Fc: cutdyn / grid", nested->figures.at("fc_n"),
                grid->figures.at("fc_n"));
    std::printf("  %-58s %8.3f / %.3f deg\n", "shear angle: cutdyn / grid",
                nested->figures.at("phi_deg"), grid->figures.at("phi_deg"));
  }
  std::printf("\n");
}

}  // namespace
}  // namespace cutdyn

int main(int argc, char** argv) {
  return cutdyn::bench::run_benchmarks(argc, argv, cutdyn::print_summary);
}
