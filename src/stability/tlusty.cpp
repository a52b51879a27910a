#include "cutdyn/stability/tlusty.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cutdyn/core/detail/roots.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn {
namespace {

using units::kPi;
using units::kTwoPi;

// Highest chatter frequency that can matter: above every mode, |G| <= Σ (|b0| + |b1|·ω)/(ω² −
// ωn²) (modal_model.hpp; 1/(k_i (r_i² − 1)) for real modes), and w_lim >= 1/(2K|G|) exceeds
// depth_max once that bound drops below 1/(2K·depth_max).
double omega_upper_bound(const ModalModel& model, Direction direction, double coefficient,
                         double depth_max) {
  double w_top = 0.0;
  for (const Mode& m : model.modes)
    if (m.direction == direction) w_top = std::max(w_top, m.natural_rad_s);
  const double need = 1.0 / (2.0 * coefficient * depth_max);
  const auto bound = [&](double w) {
    double s = 0.0;
    for (const Mode& m : model.modes) {
      if (m.direction != direction) continue;
      const auto [b0, b1] = receptance_numerator(m);
      s += (std::abs(b0) + std::abs(b1) * w) / ((w - m.natural_rad_s) * (w + m.natural_rad_s));
    }
    return s - need;
  };
  double hi = 1.01 * w_top;
  while (bound(hi) > 0.0) hi *= 2.0;
  const auto root = brent_root(bound, 1.01 * w_top, hi, 1e-9 * hi);
  return root ? root->x : hi;
}

// ε(ω)/(2π) − ωτ/(2π) is the phase mismatch; lobes are where ωτ − ε(ω) = 2πj. `arg` is arg G
// taken continuously in ω (unwrapped). Tlusty's closed form of docs/models/turning.md §3a.
double epsilon(double arg) { return 3.0 * kPi + 2.0 * arg; }

// arg g on the branch nearest `reference` (the argument at a nearby frequency).
double arg_near(std::complex<double> g, double reference) {
  return reference + std::remainder(std::arg(g) - reference, kTwoPi);
}

}  // namespace

TlustyLobePoint tlusty_lobe_point(const ModalModel& model, Direction direction,
                                  double coefficient_pa, double omega_rad_s, int lobe) {
  const auto g = frf(model, direction, omega_rad_s);
  if (!(g.real() < 0.0)) return {std::numeric_limits<double>::infinity(), 0.0};
  return {-1.0 / (2.0 * coefficient_pa * g.real()),
          (kTwoPi * lobe + epsilon(std::arg(g))) / omega_rad_s};
}

TlustyResult tlusty_critical_depth(const ModalModel& model, Direction direction,
                                   double coefficient_pa, double delay_s, double depth_max_m) {
  TlustyResult result;
  result.boundary.depth_m = depth_max_m;
  double half_bandwidth = std::numeric_limits<double>::infinity();
  for (const Mode& m : model.modes)
    if (m.direction == direction)
      half_bandwidth = std::min(half_bandwidth, std::max(m.damping_ratio, 1e-4) * m.natural_rad_s);
  if (!std::isfinite(half_bandwidth)) return result;  // no modes: never unstable

  const double w_hi = omega_upper_bound(model, direction, coefficient_pa, depth_max_m);
  // Grid: 16 points per 2π of delay phase and 4 per resonance half-bandwidth — the equal steps
  // of eq. MF-2 (docs/models/milling-stability.md) with d(ω) at its least, the sharpest mode's
  // half-bandwidth ζ·ωn (ζ taken as at least 1e-4).
  const double step = std::min(kTwoPi / (16.0 * delay_s), 0.25 * half_bandwidth);
  const auto n = static_cast<long long>(std::ceil(w_hi / step));
  // (ωτ − ε)/2π, with arg G unwrapped from `reference` (the argument at a point of the grid
  // less than a step away). For real modes Im G < 0 at every ω > 0, and arg G is continuous as
  // it is; a complex residue (modal_model.hpp) can take Im G through 0, where the principal
  // argument jumps by 2π. A root is a boundary only where Re G < 0.
  const auto phase = [&](double w, double reference) {
    return (w * delay_s - epsilon(arg_near(frf(model, direction, w), reference))) / kTwoPi;
  };

  struct Bracket {
    double lo, hi;
    int lobe;
    double estimate;
    double arg_lo;  // the unwrapped arg G at lo
  };
  std::vector<Bracket> brackets;
  double prev_w = 0.5 * step;
  auto prev_g = frf(model, direction, prev_w);
  double prev_arg = std::arg(prev_g);
  double prev_phase = (prev_w * delay_s - epsilon(prev_arg)) / kTwoPi;
  for (long long i = 1; i <= n; ++i) {
    const double w = (static_cast<double>(i) + 0.5) * step;
    const auto g = frf(model, direction, w);
    ++result.boundary.evaluations;
    const double arg = arg_near(g, prev_arg);
    const double ph = (w * delay_s - epsilon(arg)) / kTwoPi;
    if (std::floor(ph) != std::floor(prev_phase) && (g.real() < 0.0 || prev_g.real() < 0.0)) {
      // Every integer passed, in either direction.
      const double lo_j = std::min(std::floor(prev_phase), std::floor(ph)) + 1.0;
      const double hi_j = std::max(std::floor(prev_phase), std::floor(ph));
      for (double j = lo_j; j <= hi_j; j += 1.0) {
        const double t = (j - prev_phase) / (ph - prev_phase);
        const double re = std::min(prev_g.real() + t * (g.real() - prev_g.real()),
                                   std::min(prev_g.real(), g.real()));
        const double estimate = -1.0 / (2.0 * coefficient_pa * re);
        brackets.push_back({prev_w, w, static_cast<int>(j), estimate, prev_arg});
      }
    }
    prev_w = w;
    prev_g = g;
    prev_arg = arg;
    prev_phase = ph;
  }

  // Refine in order of the interpolated estimate; once an estimate exceeds the best refined
  // depth by more than the interpolation can be off, no later bracket can win.
  std::sort(brackets.begin(), brackets.end(),
            [](const Bracket& a, const Bracket& b) { return a.estimate < b.estimate; });
  for (const Bracket& b : brackets) {
    if (b.lobe < 0) continue;
    if (result.boundary.found && b.estimate > 1.5 * result.boundary.depth_m) break;
    const auto root =
        brent_root([&](double w) { return phase(w, b.arg_lo) - b.lobe; }, b.lo, b.hi, 1e-13 * b.hi);
    if (!root || !root->converged) {
      ++result.boundary.unresolved;
      continue;
    }
    result.boundary.evaluations += root->evaluations;
    const auto g = frf(model, direction, root->x);
    if (!(g.real() < 0.0)) continue;
    const double depth = -1.0 / (2.0 * coefficient_pa * g.real());
    if (depth <= depth_max_m && (!result.boundary.found || depth < result.boundary.depth_m)) {
      result.boundary.found = true;
      result.boundary.bifurcation = Bifurcation::kHopf;
      result.boundary.depth_m = depth;
      result.boundary.chatter_hz = units::rad_per_s_to_hz(root->x);
      result.lobe = b.lobe;
    }
  }
  return result;
}

}  // namespace cutdyn
