// fit_modes and fitted_frf: input checks, the band, the stabilisation diagram and the choice
// of poles, the refinement and the result. docs/models/modal-fitting.md.
#include "cutdyn/modal/frf_fit.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "cutdyn/core/error.hpp"
#include "frf_fit_internal.hpp"

namespace cutdyn {
namespace {

using fit_detail::BandData;
using fit_detail::cd;
using fit_detail::PoleResidueModel;

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr int kMinBandPoints = 10;
constexpr double kStableFrequency = 0.01;  // relative change between orders
constexpr double kStableDamping = 0.05;
constexpr double kPhaseNoteDeg = 10.0;
constexpr double kPoorFit = 0.1;  // RMS relative error
// The modes alone (the time-domain methods' structure) may differ from the table by this much
// (RMS relative) before a warning (§10).
constexpr double kModelWarning = 0.05;
// A mode the automatic choice keeps raises the RMS error by 10 % when removed from a good fit
// (RMS error <= kPoorFit), by 1 % from a poor one (where a missing mode inflates the error).
constexpr double kSignificance = 1.1;
constexpr double kSignificancePoorFit = 1.01;

std::string fixed(double value, int digits) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*f", digits, value);
  return buf;
}

// ---- input ------------------------------------------------------------------------------

BandData band_of(const MeasuredFrf& frf, const FrfFitOptions& options, FrfFit& out) {
  Validator v;
  for (const std::string& p : frf.validate()) v.add("frf." + p);
  v.throw_if_any("fit");
  const double lo = options.lo_hz.value_or(frf.min_hz());
  const double hi = options.hi_hz.value_or(frf.max_hz());
  const std::string band_text = "band " + format_value(lo) + "…" + format_value(hi) + " Hz";
  if (options.lo_hz) v.require(lo >= 0.0, "band.lo_hz", lo, "Hz", "must be at least 0");
  if (options.hi_hz) v.require(hi > lo, "band.hi_hz", hi, "Hz", "must be above band.lo_hz");
  v.require(options.modes >= 0, "modes", options.modes, "", "must be at least 0 (0 = automatic)");
  v.require(options.max_modes >= 1, "max_modes", options.max_modes, "", "must be at least 1");
  v.throw_if_any("fit");
  BandData band;
  double peak = 0.0;
  for (std::size_t i = 0; i < frf.frequency_hz.size(); ++i) {
    const double f = frf.frequency_hz[i];
    if (f < lo || f > hi) continue;
    band.omega.push_back(kTwoPi * f);
    band.g.push_back(frf.receptance_m_per_n[i]);
    peak = std::max(peak, std::abs(frf.receptance_m_per_n[i]));
  }
  const int points = static_cast<int>(band.size());
  if (points < kMinBandPoints) {
    v.add(band_text + ": holds " + std::to_string(points) + " of the table's points (" +
          format_value(frf.min_hz()) + "…" + format_value(frf.max_hz()) + " Hz), at least " +
          std::to_string(kMinBandPoints) + " are needed");
  } else if (options.modes > points / 4) {
    v.add("modes = " + std::to_string(options.modes) + ": more than a quarter of the " +
          std::to_string(points) + " points in the " + band_text + " (each mode has 4 parameters)");
  } else if (!(peak > 0.0)) {
    v.add("frf.receptance_m_per_n: zero at every point of the " + band_text);
  }
  v.throw_if_any("fit");
  if (lo < frf.min_hz() || hi > frf.max_hz())
    out.warnings.push_back(band_text + " reaches beyond the table (" + format_value(frf.min_hz()) +
                           "…" + format_value(frf.max_hz()) + " Hz): fitted over " +
                           format_value(std::max(lo, frf.min_hz())) + "…" +
                           format_value(std::min(hi, frf.max_hz())) + " Hz");
  out.lo_hz = std::max(lo, frf.min_hz());
  out.hi_hz = std::min(hi, frf.max_hz());
  out.points = points;
  band.lo_rad_s = kTwoPi * out.lo_hz;
  band.hi_rad_s = kTwoPi * out.hi_hz;
  const double floor = 1e-6 * peak;  // keeps a zero of the table from an infinite weight
  for (const cd& g : band.g) band.w.push_back(1.0 / std::max(std::abs(g), floor));
  return band;
}

// ---- stabilisation diagram and the choice of poles ----------------------------------------

struct Cluster {
  std::vector<std::size_t> members;  // indices into the diagram
  double center_hz = 0.0;
  int stable_orders = 0;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::vector<StabilisationPoint> diagram(const std::vector<std::vector<cd>>& poles) {
  std::vector<StabilisationPoint> points;
  std::vector<StabilisationPoint> previous;
  for (std::size_t i = 0; i < poles.size(); ++i) {
    std::vector<StabilisationPoint> current;
    for (const cd& lambda : poles[i]) {
      StabilisationPoint p;
      p.order = static_cast<int>(i) + 1;
      p.natural_hz = std::abs(lambda) / kTwoPi;
      p.damping_ratio = -lambda.real() / std::abs(lambda);
      for (const StabilisationPoint& q : previous) {
        if (std::abs(p.natural_hz - q.natural_hz) <= kStableFrequency * q.natural_hz &&
            std::abs(p.damping_ratio - q.damping_ratio) <= kStableDamping * q.damping_ratio)
          p.stable = true;
      }
      current.push_back(p);
    }
    points.insert(points.end(), current.begin(), current.end());
    previous = std::move(current);
  }
  return points;
}

// Groups the diagram's poles (the stable ones only, or all) by frequency, each joining the
// group of nearest median within 1 %, from the highest order down (its poles are the most
// accurate); a group's score is the number of orders at which it holds a stable pole. Sorted
// by score, then size.
std::vector<Cluster> clusters_of(const std::vector<StabilisationPoint>& points, bool stable_only) {
  std::vector<Cluster> clusters;
  for (std::size_t i = points.size(); i-- > 0;) {
    if (stable_only && !points[i].stable) continue;
    const double f = points[i].natural_hz;
    Cluster* best = nullptr;
    for (Cluster& c : clusters) {
      const double d = std::abs(f - c.center_hz);
      if (d <= kStableFrequency * c.center_hz && (!best || d < std::abs(f - best->center_hz)))
        best = &c;
    }
    if (!best) best = &clusters.emplace_back();
    best->members.push_back(i);
    std::vector<double> fs;
    for (std::size_t m : best->members) fs.push_back(points[m].natural_hz);
    best->center_hz = median(fs);
  }
  for (Cluster& c : clusters) {
    std::vector<int> orders;
    for (std::size_t m : c.members)
      if (points[m].stable) orders.push_back(points[m].order);
    std::sort(orders.begin(), orders.end());
    c.stable_orders = static_cast<int>(std::unique(orders.begin(), orders.end()) - orders.begin());
  }
  std::stable_sort(clusters.begin(), clusters.end(), [](const Cluster& a, const Cluster& b) {
    return a.stable_orders != b.stable_orders ? a.stable_orders > b.stable_orders
                                              : a.members.size() > b.members.size();
  });
  return clusters;
}

// The pole standing for a cluster: median frequency and damping of its stable members (of
// all members when none is stable).
cd representative(const Cluster& c, const std::vector<StabilisationPoint>& points) {
  std::vector<double> f, z;
  for (std::size_t m : c.members) {
    if (c.stable_orders > 0 && !points[m].stable) continue;
    f.push_back(points[m].natural_hz);
    z.push_back(points[m].damping_ratio);
  }
  const double wn = kTwoPi * median(f), zeta = median(z);
  return {-zeta * wn, wn * std::sqrt(1.0 - zeta * zeta)};
}

struct Selection {
  std::vector<cd> poles;
  int min_stable_orders = 0;
};

// The diagram's highest order: 4 per mode (2 poles per mode, doubled for the noise), at least
// 24, and below half the band's points (the LSCF unknowns, 2·order + 1, against 2 equations
// per point).
int max_order_for(int modes, int points) {
  return std::min(std::max(4 * modes, 24), std::max(2, points / 2 - 1));
}

// The poles to refine: the groups of stable poles of score >= min_stable_orders (automatic
// choice) or the `modes` best groups, completed from the groups of all poles when the stable
// ones are too few; never two within 1 % in frequency.
Selection select_poles(const std::vector<StabilisationPoint>& points, int modes, int max_order,
                       FrfFit& out) {
  Selection s;
  // 5 orders (N/10 above N = 50); fewer in a band too short for a diagram of 15 orders.
  s.min_stable_orders = std::min(std::max(5, max_order / 10), std::max(1, max_order / 3));
  const auto add = [&](const Cluster& c) {
    const cd pole = representative(c, points);
    for (const cd& q : s.poles)
      if (std::abs(std::abs(pole) - std::abs(q)) <= kStableFrequency * std::abs(q)) return;
    s.poles.push_back(pole);
  };
  const auto room = [&] { return static_cast<int>(s.poles.size()) < modes; };
  for (const Cluster& c : clusters_of(points, true))
    if (modes > 0 ? room() : c.stable_orders >= s.min_stable_orders) add(c);
  if (modes > 0)
    for (const Cluster& c : clusters_of(points, false))
      if (room()) add(c);
  if (modes > 0 && room())
    out.warnings.push_back("the diagram holds " + std::to_string(s.poles.size()) +
                           " distinct physical pole(s): " + std::to_string(s.poles.size()) +
                           " of the " + std::to_string(modes) + " modes asked are fitted");
  return s;
}

// ---- refinement and pruning -----------------------------------------------------------------

double phase_deg(cd residue) {  // relative to the real-mode residue −i·|A|
  return std::arg(residue * cd(0.0, 1.0)) * 180.0 / std::numbers::pi;
}

std::string mode_text(cd pole) { return fixed(std::abs(pole) / kTwoPi, 1) + " Hz"; }

// RMS relative error of the model without pole r, the others' residues fitted again.
double rms_without(const BandData& band, const PoleResidueModel& model, std::size_t r) {
  PoleResidueModel m = model;
  m.poles.erase(m.poles.begin() + static_cast<std::ptrdiff_t>(r));
  fit_detail::fit_residues(band, m);
  return fit_detail::rms_relative_error(band, m);
}

// Of two poles closer than 1 % in frequency or a quarter of the sum of their damping ratios
// (half their mean half-power width: both stand for one mode), the one the fit misses less;
// -1 when there are none.
int duplicate_pole(const BandData& band, const PoleResidueModel& model) {
  const auto zeta = [](cd pole) { return -pole.real() / std::abs(pole); };
  for (std::size_t r = 0; r < model.poles.size(); ++r) {
    for (std::size_t q = r + 1; q < model.poles.size(); ++q) {
      const double a = std::abs(model.poles[r]), b = std::abs(model.poles[q]);
      const double gap =
          std::max(kStableFrequency, 0.25 * (zeta(model.poles[r]) + zeta(model.poles[q])));
      if (std::abs(a - b) > gap * std::min(a, b)) continue;
      return static_cast<int>(rms_without(band, model, r) < rms_without(band, model, q) ? r : q);
    }
  }
  return -1;
}

// The pole to drop from a refined model, with the reason, or -1: a pole that left the band or
// the physical range, a negative stiffness (the residue more than 90° from the real mode's),
// one of two poles on one mode, or (automatic choice only) the least significant one if its
// removal raises the RMS error by less than kSignificance (kSignificancePoorFit). `spurious`
// tells the last two (a pole that stands for no mode) from the others (a mode lost).
int pole_to_drop(const BandData& band, const PoleResidueModel& model, bool automatic,
                 std::string& why, bool& spurious) {
  spurious = false;
  for (std::size_t r = 0; r < model.poles.size(); ++r) {
    const double wn = std::abs(model.poles[r]), zeta = -model.poles[r].real() / wn;
    const double a = std::abs(model.residues[r]);
    if (wn < band.lo_rad_s || wn > band.hi_rad_s)
      why = "left the band during the refinement: dropped";
    else if (!(zeta < 0.5))
      why = "damping ratio " + fixed(zeta, 3) + " after the refinement (at most 0.5): dropped";
    else if (!(a > 0.0) || !std::isfinite(a))
      why = "no finite residue: dropped";
    else if (const double phase = phase_deg(model.residues[r]); std::abs(phase) > 90.0)
      why = "negative stiffness (residue " + fixed(phase, 0) + "° from a real mode's): dropped";
    else
      continue;
    return static_cast<int>(r);
  }
  if (const int r = duplicate_pole(band, model); r >= 0) {
    why = "a second pole on the same mode: dropped";
    spurious = true;
    return r;
  }
  if (!automatic || model.poles.empty()) return -1;
  const double rms = fit_detail::rms_relative_error(band, model);
  int worst = -1;
  double worst_ratio = rms <= kPoorFit ? kSignificance : kSignificancePoorFit;
  for (std::size_t r = 0; r < model.poles.size(); ++r) {
    const double ratio = rms_without(band, model, r) / rms;
    if (ratio < worst_ratio) {
      worst_ratio = ratio;
      worst = static_cast<int>(r);
    }
  }
  if (worst >= 0)
    why = "removing it raises the RMS error by " + fixed(100.0 * (worst_ratio - 1.0), 1) +
          " % only (noise): dropped";
  spurious = worst >= 0;
  return worst;
}

// Refines all parameters, then drops the poles pole_to_drop names one at a time, refining
// again after each.
fit_detail::RefineStats refine_and_prune(const BandData& band, PoleResidueModel& model,
                                         bool automatic, FrfFit& out) {
  fit_detail::fit_residues(band, model);
  fit_detail::RefineStats stats = fit_detail::refine(band, model);
  std::string why;
  bool spurious = false;
  for (int r; (r = pole_to_drop(band, model, automatic, why, spurious)) >= 0;) {
    // Dropping a pole that stands for no mode is the automatic choice's work (a note); a mode
    // lost (out of the band, overdamped, negative stiffness) or asked for is a warning.
    (automatic && spurious ? out.notes : out.warnings)
        .push_back("pole at " + mode_text(model.poles[r]) + ": " + why);
    model.poles.erase(model.poles.begin() + r);
    fit_detail::fit_residues(band, model);
    stats = fit_detail::refine(band, model);
  }
  if (!automatic) {  // the modes asked are kept; say which ones the data does not need
    const double rms = fit_detail::rms_relative_error(band, model);
    for (std::size_t r = 0; r < model.poles.size(); ++r) {
      const double ratio = rms_without(band, model, r) / rms;
      if (ratio < kSignificance)
        out.warnings.push_back("mode at " + mode_text(model.poles[r]) +
                               ": removing it raises the RMS error by " +
                               fixed(100.0 * (ratio - 1.0), 1) + " % only: possibly noise");
    }
  }
  return stats;
}

using fit_detail::ResidualKind;
using fit_detail::ResidualTerm;

// The residual terms of the model (docs §1). The caller asks for the lower ones only when
// the band starts above 0 Hz: there is no mode below it otherwise, and −1/ω² has no value at 0.
std::vector<ResidualTerm> residual_terms(bool lower, bool upper) {
  std::vector<ResidualTerm> terms;
  if (lower) terms.insert(terms.end(), {{ResidualKind::kLower}, {ResidualKind::kLowerDamping}});
  if (upper)
    terms.insert(
        terms.end(),
        {{ResidualKind::kUpper}, {ResidualKind::kUpperDamping}, {ResidualKind::kUpperMass}});
  return terms;
}

double& coefficient(FrfResiduals& q, ResidualKind kind) {
  switch (kind) {
    case ResidualKind::kLower:
      return q.l2_per_kg;
    case ResidualKind::kLowerDamping:
      return q.l3_per_kg_s;
    case ResidualKind::kUpper:
      return q.u0_m_per_n;
    case ResidualKind::kUpperDamping:
      return q.u1_m_s_per_n;
    case ResidualKind::kUpperMass:
      break;
  }
  return q.u2_m_s2_per_n;
}

FrfResiduals reported(const std::vector<ResidualTerm>& terms) {
  FrfResiduals q;
  for (const ResidualTerm& t : terms) {
    const bool lower = t.kind == ResidualKind::kLower || t.kind == ResidualKind::kLowerDamping;
    (lower ? q.lower_used : q.upper_used) = true;
    coefficient(q, t.kind) = t.value;
  }
  return q;
}

FittedMode fitted_mode(const BandData& band, cd pole, cd residue) {
  FittedMode m;
  m.pole = pole;
  m.residue = residue;
  m.natural_rad_s = std::abs(pole);
  m.natural_hz = m.natural_rad_s / kTwoPi;
  m.damping_ratio = -pole.real() / m.natural_rad_s;
  // A = −i·ωn²/(2·k·ωd) for a real mode; from |A| otherwise (docs §1).
  m.stiffness_n_per_m = m.natural_rad_s * m.natural_rad_s / (2.0 * pole.imag() * std::abs(residue));
  m.residue_phase_deg = phase_deg(residue);
  double sum = 0.0;
  for (std::size_t k = 0; k < band.size(); ++k)
    sum += std::norm(band.w[k] * fit_detail::mode_term(pole, residue, band.omega[k]));
  m.contribution = std::sqrt(sum / static_cast<double>(band.size()));
  return m;
}

// The RMS relative error of `model` (the modes without the residual terms) against the table,
// weighted as the fit's (§10).
double model_error(const BandData& band, const ModalModel& model, Direction direction) {
  double sum = 0.0;
  for (std::size_t k = 0; k < band.size(); ++k)
    sum += std::norm(band.w[k] * (frf(model, direction, band.omega[k]) - band.g[k]));
  return std::sqrt(sum / static_cast<double>(band.size()));
}

// Warnings on the result: no mode, poor fit, no convergence, a mode at the band's edge, modes
// that alone miss the table; a note on a complex residue.
void review(FrfFit& out) {
  if (out.modes.empty())
    out.warnings.push_back("no mode found: the band holds no stable physical pole");
  if (!(out.rms_relative_error <= kPoorFit))
    out.warnings.push_back("poor fit: RMS relative error " +
                           fixed(100.0 * out.rms_relative_error, 1) + " % over the band");
  if (!out.converged)
    out.warnings.push_back("the refinement stopped after " + std::to_string(out.iterations) +
                           " iterations before converging");
  for (const FittedMode& m : out.modes) {
    const std::string at = "mode at " + fixed(m.natural_hz, 1) + " Hz: ";
    const double f1 = m.natural_hz * (1.0 - m.damping_ratio);
    const double f2 = m.natural_hz * (1.0 + m.damping_ratio);
    if ((out.lo_hz > 0.0 && f1 < out.lo_hz) || f2 > out.hi_hz)
      out.warnings.push_back(at + "its half-power band " + fixed(f1, 1) + "…" + fixed(f2, 1) +
                             " Hz reaches past the band's edge: its parameters are uncertain");
    if (std::abs(m.residue_phase_deg) > kPhaseNoteDeg)
      out.notes.push_back(at + "complex residue (" + fixed(m.residue_phase_deg, 0) +
                          "° from a real mode's): kept as a non-proportionally damped mode");
  }
  if (!out.modes.empty() && out.model_rms_relative_error > kModelWarning &&
      out.rms_relative_error <= kPoorFit)
    out.warnings.push_back(
        "the modes alone reproduce the table to " + fixed(100.0 * out.model_rms_relative_error, 1) +
        " % RMS (the fit with its residual terms to " + fixed(100.0 * out.rms_relative_error, 1) +
        " %): modes outside the band carry the rest, and the time-domain methods (full "
        "discretization, simulation) do not see them");
}

}  // namespace

FrfFit fit_modes(const MeasuredFrf& frf, Direction direction, const FrfFitOptions& options) {
  FrfFit out;
  out.direction = direction;
  out.automatic = options.modes == 0;
  const BandData band = band_of(frf, options, out);
  const int target = out.automatic ? std::min(options.max_modes, out.points / 4) : options.modes;
  const int max_order = max_order_for(target, out.points);
  out.stabilisation = diagram(fit_detail::lscf_poles(band, max_order));
  Selection sel = select_poles(out.stabilisation, out.automatic ? 0 : target, max_order, out);
  if (static_cast<int>(sel.poles.size()) > target) sel.poles.resize(target);

  PoleResidueModel model;
  model.poles = sel.poles;
  model.residuals = residual_terms(options.residuals && out.lo_hz > 0.0, options.residuals);
  const fit_detail::RefineStats stats = refine_and_prune(band, model, out.automatic, out);
  out.iterations = stats.iterations;
  out.converged = stats.converged;
  out.residuals = reported(model.residuals);
  out.rms_relative_error = fit_detail::rms_relative_error(band, model);
  for (std::size_t r = 0; r < model.poles.size(); ++r)
    out.modes.push_back(fitted_mode(band, model.poles[r], model.residues[r]));
  std::sort(out.modes.begin(), out.modes.end(),
            [](const FittedMode& a, const FittedMode& b) { return a.natural_hz < b.natural_hz; });
  for (const FittedMode& m : out.modes)
    out.model.modes.push_back(Mode{direction, m.natural_rad_s, m.damping_ratio,
                                   m.stiffness_n_per_m, m.residue_phase_deg * kTwoPi / 360.0});
  out.model_rms_relative_error = model_error(band, out.model, direction);
  review(out);
  return out;
}

MeasuredFrf fitted_frf(const FrfFit& fit, const std::vector<double>& frequency_hz) {
  Validator v;
  for (std::size_t i = 0; i < frequency_hz.size(); ++i) {
    const double f = frequency_hz[i];
    const std::string at = "frequency_hz[" + std::to_string(i) + "]";
    v.require(f >= 0.0, at, f, "Hz", "must be at least 0");
    if (i > 0 && std::isfinite(f))
      v.require(
          f > frequency_hz[i - 1], at, f, "Hz",
          "must be greater than the one before (" + format_value(frequency_hz[i - 1]) + " Hz)");
  }
  v.throw_if_any("fitted_frf");
  MeasuredFrf out;
  out.frequency_hz = frequency_hz;
  PoleResidueModel model;
  for (const FittedMode& m : fit.modes) {
    model.poles.push_back(m.pole);
    model.residues.push_back(m.residue);
  }
  model.residuals = residual_terms(fit.residuals.lower_used, fit.residuals.upper_used);
  FrfResiduals q = fit.residuals;
  for (ResidualTerm& t : model.residuals) t.value = coefficient(q, t.kind);
  for (double f : frequency_hz) {
    const bool in_band = f >= fit.lo_hz && f <= fit.hi_hz && f > 0.0;
    out.receptance_m_per_n.push_back(fit_detail::evaluate(model, kTwoPi * f, in_band));
  }
  return out;
}

}  // namespace cutdyn
