// Milling time-domain simulation: slice-force evaluations per second per core (the target: tens
// of millions), and
// the ratio against a plain loop over the same slices as textbook codes write it (angle,
// window and trigonometry per slice and step, Euler steps for the structure), measured in
// the same run. docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "bench_support.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/simulate/milling_simulation.hpp"
#include "support/reference_cases.hpp"

namespace cutdyn {
namespace {

using namespace bench;
using units::kPi;
using units::kTwoPi;

constexpr double kRevolutions = 20.0;

// Four teeth, 20 mm, 30° helix, half immersion down-milling, 5 mm deep, on the Insperger–
// Stépán structure at 9000 rpm, regenerative, mechanistic law: 47 slices per tooth.
MillingCut bench_cut() {
  const MillingProcess m = testing::insperger_benchmark(0.5);
  MillingCut c;
  c.process.modal = m.modal;
  for (Mode& mode : c.process.modal.modes) mode.stiffness_n_per_m *= 100.0;  // stable at 5 mm
  c.process.tool.teeth = 4;
  c.process.tool.diameter_m = 0.02;
  c.process.tool.helix_rad = units::deg_to_rad(30.0);
  c.process.engagement.entry_rad = m.engagement.entry_angle();
  c.process.engagement.exit_rad = m.engagement.exit_angle();
  c.spindle_rad_s = units::rpm_to_rad_per_s(9000.0);
  c.feed_per_tooth_m = 0.05e-3;
  c.width_m = 5e-3;
  c.process.cutting = MechanisticForceLaw{6e8, 2e8, 0.0, 0.0};
  return c;
}

MillingSimulationOptions bench_options() {
  MillingSimulationOptions o;
  o.revolutions = kRevolutions;
  o.summary_revolutions = 2.0;
  return o;
}

// The textbook loop over the same slices and steps: per slice and step the angle from the
// time, fmod for the window, sin and cos, the chip from the stored surface, the force; the
// modes by (semi-implicit) Euler steps. Returns the mean |F| of the last two revolutions.
double textbook(const MillingCut& c, int steps_per_rev, int slices, long long* evaluations) {
  const double dt = kTwoPi / (c.spindle_rad_s * steps_per_rev);
  const double lag = c.lag_angle();
  const double b = c.width_m / slices;
  const MechanisticForceLaw& law = c.process.cutting;
  const EngagementWindow window = c.process.engagement.window();
  std::vector<double> surf(static_cast<std::size_t>(slices * steps_per_rev), 0.0);
  std::vector<double> q(c.process.modal.modes.size(), 0.0), v(c.process.modal.modes.size(), 0.0);
  const long long steps = std::llround(kRevolutions * steps_per_rev);
  double x = 0, y = 0, sum = 0;
  long long counted = 0;
  *evaluations = 0;
  for (long long n = 0; n < steps; ++n) {
    const double t = static_cast<double>(n) * dt;
    double fx = 0, fy = 0;
    for (int k = 0; k < c.process.tool.teeth; ++k) {
      for (int j = 0; j < slices; ++j) {
        ++*evaluations;
        const double phi = std::fmod(c.spindle_rad_s * t - kTwoPi * k / c.process.tool.teeth -
                                         (j + 0.5) * lag / slices + 4 * kTwoPi,
                                     kTwoPi);
        if (phi <= window.entry_rad || phi >= window.exit_rad) continue;
        const auto bin = static_cast<std::size_t>(
            j * steps_per_rev +
            static_cast<int>(std::lround(phi / (kTwoPi / steps_per_rev))) % steps_per_rev);
        const double s = std::sin(phi), co = std::cos(phi);
        const double pos =
            (c.feed_per_tooth_m * c.process.tool.teeth * c.spindle_rad_s / kTwoPi * t + x) * s +
            y * co;
        const double h = surf[bin] == 0.0 ? c.feed_per_tooth_m * s : pos - surf[bin];
        if (h <= 0.0) continue;
        surf[bin] = pos;
        const double ft = law.kt_pa * b * h, fr = law.kr_pa * b * h;
        fx += -ft * co - fr * s;
        fy += ft * s - fr * co;
      }
    }
    if (n >= steps - 2 * steps_per_rev) {
      sum += std::hypot(fx, fy);
      ++counted;
    }
    x = y = 0;
    for (std::size_t i = 0; i < q.size(); ++i) {
      const Mode& m = c.process.modal.modes[i];
      const double mass = m.stiffness_n_per_m / (m.natural_rad_s * m.natural_rad_s);
      const double f = m.direction == Direction::kX ? fx : fy;
      const double a =
          (f - 2 * m.damping_ratio * m.natural_rad_s * mass * v[i] - m.stiffness_n_per_m * q[i]) /
          mass;
      v[i] += a * dt;  // velocity first (semi-implicit Euler, as the textbook codes)
      q[i] += v[i] * dt;
      (m.direction == Direction::kX ? x : y) += q[i];
    }
  }
  return sum / static_cast<double>(counted);
}

void BM_MillingSimulation(benchmark::State& state) {
  const MillingCut c = bench_cut();
  const MillingSimulationOptions o = bench_options();
  MillingSimulationResult r;
  Result& res = timed(state, "cutdyn", [&] { r = simulate_milling(c, o); });
  // Counted over the run; the two revolutions before t = 0 that find and follow the periodic
  // forced vibration (the steady start) are extra work, inside the time but not counted.
  const double evaluations = static_cast<double>(r.steps) * c.process.tool.teeth * r.slices;
  res.figures["evaluations"] = evaluations;
  res.figures["per_s"] = evaluations / res.seconds;
  res.figures["slices"] = r.slices;
  res.figures["steps_per_rev"] = r.steps_per_revolution;
  res.figures["mean_force"] = r.mean_force_n;
  state.counters["evals_per_s"] = evaluations / res.seconds;
  state.counters["slices"] = r.slices;
  state.counters["mean_force_n"] = r.mean_force_n;
}

void BM_TextbookLoop(benchmark::State& state) {
  const MillingCut c = bench_cut();
  const MillingSimulationResult ref = simulate_milling(c, bench_options());  // same grid
  long long evaluations = 0;
  double mean = 0.0;
  Result& res = timed(state, "textbook", [&] {
    mean = textbook(c, ref.steps_per_revolution, ref.slices, &evaluations);
  });
  res.figures["per_s"] = static_cast<double>(evaluations) / res.seconds;
  res.figures["mean_force"] = mean;
  state.counters["evals_per_s"] = static_cast<double>(evaluations) / res.seconds;
  state.counters["mean_force_n"] = mean;
}

constexpr auto kMs = benchmark::kMillisecond;
BENCHMARK(BM_MillingSimulation)->Unit(kMs)->UseRealTime();
BENCHMARK(BM_TextbookLoop)->Unit(kMs)->UseRealTime();

void print_summary() {
  std::printf("\n==== cutdyn milling simulation: summary (wall clock, one thread) ====\n\n");
  const auto ours = result("cutdyn"), plain = result("textbook");
  if (ours) {
    std::printf(
        "  4 teeth, 30 deg helix, %.0f slices, %.0f steps per revolution, %.0f revolutions: %.3g "
        "slice evaluations\n",
        ours->figures.at("slices"), ours->figures.at("steps_per_rev"), kRevolutions,
        ours->figures.at("evaluations"));
  }
  line("cutdyn simulate_milling", ours);
  line("textbook loop (trig per slice, Euler steps)", plain);
  if (ours)
    std::printf("  %-58s %10.1f M/s\n", "slice evaluations per second, cutdyn",
                1e-6 * ours->figures.at("per_s"));
  if (plain)
    std::printf("  %-58s %10.1f M/s\n", "slice evaluations per second, textbook",
                1e-6 * plain->figures.at("per_s"));
  ratio("ratio textbook / cutdyn (time)", plain, 1.0, ours, 1.0);
  if (ours && plain)
    std::printf("  mean |F| over the last 2 revolutions: cutdyn %.2f N, textbook %.2f N\n\n",
                ours->figures.at("mean_force"), plain->figures.at("mean_force"));
}

}  // namespace
}  // namespace cutdyn

int main(int argc, char** argv) {
  return cutdyn::bench::run_benchmarks(argc, argv, cutdyn::print_summary);
}
