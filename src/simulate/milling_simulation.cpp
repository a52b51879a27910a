#include "cutdyn/simulate/milling_simulation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/simulate/detail/modal_stepper.hpp"
#include "cutdyn/simulate/growth_estimate.hpp"

namespace cutdyn {
namespace {

using units::kPi;
using units::kTwoPi;

// Unit force directions on the cutter for a tooth at angle θ (clockwise from +y): t̂ opposes
// the tooth's motion, r̂ points to the cutter's centre; d(α) = cos α·t̂ + sin α·r̂ is the
// direction α from the tangent, (−cos u, sin u) with u = θ − α. With a spread L (the S1 closed
// form) it is averaged over the lags φω in [0, L] ([Ermolaev2020] eqs. 8–9, divided by L: the
// decision of docs/models/milling-simulation.md, "Force laws"):
// cos u → cos u·sin L/L + sin u·(1 − cos L)/L, sin u → sin u·sin L/L − cos u·(1 − cos L)/L.
// Evaluated from sin θ and cos θ, which the simulation tabulates per angle bin.
class Direction2 {
 public:
  Direction2(double alpha, double spread)
      : ca_(std::cos(alpha)),
        sa_(std::sin(alpha)),
        a_(spread < 1e-12 ? 1.0 : std::sin(spread) / spread),
        b_(spread < 1e-12 ? 0.0 : (1.0 - std::cos(spread)) / spread) {}
  Eigen::Vector2d at(double sin_theta, double cos_theta) const {
    const double cu = cos_theta * ca_ + sin_theta * sa_;
    const double su = sin_theta * ca_ - cos_theta * sa_;
    return {-(cu * a_ + su * b_), su * a_ - cu * b_};
  }

 private:
  double ca_, sa_, a_, b_;
};

double wrap(double angle) {
  double a = std::fmod(angle, kTwoPi);
  if (a < 0.0) a += kTwoPi;
  return a;
}

// Strictly inside, by more than `margin` (a node that rounding puts a hair inside a zero-chip
// edge is an edge node).
bool in_window(double theta, double entry, double exit, double margin) {
  const double a = wrap(theta);
  return a > entry + margin && a < exit - margin;
}

// ΔP = (Pmax − Pmin)/(|Pmax| + |Pmin|): (Pmax − Pmin)/(Pmax + Pmin) for a force that keeps its
// sign, 1 when it falls to zero or reverses, 0 for no force.
double pulsation(double most, double least) {
  const double scale = std::abs(most) + std::abs(least);
  return scale > 0.0 ? (most - least) / scale : 0.0;
}

}  // namespace

std::vector<std::string> MillingCut::validate() const {
  Validator v;
  v.merge(process.validate());
  v.require_positive("spindle_rad_s", spindle_rad_s, "rad/s");
  v.require_positive("feed_per_tooth_m", feed_per_tooth_m, "m");
  v.require_positive("width_m", width_m, "m");
  return v.problems();
}

std::vector<std::string> MillingSimulationOptions::validate() const {
  Validator v;
  v.require(steps_per_tooth >= 8 && steps_per_tooth <= 100000, "steps_per_tooth", steps_per_tooth,
            "", "must be 8 to 100000");
  v.require(revolutions >= 1.0 && revolutions <= 1e6, "revolutions", revolutions, "",
            "must be 1 to 1e6");
  v.require(summary_revolutions > 0.0 && summary_revolutions <= revolutions, "summary_revolutions",
            summary_revolutions, "", "must be positive and at most `revolutions`");
  v.require(slices >= 0 && slices <= 10000, "slices", slices, "", "must be 0 (automatic) to 10000");
  v.require(max_recorded_samples >= 2, "max_recorded_samples", max_recorded_samples, "",
            "must be at least 2");
  v.require(perturbation > 0.0 && perturbation <= 1.0, "perturbation", perturbation,
            "(of the feed per tooth)",
            "must be greater than 0 (the disturbance whose growth decides chatter) and at most 1");
  return v.problems();
}

MillingSimulationResult simulate_milling(const MillingCut& cut, const MillingSimulationOptions& o) {
  Validator v;
  v.merge(cut.validate());
  v.merge(o.validate());
  v.throw_if_any("milling simulation");

  const MillingProcess& process = cut.process;
  const ModalModel modes = process.structure_modes();  // fitted to a measured FRF too
  const EngagementWindow window = process.engagement.window();
  const int z = process.tool.teeth;
  const double omega = cut.spindle_rad_s;
  // Time step: a whole number of angle bins per revolution, z·spt.
  // With regeneration the chip follows the cutter's vibration: put 64 steps in the shortest
  // mode period. Without it the exact (zero-order-hold) step needs no such resolution.
  int spt = o.steps_per_tooth;
  if (!modes.modes.empty() && cut.regenerative) {
    const double tooth_period = kTwoPi / (omega * z);
    const double shortest = kTwoPi / modes.max_natural_rad_s();
    spt = std::max(spt, static_cast<int>(std::ceil(64.0 * tooth_period / shortest)));
  }
  const long long bins = static_cast<long long>(z) * spt;
  const double dtheta = kTwoPi / static_cast<double>(bins);
  const double dt = dtheta / omega;
  const auto steps =
      static_cast<long long>(std::llround(o.revolutions * static_cast<double>(bins)));
  constexpr long long kMaxWork = 4'000'000'000LL;

  // Teeth: angle behind tooth 0, snapped to the bins (uneven pitch), and feed per revolution.
  std::vector<double> pitch = process.tool.pitch_rad;
  if (pitch.empty()) pitch.assign(static_cast<std::size_t>(z), kTwoPi / z);
  std::vector<long long> behind_bins(static_cast<std::size_t>(z), 0);
  double behind = 0.0;
  for (int k = 1; k < z; ++k) {
    behind += pitch[static_cast<std::size_t>(k)];
    behind_bins[static_cast<std::size_t>(k)] = std::llround(behind / dtheta);
  }
  const double feed_speed = cut.feed_per_tooth_m * z * omega / kTwoPi;  // m/s along +x

  // Slices.
  const double lag = cut.lag_angle();
  int n_slices = 1;
  if (lag > 0.0 && !o.closed_form_helix) {
    // Automatic: one angle step of lag per slice, at most 1000 slices and 8 million
    // slice-bins (the tables below).
    const auto most = static_cast<int>(std::clamp(8'000'000LL / bins, 1LL, 1000LL));
    n_slices =
        o.slices > 0 ? o.slices : std::clamp(static_cast<int>(std::lround(lag / dtheta)), 1, most);
  }
  const double slice_width = cut.width_m / n_slices;
  std::vector<double> slice_lag(static_cast<std::size_t>(n_slices), 0.0);
  if (!o.closed_form_helix)
    for (int j = 0; j < n_slices; ++j)
      slice_lag[static_cast<std::size_t>(j)] = (j + 0.5) * lag / n_slices;
  if (static_cast<double>(n_slices) * static_cast<double>(bins) > 1e8) {
    throw InvalidInput({"slices = " + std::to_string(n_slices) + " × " + std::to_string(bins) +
                        " steps per revolution: more than 1e8 slice-bins of surface memory (fewer "
                        "slices or steps per tooth)"},
                       "milling simulation");
  }
  if (static_cast<double>(steps) * z * n_slices > static_cast<double>(kMaxWork)) {
    throw InvalidInput(
        {"revolutions = " + format_value(o.revolutions) + " with " + std::to_string(z) +
         " teeth × " + std::to_string(n_slices) + " slices × " + std::to_string(bins) +
         " steps per revolution: " + format_value(static_cast<double>(steps) * z * n_slices) +
         " slice evaluations, more than the limit 4e9 (fewer revolutions, slices or "
         "steps per tooth)"},
        "milling simulation");
  }

  // sin θ, cos θ and the window of every slice at every bin of its tooth's tip (θ ≡ bin·Δθ −
  // lag_j): tabulated once, bin-major (the slices of one bin together), so that a slice
  // evaluation needs no trigonometry. The force is linear between nodes (first-order hold);
  // a node's force counts, for the step it ends and the step it starts, with the fraction of
  // that step inside the window (the window's exact mean over the step, as in the full
  // discretization [Ding2010]). `in` (strictly inside at the node) gives the reported force.
  // An edge node (outside the window, next to it) carries the force at the window's edge by
  // linear extrapolation of the chip; whether the tooth cuts there is decided at the middle of
  // the in-window part of its step, where `s_in` is sin θ. (Deciding it by the sign of the
  // chip at the node itself, where the rigid chip s_z·sin θ is zero or negative at a
  // zero-chip edge, dropped half the regenerative force of these nodes: an O(Δt) error that
  // put the simulated boundary 0.4 % (slotting) to 1.8 % (a/D 0.25) above the lobes.)
  struct Angle {  // 32 bytes: the table is read every step
    double s, c;
    float g_end, g_start;
    bool in, active;
    float s_in;
  };
  struct Overlap {
    double fraction = 0.0, middle = 0.0;  // of the step [from, from + Δθ] inside the window
  };
  const auto window_overlap = [&](double from) {
    const double a = wrap(from);
    Overlap best;
    double total = 0.0;
    for (double turn : {0.0, kTwoPi}) {
      const double lo = std::max(a, window.entry_rad + turn);
      const double hi = std::min(a + dtheta, window.exit_rad + turn);
      if (hi <= lo) continue;
      total += hi - lo;
      if (hi - lo > best.fraction * dtheta) best.middle = from + (0.5 * (lo + hi) - a);
      best.fraction = std::max(best.fraction, (hi - lo) / dtheta);
    }
    const double g = total / dtheta;
    best.fraction = g > 1.0 - 1e-9 ? 1.0 : (g < 1e-9 ? 0.0 : g);
    return best;
  };
  std::vector<Angle> angles(static_cast<std::size_t>(n_slices * bins));
  for (int j = 0; j < n_slices; ++j) {
    for (long long b = 0; b < bins; ++b) {
      const double theta = static_cast<double>(b) * dtheta - slice_lag[static_cast<std::size_t>(j)];
      const Overlap end = window_overlap(theta - dtheta), start = window_overlap(theta);
      const double inside = start.fraction >= end.fraction ? start.middle : end.middle;
      angles[static_cast<std::size_t>(b * n_slices + j)] = {
          std::sin(theta),
          std::cos(theta),
          static_cast<float>(end.fraction),
          static_cast<float>(start.fraction),
          in_window(theta, window.entry_rad, window.exit_rad, 1e-6 * dtheta),
          end.fraction > 0.0 || start.fraction > 0.0,
          static_cast<float>(std::sin(inside))};
    }
  }

  // Structure.
  const bool rigid = modes.modes.empty();
  std::optional<ModalStepper> stepper;
  Eigen::MatrixXd c_gamma_end;  // C·Γ1
  if (!rigid) {
    stepper.emplace(modes, std::vector<Direction>{Direction::kX, Direction::kY}, dt);
    c_gamma_end = stepper->output_matrix() * stepper->gamma_end();
  }

  // Surfaces, per slice and bin: the feed position plus displacement along the bin's normal
  // when a tooth last cut there, kept at every node next to the window. A slice's surface is
  // indexed by the step of its tooth's tip (its own lag is the same for every tooth), so
  // consecutive teeth meet exactly the same bins.
  const auto bin_of = [&](long long tip_step) {
    long long b = tip_step % bins;
    if (b < 0) b += bins;
    return static_cast<std::size_t>(b);
  };
  std::vector<double> surface(static_cast<std::size_t>(n_slices * bins),
                              std::numeric_limits<double>::quiet_NaN());
  // Steps by which tooth k trails the tooth ahead of it (the rigid chip is the feed over them).
  std::vector<long long> gap_bins(static_cast<std::size_t>(z));
  for (int k = 0; k < z; ++k)
    gap_bins[static_cast<std::size_t>(k)] =
        k == 0 ? bins - behind_bins[static_cast<std::size_t>(z - 1)]
               : behind_bins[static_cast<std::size_t>(k)] -
                     behind_bins[static_cast<std::size_t>(k - 1)];

  const ErmolaevForceLaw* erm = process.s1_law ? &*process.s1_law : nullptr;
  const MechanisticForceLaw* mech = erm ? nullptr : &process.cutting;
  std::vector<double> lagged(static_cast<std::size_t>(z * n_slices), 0.0);  // U, S1 law
  const double t2 = erm ? erm->time_constant_s(omega) : 0.0;
  const double relax = t2 > 0.0 ? std::exp(-dt / t2) : 0.0;

  // Per slice: its width (the whole flute in the closed form) and force directions.
  const double spread = o.closed_form_helix ? lag : 0.0;
  const double width = o.closed_form_helix ? cut.width_m : slice_width;
  const double share = o.closed_form_helix ? 1.0 : 1.0 / n_slices;
  const Direction2 tangential(0.0, spread), radial(0.5 * kPi, spread);
  const Direction2 cutting(erm ? erm->phi_rez_rad : 0.0, spread);
  const Direction2 flank(erm ? erm->phi_skv_rad : 0.0, spread);
  // Loss of contact inside the window, away from its zero-chip edges (|sin θ| < kEdge).
  constexpr double kEdge = 0.05;

  // The forces of every slice at node n: `end` and `start` weighted for the steps that end
  // and start there, `now` the force at the instant. The chip is the stored surface's (r the
  // cutter's displacement) or, with `rigid_chip`, the feed since the tooth ahead (the steady
  // cut); a cutting slice stores its surface with r.
  struct NodeForces {
    Eigen::Vector2d end = Eigen::Vector2d::Zero(), start = Eigen::Vector2d::Zero(),
                    now = Eigen::Vector2d::Zero();
    double engaged = 0.0;
    double cutting = 0.0;  // ΣP: the teeth's cutting forces without the flank contact
    long long window = 0, lost = 0;
  };
  const auto evaluate = [&](long long n, const Eigen::Vector2d& r, bool rigid_chip) {
    // Local copies: the stores to the surfaces below cannot alias them, so they stay in
    // registers (through the closure the compiler reloaded them for every slice).
    const Direction2 t_dir = tangential, r_dir = radial, cut_dir = cutting, flank_dir = flank;
    const MechanisticForceLaw m_law = mech ? *mech : MechanisticForceLaw{};
    const double kt_b = m_law.kt_pa * width, kr_b = m_law.kr_pa * width;
    const double kte_b = m_law.kte_n_per_m * width, kre_b = m_law.kre_n_per_m * width;
    const bool regenerative = cut.regenerative;
    const bool unwindowed = erm && erm->lag_input == ErmolaevForceLaw::LagInput::kUnwindowed;
    const double r_x = r.x(), r_y = r.y();
    NodeForces nf;
    const double feed = feed_speed * static_cast<double>(n) * dt;  // feed motion along +x
    for (int k = 0; k < z; ++k) {
      const std::size_t bin = bin_of(n - behind_bins[static_cast<std::size_t>(k)]);
      const double rigid_feed =
          feed_speed * static_cast<double>(gap_bins[static_cast<std::size_t>(k)]) * dt;
      for (int j = 0; j < n_slices; ++j) {
        const std::size_t at =
            bin * static_cast<std::size_t>(n_slices) + static_cast<std::size_t>(j);
        const Angle& a = angles[at];
        double& u = lagged[static_cast<std::size_t>(k * n_slices + j)];
        double chip = 0.0;
        bool in_contact = false, known = false;  // known: a surface to measure the chip from
        if (a.active) {
          double& stored = surface[at];
          const double here = regenerative ? (feed + r_x) * a.s + r_y * a.c : feed * a.s;
          const bool fresh = !rigid_chip && std::isnan(stored);  // no surface yet: no chip
          known = !fresh;
          if (!fresh) {
            chip = rigid_chip ? rigid_feed * a.s : here - stored;
            // Inside the window the chip at the node decides; at an edge node the chip at the
            // middle of the in-window part of its step (the rigid chip there, the same
            // vibration).
            in_contact = a.in ? chip > 0.0 : chip + rigid_feed * (a.s_in - a.s) > 0.0;
          }
          if (in_contact || fresh) stored = here;  // else the older surface stays
        }
        if (a.in && std::abs(a.s) >= kEdge) {
          ++nf.window;
          if (!in_contact) ++nf.lost;
        }
        if (erm) {
          // U follows the chip inside the window only (a node next to it weighs its step's
          // share); unwindowed, also the chip out of contact and the tooth's path s_z·sin θ
          // outside the window ([Ermolaev2020] eqs. 3 and 5 as printed).
          double x_in = 0.0;
          if (in_contact && a.in)
            x_in = chip;
          else if (unwindowed)
            x_in = a.in && known ? chip : rigid_feed * a.s;
          u = x_in + (u - x_in) * relax;  // exact for X held over the step
        }
        if (!in_contact) continue;
        Eigen::Vector2d f;
        double p_cut = 0.0;  // the cutting force alone: Ft, or c·U (per flute)
        if (mech) {
          const double ft = kt_b * chip + kte_b;
          const double fr = kr_b * chip + kre_b;
          f = ft * t_dir.at(a.s, a.c) + fr * r_dir.at(a.s, a.c);
          p_cut = ft;
        } else {
          const double p = erm->c_n_per_m * (t2 > 0.0 ? u : chip);
          p_cut = share * p;
          // (An edge node's extrapolated chip may be slightly negative: the flank contact is
          // at most its value at zero chip.)
          const double contact = erm->p0_n * std::exp(-std::max(chip, 0.0) / erm->t1_m);
          f = share * (p * cut_dir.at(a.s, a.c) + contact * flank_dir.at(a.s, a.c));
        }
        nf.end += static_cast<double>(a.g_end) * f;
        nf.start += static_cast<double>(a.g_start) * f;
        if (a.in) {
          nf.now += f;
          nf.cutting += p_cut;
          nf.engaged += 1.0 / n_slices;
        }
      }
    }
    return nf;
  };

  // Once-per-period samples (tooth period; a revolution with uneven pitch).
  const long long period_steps = process.tool.pitch_rad.empty() ? spt : bins;
  Eigen::VectorXd x;                                      // modal state at the last node
  Eigen::Vector2d start_force = Eigen::Vector2d::Zero();  // of the step from the last node
  std::vector<Eigen::VectorXd> ring;                      // the states of the last period
  double orbit_peak = 0.0;                                // largest |r| of the forced vibration
  // Before t = 0 the cut is steady: the cutter on its periodic forced vibration, whose chip is
  // the feed since the tooth ahead (the regeneration of a periodic motion is zero). That
  // vibration is found by one revolution from rest under the steady forces, x_T, and the
  // periodic start x0 = (I − Φ_T)⁻¹·x_T [Floquet]; a second revolution from x0 follows it and
  // leaves its surfaces.
  // The S1 law's lag U starts on its periodic state too. U is affine in its start over a
  // revolution, U_T = relax^bins·U_0 + b (each step u ← relax·u + (1 − relax)·X), so one
  // revolution from U = 0 gives b and the periodic start is U_0 = b/(1 − relax^bins). (Started
  // from 0, U's transient made the first revolution's force aperiodic, and the periodic start
  // x0 amplified that by 1/|I − Φ_T| where the revolution nears a multiple of a mode's period:
  // 40 µm of free 503 Hz vibration at 15 060 rpm in the lightly damped ermolaev2020-fig7.)
  std::vector<double> periodic_lag;
  if (erm && relax > 0.0) {
    for (long long n = -bins; n < 0; ++n) evaluate(n, Eigen::Vector2d::Zero(), true);
    const double a = std::pow(relax, static_cast<double>(bins));
    for (double& u : lagged) u /= 1.0 - a;
    periodic_lag = lagged;
  }
  if (!rigid) {
    x = Eigen::VectorXd::Zero(stepper->states());
    start_force = evaluate(-bins, Eigen::Vector2d::Zero(), true).start;
    for (long long n = -bins + 1; n <= 0; ++n) {
      const NodeForces nf = evaluate(n, Eigen::Vector2d::Zero(), true);
      stepper->step_linear(x, start_force, nf.end);
      start_force = nf.start;
    }
    Eigen::MatrixXd phi_rev = Eigen::MatrixXd::Identity(x.size(), x.size()), power = stepper->phi();
    for (long long e = bins; e > 0; e >>= 1) {
      if (e & 1) phi_rev = phi_rev * power;
      power = power * power;
    }
    x = (Eigen::MatrixXd::Identity(x.size(), x.size()) - phi_rev).partialPivLu().solve(x);
    if (!periodic_lag.empty()) lagged = periodic_lag;  // the second revolution starts on it too
  }
  ring.assign(static_cast<std::size_t>(period_steps), rigid ? Eigen::VectorXd() : x);
  // The step in two halves (no allocation): predict() puts Φ·x(n−1) + Γ0·F(n−1) in `base` and
  // returns the displacement with the force held from n − 1 (error O(h³)); correct() adds
  // Γ1·F(n), the first-order hold x(n) = Φ·x(n−1) + Γ0·F(n−1) + Γ1·F(n) [Ding2010, W0 and W1].
  Eigen::VectorXd base, difference;
  if (!rigid) {
    base = x;
    difference = x;
  }
  const auto predict = [&](Eigen::Vector2d& r) {
    base.noalias() = stepper->phi() * x;
    base.noalias() += stepper->gamma_start() * start_force;
    r.noalias() = stepper->output_matrix() * base;
    r.noalias() += c_gamma_end * start_force;
  };
  const auto correct = [&](const NodeForces& nf) {
    x = base;
    x.noalias() += stepper->gamma_end() * nf.end;
    start_force = nf.start;
  };
  for (long long n = -bins; n < 0; ++n) {
    Eigen::Vector2d r = Eigen::Vector2d::Zero();
    if (!rigid && n > -bins)
      predict(r);
    else if (!rigid)
      r.noalias() = stepper->output_matrix() * x;
    const NodeForces nf = evaluate(n, r, true);
    if (!rigid) {
      if (n > -bins)
        correct(nf);
      else
        start_force = nf.start;
      orbit_peak = std::max(orbit_peak, (stepper->output_matrix() * x).cwiseAbs().maxCoeff());
      if (n >= -period_steps) ring[static_cast<std::size_t>((n + bins) % period_steps)] = x;
    }
  }
  // Runaway: far beyond any cut (the linear force law long invalid) and before overflow.
  const double runaway_bound = 1e3 * (cut.feed_per_tooth_m + orbit_peak);
  Eigen::VectorXd kick;
  if (!rigid) {
    kick = Eigen::VectorXd::Zero(x.size());
    for (Eigen::Index i = 0; i < x.size(); i += 2) kick(i) = o.perturbation * cut.feed_per_tooth_m;
  }

  MillingSimulationResult out;
  out.growth_settled = rigid || !cut.regenerative;  // no regeneration: forced by construction
  out.step_s = dt;
  out.steps = steps;
  out.slices = n_slices;
  out.steps_per_revolution = static_cast<int>(bins);
  const long long stride = std::max<long long>(1, steps / o.max_recorded_samples + 1);
  const auto summary_from = steps - std::llround(o.summary_revolutions * static_cast<double>(bins));
  // The wall is finished where the chip thickness s_z·sin θ vanishes: θ = π (down) or 0 (up).
  std::optional<double> finishing;
  if (window.exit_rad >= kPi - 1e-9)
    finishing = kPi;
  else if (window.entry_rad <= 1e-9)
    finishing = 0.0;
  // Its bin and the wall's normal there (n·r is the overcut).
  const std::size_t finishing_bin = finishing ? bin_of(std::llround(*finishing / dtheta)) : 0;
  const double normal_x = finishing ? std::sin(*finishing) : 0.0;
  const double normal_y = finishing ? std::cos(*finishing) : 0.0;

  // Summary tallies: over the summary revolutions, and per revolution (for a run stopped early).
  struct Tally {
    long long count = 0, sle_count = 0, window = 0, lost = 0;
    double f_sum = 0, fx_sum = 0, fy_sum = 0, teeth_sum = 0, f_max = 0, sle_sum = 0;
    double f_min = std::numeric_limits<double>::infinity();
    double p_sum = 0, p_max = -std::numeric_limits<double>::infinity();
    double p_min = std::numeric_limits<double>::infinity();
    double x_min = 1e300, x_max = -1e300, y_min = 1e300, y_max = -1e300;
    void merge(const Tally& t) {
      count += t.count;
      sle_count += t.sle_count;
      window += t.window;
      lost += t.lost;
      f_sum += t.f_sum;
      fx_sum += t.fx_sum;
      fy_sum += t.fy_sum;
      teeth_sum += t.teeth_sum;
      sle_sum += t.sle_sum;
      f_max = std::max(f_max, t.f_max);
      f_min = std::min(f_min, t.f_min);
      p_sum += t.p_sum;
      p_max = std::max(p_max, t.p_max);
      p_min = std::min(p_min, t.p_min);
      x_min = std::min(x_min, t.x_min);
      x_max = std::max(x_max, t.x_max);
      y_min = std::min(y_min, t.y_min);
      y_max = std::max(y_max, t.y_max);
    }
  };
  Tally summary, this_rev, last_rev;
  std::vector<Eigen::Vector2d> sync;
  std::vector<double> period_amplitude;  // of x(t) − x(t − period), per period
  // x(t) − x(t − period) at four phases of each period: linear observations of the free
  // response, for its dominant multiplier.
  constexpr int kPhases = 4;
  std::vector<std::vector<double>> period_samples;
  double amplitude_sum = 0.0;

  long long n = 0;
  int reported = -1;  // the last hundredth of the run reported
  for (; n < steps; ++n) {
    if (o.progress && static_cast<int>(n * 100 / steps) != reported) {
      reported = static_cast<int>(n * 100 / steps);
      o.progress(reported, 100);
    }
    const double t = static_cast<double>(n) * dt;
    // Predictor: the displacement with the force held from the last node (error O(h³)).
    Eigen::Vector2d r = Eigen::Vector2d::Zero();
    if (!rigid) predict(r);
    const NodeForces nf = evaluate(n, r, false);
    if (!rigid) {
      correct(nf);
      // The disturbance whose growth decides chatter; a chip from the feed alone cannot
      // chatter, and the kick's free vibration would only blur its forced vibration (for ever
      // in a lightly damped mode).
      if (n == 0 && cut.regenerative) x += kick;
      r.noalias() = stepper->output_matrix() * x;
    }
    const Eigen::Vector2d& f = nf.now;
    const double magnitude = f.norm();
    if (n % stride == 0) {
      out.time_s.push_back(t);
      out.fx_n.push_back(f.x());
      out.fy_n.push_back(f.y());
      out.force_n.push_back(magnitude);
      out.cutting_force_n.push_back(nf.cutting);
      out.x_m.push_back(r.x());
      out.y_m.push_back(r.y());
      out.teeth_in_cut.push_back(nf.engaged);
    }
    Tally step;
    step.count = 1;
    step.window = nf.window;
    step.lost = nf.lost;
    step.f_sum = step.f_max = step.f_min = magnitude;
    step.p_sum = step.p_max = step.p_min = nf.cutting;
    step.fx_sum = f.x();
    step.fy_sum = f.y();
    step.teeth_sum = nf.engaged;
    step.x_min = step.x_max = r.x();
    step.y_min = step.y_max = r.y();
    if (finishing) {
      for (int k = 0; k < z; ++k) {
        if (bin_of(n - behind_bins[static_cast<std::size_t>(k)]) == finishing_bin) {
          step.sle_sum += r.x() * normal_x + r.y() * normal_y;
          ++step.sle_count;
        }
      }
    }
    if (n >= summary_from) summary.merge(step);
    this_rev.merge(step);
    if ((n + 1) % bins == 0) {
      last_rev = this_rev;
      this_rev = Tally{};
    }
    if (n % period_steps == 0) sync.push_back(r);
    if (!rigid) {
      Eigen::VectorXd& then = ring[static_cast<std::size_t>(n % period_steps)];
      difference = x - then;
      amplitude_sum += std::sqrt(stepper->squared_amplitude(difference));
      then = x;
      const long long phase = (n + 1) % period_steps;
      for (int q = 0; q < kPhases; ++q) {
        if (phase != period_steps * q / kPhases) continue;
        if (q == 0) period_samples.emplace_back();
        if (!period_samples.empty())
          period_samples.back().insert(period_samples.back().end(), difference.data(),
                                       difference.data() + difference.size());
      }
      if ((n + 1) % period_steps == 0) {
        period_amplitude.push_back(amplitude_sum / static_cast<double>(period_steps));
        amplitude_sum = 0.0;
      }
      if (!(r.cwiseAbs().maxCoeff() <= runaway_bound)) {  // also catches NaN
        out.status = SimulationStatus::kRunaway;
        out.stop_time_s = t;
        ++n;
        break;
      }
    }
  }
  if (out.status == SimulationStatus::kCompleted) out.stop_time_s = static_cast<double>(steps) * dt;
  out.steps = n;
  if (summary.count == 0) {  // stopped before the summary revolutions: the last one or two
    summary = last_rev;
    summary.merge(this_rev);
  }

  const auto count = static_cast<double>(summary.count);
  out.mean_force_n = summary.f_sum / count;
  out.mean_fx_n = summary.fx_sum / count;
  out.mean_fy_n = summary.fy_sum / count;
  out.mean_teeth_in_cut = summary.teeth_sum / count;
  out.peak_force_n = summary.f_max;
  out.min_force_n = summary.f_min;
  out.force_pulsation = pulsation(summary.f_max, summary.f_min);
  out.mean_cutting_force_n = summary.p_sum / count;
  out.cutting_force_pulsation = pulsation(summary.p_max, summary.p_min);
  out.vibration_pp_x_m = summary.x_max - summary.x_min;
  out.vibration_pp_y_m = summary.y_max - summary.y_min;
  if (summary.sle_count > 0)
    out.surface_location_error_m = summary.sle_sum / static_cast<double>(summary.sle_count);
  out.contact_loss = summary.window > 0
                         ? static_cast<double>(summary.lost) / static_cast<double>(summary.window)
                         : 0.0;

  // Chatter indicator: the once-per-period samples of a forced (stable) vibration repeat;
  // chatter makes them wander. Over the second half of the run.
  std::vector<double> change;
  for (std::size_t i = sync.size() / 2 + 1; i < sync.size(); ++i)
    change.push_back((sync[i] - sync[i - 1]).norm());
  const double pp = std::max(out.vibration_pp_x_m, out.vibration_pp_y_m);
  if (!change.empty() && pp > 0.0) {
    double mean = 0.0;
    for (double d : change) mean += d;
    out.chatter_indicator = mean / static_cast<double>(change.size()) / pp;
  }

  // Growth of the perturbation: the forced vibration repeats every period, so x(t) − x(t −
  // period) is the free (regenerative) response to the disturbance at t = 0 alone. Taken over
  // the periods before it fell 1e9-fold (rounding) or reached 10 % of the feed per tooth (teeth
  // leaving the cut: no longer linear): the largest multiplier present in its samples, or,
  // where a few multipliers do not explain them, the slope of its log-amplitude over the
  // second half of those periods.
  if (!rigid && cut.regenerative && period_amplitude.size() >= 2) {
    std::size_t end = period_amplitude.size();
    double largest = 0.0;
    for (std::size_t i = 0; i < period_amplitude.size(); ++i) {
      const double a = period_amplitude[i];
      largest = std::max(largest, a);
      if (!(a > 1e-9 * largest) || a > 0.1 * cut.feed_per_tooth_m) {
        end = std::max<std::size_t>(i + (a > 0.1 * cut.feed_per_tooth_m ? 1 : 0), 2);
        break;
      }
    }
    const std::size_t begin = std::min(end / 2, end - 2);
    std::vector<double> log_amplitude;
    for (std::size_t i = begin; i < end; ++i)
      log_amplitude.push_back(std::log(std::max(period_amplitude[i], 1e-300)));
    // (A sample is whole once its period has ended; the last one may not have.)
    period_samples.resize(std::min(period_samples.size(), end));
    if (!period_samples.empty() &&
        period_samples.back().size() != static_cast<std::size_t>(kPhases * x.size()))
      period_samples.pop_back();
    if (const auto multiplier = dominant_multiplier(period_samples)) {
      out.growth_per_period = multiplier->growth_per_period;
      out.growth_components = multiplier->components;
      out.growth_settled = true;
    } else {
      out.growth_per_period = index_slope(log_amplitude);
      out.growth_settled = slope_settled(log_amplitude);
    }
    out.growth_rate_per_s = out.growth_per_period / (static_cast<double>(period_steps) * dt);
  }
  // Without regeneration the vibration is forced by construction: no chatter.
  out.chatter = cut.regenerative && !rigid &&
                (out.status == SimulationStatus::kRunaway || out.growth_per_period > 0.0);
  return out;
}

}  // namespace cutdyn
