#include "cutdyn/stability/milling.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <limits>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/stability/lobes.hpp"
#include "cutdyn/stability/multi_frequency.hpp"

namespace cutdyn {
namespace {

using cplx = std::complex<double>;
using units::kPi;
using units::kTwoPi;

// ∫_a^b e^(iκφ) dφ.
cplx exp_integral(double kappa, double a, double b) {
  if (kappa == 0.0) return {b - a, 0.0};
  const cplx i(0.0, 1.0);
  return (std::exp(i * kappa * b) - std::exp(i * kappa * a)) / (i * kappa);
}

// ∫_a^b A(φ) e^(−iκφ) dφ for Altintas' directional matrix, from the integrals of
// e^(−iκφ), e^(i(2−κ)φ) and e^(−i(2+κ)φ) (sin 2φ and cos 2φ as exponentials). A(φ) of
// eq. MS-2 (docs/models/milling-stability.md), entry by entry.
Eigen::Matrix2cd directional_integral(double kappa, double a, double b, double kr) {
  const cplx i(0.0, 1.0);
  const cplx one = exp_integral(-kappa, a, b);
  const cplx ep = exp_integral(2.0 - kappa, a, b);   // e^(2iφ)
  const cplx em = exp_integral(-2.0 - kappa, a, b);  // e^(−2iφ)
  const cplx s2 = (ep - em) / (2.0 * i);             // ∫ sin 2φ·e^(−iκφ)
  const cplx c2 = (ep + em) / 2.0;                   // ∫ cos 2φ·e^(−iκφ)
  Eigen::Matrix2cd m;
  m(0, 0) = -s2 - kr * (one - c2);
  m(0, 1) = -(one + c2) - kr * s2;
  m(1, 0) = (one - c2) - kr * s2;
  m(1, 1) = s2 - kr * (one + c2);
  return m;
}

// ∫_a^b A(φ) dφ, real and in closed form: with ∫ sin 2φ = sin(a + b)·sin(b − a) and
// ∫ cos 2φ = cos(a + b)·sin(b − a) over [a, b] (no cancellation on short intervals). The
// κ = 0 case of directional_integral, which the period means of every step ask for (eq. MS-2,
// docs/models/milling-stability.md).
Eigen::Matrix2d directional_mean_integral(double a, double b, double kr) {
  const double l = b - a, sl = std::sin(l);
  const double s2 = std::sin(a + b) * sl, c2 = std::cos(a + b) * sl;
  Eigen::Matrix2d m;
  m << -s2 - kr * (l - c2), -(l + c2) - kr * s2, (l - c2) - kr * s2, s2 - kr * (l + c2);
  return m;
}

// Σ piece(lo, hi) over the parts [lo, hi] of [a, b] inside the window [φst, φex] repeated
// every 2π.
template <class Piece>
auto windowed_sum(double a, double b, double st, double ex, const Piece& piece) {
  decltype(piece(a, b)) sum;
  sum.setZero();
  const double k0 = std::floor((a - ex) / kTwoPi);
  for (double k = k0; st + kTwoPi * k < b; k += 1.0) {
    const double lo = std::max(a, st + kTwoPi * k);
    const double hi = std::min(b, ex + kTwoPi * k);
    if (hi > lo) sum += piece(lo, hi);
  }
  return sum;
}

// ∫ over φ in [a, b] of A(φ)·g(φ)·e^(−iκφ), with g the window [φst, φex] repeated every 2π.
Eigen::Matrix2cd windowed_integral(double kappa, double a, double b, double st, double ex,
                                   double kr) {
  return windowed_sum(a, b, st, ex, [&](double lo, double hi) {
    return directional_integral(kappa, lo, hi, kr);
  });
}

}  // namespace

// Eq. MS-2 (docs/models/milling-stability.md): the forces of eq. MS-1 summed, F = (a/2)·Kt·A·Δ.
Eigen::Matrix2d milling_directional_matrix(double phi, double kr) {
  const double s2 = std::sin(2.0 * phi), c2 = std::cos(2.0 * phi);
  Eigen::Matrix2d a;
  a << -s2 - kr * (1.0 - c2), -(1.0 + c2) - kr * s2, (1.0 - c2) - kr * s2, s2 - kr * (1.0 + c2);
  return a;
}

namespace {

// h(t) = scale·Σi weight_i·A(Ωs·t − c_i)·g(Ωs·t − c_i): teeth (and axial slices of them) at
// angular offsets c_i behind the reference tooth, periodic with `period_s`. Means and Fourier
// coefficients are exact (closed-form integrals of e^(iκφ) over the windows).
struct ToothSet {
  std::vector<double> offsets_rad;  // c_i
  double weight = 1.0;              // per offset (1/slices)
  std::vector<double> edges_rad;    // offsets of the tooth tips (no helix lag): breakpoints
};

PeriodicCoefficient tooth_coefficient(const MillingProcess& m, double spindle, double period_s,
                                      const ToothSet& teeth) {
  const double st = m.engagement.entry_angle(), ex = m.engagement.exit_angle();
  const double kr = m.cutting.kr_pa / m.cutting.kt_pa;
  // H = −(Kt/2)·A, eq. MS-3 (docs/models/milling-stability.md).
  const double scale = -0.5 * m.cutting.kt_pa;
  const double span = spindle * period_s;
  PeriodicCoefficient h;
  h.dim = 2;
  h.period_s = period_s;
  for (double c : teeth.edges_rad) {
    for (double edge : {st, ex}) {
      double phase = std::fmod(edge + c, span);
      if (phase < 0.0) phase += span;
      const double t = phase / spindle;
      if (t >= 0.0 && t < period_s) h.breakpoints_s.push_back(t);
    }
  }
  std::sort(h.breakpoints_s.begin(), h.breakpoints_s.end());
  h.mean = [=](double t0, double t1) {
    Eigen::Matrix2d sum = Eigen::Matrix2d::Zero();
    for (double c : teeth.offsets_rad) {
      sum += windowed_sum(spindle * t0 - c, spindle * t1 - c, st, ex, [&](double lo, double hi) {
        return directional_mean_integral(lo, hi, kr);
      });
    }
    return Eigen::MatrixXd(scale * teeth.weight * sum / (spindle * (t1 - t0)));
  };
  // H_p = (1/P)∫0^P h(t)·e^(−ipω0·t) dt; with φ = Ωs·t − c: e^(−iνc)·∫ A·g·e^(−iνφ) dφ over
  // [−c, Ωs·P − c], ν = p·ω0/Ωs. For the tooth period (ν = pz) this is eq. MS-5
  // (docs/models/milling-stability.md).
  h.fourier = [=](int p) {
    const double nu = static_cast<double>(p) * kTwoPi / span;
    Eigen::Matrix2cd sum = Eigen::Matrix2cd::Zero();
    for (double c : teeth.offsets_rad)
      sum += std::polar(1.0, -nu * c) * windowed_integral(nu, -c, span - c, st, ex, kr);
    return Eigen::MatrixXcd(sum * (scale * teeth.weight / span));
  };
  return h;
}

}  // namespace

DelayedSystem milling_system(const MillingProcess& model, double rpm, double depth_m) {
  if (const auto problems = model.validate_for_stability(); !problems.empty())
    throw InvalidInput(problems, "milling model");
  if (!(depth_m >= 0.0))
    throw InvalidInput({"depth = " + format_value(depth_m) + " m: must not be negative"},
                       "milling model");
  const auto ss = modal_state_space(model.structure_modes(), {Direction::kX, Direction::kY});
  DelayedSystem s;
  s.A0 = ss.A;
  s.E = ss.B;
  s.C = ss.C;
  if (model.measured) {
    s.measured_response = [given = model.modal, measured = *model.measured,
                           directions = std::vector<Direction>{Direction::kX, Direction::kY}](double w,
                                                                  Eigen::MatrixXcd& g) {
      combined_receptance(given, measured, directions, w, g);
    };
  }
  const double spindle = units::rpm_to_rad_per_s(rpm);  // Ωs
  const int z = model.tool.teeth;
  // Axial slices: slice k of K lags the tooth tip by (k + 1/2)·λ/K, λ the flute's lag over
  // the depth; each carries 1/K of the depth.
  const int K = model.tool.slices(depth_m);
  const double lag = model.tool.lag_angle(depth_m);
  std::vector<double> slice_lags;
  for (int k = 0; k < K; ++k) slice_lags.push_back((k + 0.5) * lag / K);

  if (model.tool.even_pitch()) {
    // One term: every tooth sees the previous one's surface τ = T = 2π/(z·Ωs) earlier, and the
    // coefficient has the tooth period (eq. MS-4, docs/models/milling-stability.md).
    const double pitch = kTwoPi / z;
    ToothSet set;
    set.weight = 1.0 / K;
    for (int j = 0; j < z; ++j) {
      set.edges_rad.push_back(pitch * j);
      for (double d : slice_lags) set.offsets_rad.push_back(pitch * j + d);
    }
    s.delay_s = pitch / spindle;
    s.H = tooth_coefficient(model, spindle, s.delay_s, set);
    return s;
  }
  // Uneven pitch: tooth j trails tooth j − 1 by pitch_j and cuts its surface pitch_j/Ωs later:
  // one delay term per tooth, all with the period of one revolution (eq. MS-13,
  // docs/models/milling-stability.md).
  const std::vector<double> pitches = model.tool.pitch_angles();
  const double revolution = kTwoPi / spindle;
  double behind = 0.0;  // angle of tooth j behind tooth 0
  for (int j = 0; j < z; ++j) {
    if (j > 0) behind += pitches[static_cast<std::size_t>(j)];
    ToothSet set;
    set.weight = 1.0 / K;
    set.edges_rad.push_back(behind);
    for (double d : slice_lags) set.offsets_rad.push_back(behind + d);
    DelayTerm term{tooth_coefficient(model, spindle, revolution, set),
                   pitches[static_cast<std::size_t>(j)] / spindle};
    if (j == 0) {
      s.H = std::move(term.H);
      s.delay_s = term.delay_s;
    } else {
      s.more_delays.push_back(std::move(term));
    }
  }
  return s;
}

std::span<const Field<MillingStabilityOptions>> MillingStabilityOptions::fields() {
  using O = MillingStabilityOptions;
  static const Field<O> list[] = {
      make_field(stability_fields::kDepthMax, &O::depth_max_m),
      make_field(stability_fields::kHarmonics, &O::harmonics),
      {"rel_tol", FieldType::kNumber, fields::kNone, FieldRange::closed(1e-12, 0.1), &O::rel_tol,
       "depth tolerance", "relative tolerance of the critical depth"},
      {"coarse_steps", FieldType::kInteger, fields::kNone, FieldRange::closed(1, 10000),
       &O::coarse_steps, "depth grid", "depths scanned below the limit before Brent's method"},
  };
  return list;
}

std::vector<std::string> MillingStabilityOptions::validate() const {
  Validator v;
  check_fields(*this, fields(), v);
  v.merge(fd.validate());
  return v.problems();
}

MillingStabilityOptions extend_search(const MillingStabilityOptions& o, double depth_m) {
  depth_m = std::min(depth_m, kMaxDepthM);  // no search deeper than any cut (method.hpp)
  if (!(depth_m > o.depth_max_m)) return o;
  Validator v;
  v.require(depth_m <= kMaxSearchExtension * o.depth_max_m, "depth", depth_m, "m",
            "must be at most " + format_value(kMaxSearchExtension) + " times the search limit " +
                format_value(o.depth_max_m) + " m (raise the depth limit)");
  v.throw_if_any("stability search");
  MillingStabilityOptions out = o;
  const double step = o.depth_max_m / o.coarse_steps;
  out.coarse_steps = static_cast<int>(std::ceil(depth_m / step - 1e-9));
  out.depth_max_m = out.coarse_steps * step;
  if (out.depth_max_m > kMaxDepthM) {  // the grid point past 10 m: the one below it
    --out.coarse_steps;
    out.depth_max_m = out.coarse_steps * step;
  }
  return out;
}

namespace {

// The search at one speed; hint > 0: the full discretization starts from it (straddling it
// first when `close`).
MillingBoundary critical_depth_at(const MillingProcess& model, double rpm,
                                  const MillingStabilityOptions& o, double hint,
                                  bool close = false) {
  Validator v;
  v.merge(model.validate_for_stability());
  v.merge(o.validate());
  v.require_positive("spindle speed", rpm, "rpm");
  v.throw_if_any("milling stability");
  const bool helical = model.tool.helix_rad > 0.0;
  const auto system_at = [&](double depth) { return milling_system(model, rpm, depth); };
  MillingBoundary out;
  switch (o.method) {
    case MillingMethod::kZeroOrder:
    case MillingMethod::kMultiFrequency: {
      MultiFrequencyOptions mf;
      // Zero-order: no harmonics, eq. MS-6 (docs/models/milling-stability.md).
      mf.harmonics = o.method == MillingMethod::kZeroOrder ? 0 : o.harmonics;
      mf.exact_harmonics = o.exact_harmonics;
      mf.dense_eigenvalues = o.dense_eigenvalues;
      mf.uniform_step = o.uniform_frequency_step;
      // Uneven pitch: H has the period of a revolution, so the same resolution in frequency
      // needs z harmonics of the spindle frequency per harmonic of the tooth frequency.
      if (!model.tool.even_pitch()) {
        mf.harmonics *= model.tool.teeth;
        mf.max_harmonics = std::max(mf.max_harmonics, mf.harmonics);
      }
      mf.depth_max_m = o.depth_max_m;
      if (!helical || mf.harmonics == 0) {
        out.boundary = multi_frequency_critical_depth(system_at(0.0), mf);
        break;
      }
      // H depends on the depth: the boundary is where a = w_crit(H(a)). The margin's sign only
      // asks whether H(a) has a boundary below a, and its value matters near the root: the
      // frozen system's scan looks no deeper than 2a (a > 0; where it finds nothing, the
      // margin is taken as a − 4a). A shallow limit lets the scan leave out the small
      // eigenvalues, which are most of its cost.
      const auto limit = [&](double a) {
        return a > 0.0 ? std::min(2.0 * a, mf.depth_max_m) : mf.depth_max_m;
      };
      const auto frozen = [&](double a) {
        MultiFrequencyOptions near = mf;
        near.depth_max_m = limit(a);
        return multi_frequency_critical_depth(system_at(a), near);
      };
      const auto margin = [&](double a) {
        const CriticalDepth c = frozen(a);
        return a - (c.found ? c.depth_m : 2.0 * limit(a));
      };
      out.boundary = critical_depth_by_bracketing(margin, o.depth_max_m, o.coarse_steps, o.rel_tol);
      if (out.boundary.found) {
        const CriticalDepth at = frozen(out.boundary.depth_m);
        out.boundary.chatter_hz = at.chatter_hz;
        out.boundary.bifurcation = at.bifurcation;
        out.boundary.truncated = at.truncated;
      }
      break;
    }
    case MillingMethod::kFullDiscretization:
    case MillingMethod::kFullDiscretizationDense: {
      FdOptions fd = o.fd;
      fd.depth_max_m = o.depth_max_m;
      const RadiusSolver solver = o.method == MillingMethod::kFullDiscretizationDense
                                      ? RadiusSolver::kDense
                                      : RadiusSolver::kArnoldi;
      if (hint > 0.0) {
        out.boundary = helical ? fd_critical_depth_from_hint(system_at, fd, solver, o.rel_tol,
                                                             o.coarse_steps, hint, close)
                               : fd_critical_depth_from_hint(system_at(0.0), fd, solver,
                                                             o.rel_tol, o.coarse_steps, hint,
                                                             close);
        break;
      }
      out.boundary =
          helical
              ? fd_critical_depth_by_radius(system_at, fd, solver, o.rel_tol, o.coarse_steps)
              : fd_critical_depth_by_radius(system_at(0.0), fd, solver, o.rel_tol, o.coarse_steps);
      break;
    }
  }
  if (out.boundary.found) {
    // T = 60/(n·z), eq. MS-4 (docs/models/milling-stability.md).
    const double tooth_period = 60.0 / (rpm * model.tool.teeth);
    out.lobe = static_cast<int>(std::floor(out.boundary.chatter_hz * tooth_period));
  }
  return out;
}

}  // namespace

MillingBoundary milling_critical_depth(const MillingProcess& model, double rpm,
                                       const MillingStabilityOptions& o) {
  return critical_depth_at(model, rpm, o, 0.0);
}

MillingBoundary milling_critical_depth(const MillingProcess& model, double rpm,
                                       const MillingStabilityOptions& o, double hint_depth_m) {
  if (!(hint_depth_m > 0.0) || !std::isfinite(hint_depth_m))
    throw InvalidInput({"depth hint = " + format_value(hint_depth_m) + " m: must be positive"},
                       "milling stability");
  return critical_depth_at(model, rpm, o, hint_depth_m);
}

MillingDepthHint milling_depth_prediction(double rpm, const std::vector<const LobePoint*>& near) {
  if (near.empty() || !near[0]->boundary.found) return {};
  const LobePoint& a = *near[0];
  if (near.size() < 2 || !near[1]->boundary.found) return {a.boundary.depth_m, false};
  const LobePoint& b = *near[1];
  const double da = a.boundary.depth_m, db = b.boundary.depth_m;
  const auto same_lobe = [](const LobePoint& p, const LobePoint& q) {
    return p.lobe == q.lobe && p.boundary.bifurcation == q.boundary.bifurcation && p.rpm != q.rpm;
  };
  if (!same_lobe(a, b)) {
    // Across a cusp: a refined speed between a and b lies near both; a run's next speed
    // after a lobe change is nearest to a.
    return {(rpm - a.rpm) * (rpm - b.rpm) < 0.0 ? std::min(da, db) : da, false};
  }
  // Along a lobe ln(depth) is smooth in the speed. Three speeds before this one on the lobe:
  // the parabola through them (Lagrange form), usually within a fraction of the search's
  // tolerance (on the default milling lobes, half of the speeds within 0.015 %); two: the line.
  const double la = std::log(da), lb = std::log(db);
  double predicted = la + (lb - la) * (rpm - a.rpm) / (b.rpm - a.rpm);
  bool close = false;
  if (near.size() >= 3 && near[2]->boundary.found && same_lobe(b, *near[2]) &&
      near[2]->rpm != a.rpm) {
    const LobePoint& c = *near[2];
    const double lc = std::log(c.boundary.depth_m);
    const double xa = a.rpm, xb = b.rpm, xc = c.rpm;
    predicted = la * (rpm - xb) * (rpm - xc) / ((xa - xb) * (xa - xc)) +
                lb * (rpm - xa) * (rpm - xc) / ((xb - xa) * (xb - xc)) +
                lc * (rpm - xa) * (rpm - xb) / ((xc - xa) * (xc - xb));
    close = true;
  }
  return {std::clamp(std::exp(predicted), 0.5 * da, 2.0 * da), close};
}

double milling_depth_hint(double rpm, const std::vector<const LobePoint*>& near) {
  return milling_depth_prediction(rpm, near).depth_m;
}

LobesReport trace_milling_lobes(const MillingProcess& model, const MillingStabilityOptions& o,
                                const LobesOptions& grid,
                                const std::function<void(int, int)>& progress) {
  const bool fd = o.method == MillingMethod::kFullDiscretization ||
                  o.method == MillingMethod::kFullDiscretizationDense;
  if (!fd || !o.warm_start) {
    return trace_lobes(
        [&](double rpm) {
          const MillingBoundary b = milling_critical_depth(model, rpm, o);
          return LobePoint{rpm, b.boundary, 1.0, b.lobe};
        },
        grid, progress);
  }
  return trace_lobes_warm(
      [&](double rpm, const std::vector<const LobePoint*>& near) {
        const MillingDepthHint hint = milling_depth_prediction(rpm, near);
        const MillingBoundary b = critical_depth_at(model, rpm, o, hint.depth_m, hint.close);
        return LobePoint{rpm, b.boundary, 1.0, b.lobe};
      },
      grid, progress);
}

std::optional<std::string> milling_method_caveat(const MillingProcess& model, MillingMethod method,
                                                 double rpm_min, double /*rpm_max*/) {
  if (method != MillingMethod::kZeroOrder) return std::nullopt;
  std::vector<std::string> reasons;
  if (model.engagement.exit_angle() - model.engagement.entry_angle() < units::kPi - 1e-9)
    reasons.push_back(
        "the cut is not a slot (it misses flip lobes, about half the depth at a/D "
        "<= 0.1)");
  double lowest_hz = std::numeric_limits<double>::infinity();
  for (const Mode& m : model.structure_modes().modes)
    lowest_hz = std::min(lowest_hz, units::rad_per_s_to_hz(m.natural_rad_s));
  const double threshold_rpm = 0.5 * lowest_hz * 60.0 / model.tool.teeth;
  if (rpm_min < threshold_rpm) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "below %.0f rpm the tooth frequency is under half the lowest mode's (%.4g Hz)",
                  threshold_rpm, lowest_hz);
    reasons.emplace_back(text);
  }
  if (reasons.empty()) return std::nullopt;
  std::string text = "zero-order (averaged) method outside its range: ";
  for (std::size_t i = 0; i < reasons.size(); ++i) text += (i ? "; " : "") + reasons[i];
  return text +
         "; it was 17-86 % off such cuts in the cross-method tests, in either direction — a "
         "screening method only; full-discretization (the default) decides";
}

const char* to_string(MillingMethod method) {
  switch (method) {
    case MillingMethod::kZeroOrder:
      return "zero-order";
    case MillingMethod::kMultiFrequency:
      return "multi-frequency";
    case MillingMethod::kFullDiscretization:
      return "full-discretization";
    case MillingMethod::kFullDiscretizationDense:
      return "full-discretization-dense";
  }
  return "?";
}

MillingMethod milling_method(StabilityMethod asked) {
  switch (asked) {
    case StabilityMethod::kZeroOrder:
    case StabilityMethod::kClosedForm:
      return MillingMethod::kZeroOrder;
    case StabilityMethod::kMultiFrequency:
      return MillingMethod::kMultiFrequency;
    case StabilityMethod::kFullDiscretizationDense:
      return MillingMethod::kFullDiscretizationDense;
    case StabilityMethod::kFullDiscretization:
    case StabilityMethod::kAuto:
      break;
  }
  return MillingMethod::kFullDiscretization;
}

}  // namespace cutdyn
