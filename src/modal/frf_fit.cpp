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
// A split of a mode into two (§3.1) is kept when the weighted squared error falls by this many
// times its per-number variance (χ² with 4 degrees of freedom: 100 is far beyond chance), or
// by kSignificance in RMS; between kSplitChi2Doubt and kSplitChi2 it is a doubt, said.
constexpr double kSplitChi2 = 100.0;
constexpr double kSplitChi2Doubt = 30.0;
// Levenberg–Marquardt iterations of a trial model (a split, an outside pole): it starts near
// the fit and is kept only if it improves it clearly, which a few iterations show.
constexpr int kTrialIterations = 20;
// An RMS relative error below this is a table fitted to rounding (no noise to speak of).
constexpr double kExactFit = 1e-7;
// Coherence (§4.3): a point's relative noise is taken as sqrt((1 − γ²)/γ²), with γ² held
// within [kLowCoherence, kHighCoherence] (γ² = 1 would give a weight without bound, γ² = 0
// a zero one); a table whose γ² is above kHighCoherence everywhere (one average, or a
// synthetic table) says nothing about its noise, which is then estimated from the data.
constexpr double kHighCoherence = 0.9999;
constexpr double kLowCoherence = 0.01;

std::string fixed(double value, int digits) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*f", digits, value);
  return buf;
}

// ---- input ------------------------------------------------------------------------------

// The weights of the table's coherence (§4.3): each point's noise relative to |G| is
// sqrt((1 − γ²)/γ²) [Bendat2010, ch. 9: the random error of the H1 estimate is that over
// sqrt(2·averages)], so w = 1/(|G|·sqrt((1 − γ²)/γ²)) in the first pass (the model's |G| in
// the second, coherence_reweighted); the number of averages only scales every weight alike
// and is left to the noise the residuals show. Eq. (4.4) of docs/models/modal-fitting.md with
// the table's |G_k|.
void weigh_by_coherence(const std::vector<double>& gamma2, BandData& band, FrfFit& out) {
  const double lowest = *std::min_element(gamma2.begin(), gamma2.end());
  if (lowest > kHighCoherence) {
    out.notes.push_back("the coherence is above " + format_value(kHighCoherence) +
                        " at every point (one average?): it tells nothing of the noise, which "
                        "is estimated from the table instead");
    return;
  }
  std::size_t poor = 0;
  for (std::size_t k = 0; k < band.size(); ++k) {
    const double c = std::clamp(gamma2[k], kLowCoherence, kHighCoherence);
    if (gamma2[k] < 0.5) ++poor;
    band.coherence_noise.push_back(std::sqrt((1.0 - c) / c));
    band.w[k] = band.w_rel[k] / band.coherence_noise[k];
  }
  out.coherence_weighted = true;
  out.notes.push_back("weighted by the table's coherence (lowest γ² " + fixed(lowest, 3) + "; " +
                      std::to_string(poor) + " of " + std::to_string(band.size()) +
                      " points below 0.5)");
}

BandData band_of(const MeasuredFrf& frf, const FrfFitOptions& options, FrfFit& out) {
  Validator v;
  for (const std::string& p : frf.validate()) v.add("frf." + p);
  v.throw_if_any("fit");
  const double lo = options.lo_hz.value_or(frf.min_hz());
  const double hi = options.hi_hz.value_or(frf.max_hz());
  const std::string band_text = "band " + format_value(lo) + "…" + format_value(hi) + " Hz";
  if (options.lo_hz) v.require(lo >= 0.0, "band.lo_hz", lo, "Hz", "must be at least 0");
  if (options.hi_hz) v.require(hi > lo, "band.hi_hz", hi, "Hz", "must be above band.lo_hz");
  v.require(options.modes >= 0 && options.modes <= kMaxFitModes, "modes", options.modes, "",
            "must be 0 (automatic) to " + std::to_string(kMaxFitModes));
  v.require(options.max_modes >= 1 && options.max_modes <= kMaxFitModes, "max_modes",
            options.max_modes, "", "must be 1 to " + std::to_string(kMaxFitModes));
  v.throw_if_any("fit");
  BandData band;
  std::vector<double> gamma2;  // the coherence in the band, where the table has one
  double peak = 0.0;
  for (std::size_t i = 0; i < frf.frequency_hz.size(); ++i) {
    const double f = frf.frequency_hz[i];
    if (f < lo || f > hi) continue;
    band.omega.push_back(kTwoPi * f);
    band.g.push_back(frf.receptance_m_per_n[i]);
    if (!frf.coherence.empty()) gamma2.push_back(frf.coherence[i]);
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
  // The relative weights of eq. FIT-9 (docs/models/modal-fitting.md).
  const double floor = 1e-6 * peak;  // keeps a zero of the table from an infinite weight
  for (const cd& g : band.g) band.w.push_back(1.0 / std::max(std::abs(g), floor));
  band.w_rel = band.w;
  if (!gamma2.empty()) weigh_by_coherence(gamma2, band, out);
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
  // λ = −ζ·ωn + i·ωd, eq. FIT-2 (docs/models/modal-fitting.md).
  const double wn = kTwoPi * median(f), zeta = median(z);
  return {-zeta * wn, wn * std::sqrt(1.0 - zeta * zeta)};
}

struct Selection {
  std::vector<cd> poles;
  int min_stable_orders = 0;
};

// The diagram's highest order: 4 per mode (2 poles per mode, doubled for the noise), at least
// 24, and below half the band's points (the LSCF unknowns, 2·order + 1, against 2 equations
// per point): eq. FIT-8 (docs/models/modal-fitting.md).
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
  return fit_detail::rms_fit_error(band, m);
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
  const double rms = fit_detail::rms_fit_error(band, model);
  int worst = -1;
  double worst_ratio = fit_detail::rms_relative_error(band, model) <= kPoorFit
                           ? kSignificance
                           : kSignificancePoorFit;
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
    const double rms = fit_detail::rms_fit_error(band, model);
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
  // A = −i·ωn²/(2·k·ωd) for a real mode; from |A| otherwise (docs §1): eq. FIT-5
  // (docs/models/modal-fitting.md).
  m.stiffness_n_per_m = m.natural_rad_s * m.natural_rad_s / (2.0 * pole.imag() * std::abs(residue));
  m.residue_phase_deg = phase_deg(residue);
  double sum = 0.0;
  for (std::size_t k = 0; k < band.size(); ++k)
    sum += std::norm(band.w_rel[k] * fit_detail::mode_term(pole, residue, band.omega[k]));
  m.contribution = std::sqrt(sum / static_cast<double>(band.size()));
  return m;
}

// The covariance of (fn, ζ, k) from that of (σ, ωd, Re A, Im A) (§4.2): ωn = sqrt(σ² + ωd²),
// ζ = σ/ωn, k = ωn²/(2·ωd·|A|), to first order (the Jacobian of that map: eq. FIT-11 of
// docs/models/modal-fitting.md).
void set_uncertainty(FittedMode& m, const Eigen::Matrix4d& c) {
  const double sigma = -m.pole.real(), wd = m.pole.imag(), wn = std::abs(m.pole);
  const double a2 = std::norm(m.residue), a = std::sqrt(a2), k = m.stiffness_n_per_m;
  Eigen::Matrix<double, 3, 4> g;
  g << sigma / (wn * kTwoPi), wd / (wn * kTwoPi), 0.0, 0.0,                       // fn
      wd * wd / (wn * wn * wn), -sigma * wd / (wn * wn * wn), 0.0, 0.0,          // ζ
      sigma / (wd * a), (wd * wd - sigma * sigma) / (2.0 * wd * wd * a),         // k
      -k * m.residue.real() / a2, -k * m.residue.imag() / a2;
  const Eigen::Matrix3d q = g * c * g.transpose();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m.covariance[i][j] = std::isfinite(q(i, j)) ? q(i, j) : 0.0;
  m.natural_hz_sigma = std::sqrt(std::max(m.covariance[0][0], 0.0));
  m.damping_ratio_sigma = std::sqrt(std::max(m.covariance[1][1], 0.0));
  m.stiffness_sigma_n_per_m = std::sqrt(std::max(m.covariance[2][2], 0.0));
}

// The RMS relative error of `model` (the modes without the residual terms) against the table,
// weighted as the fit's (§10).
double model_error(const BandData& band, const ModalModel& model, Direction direction) {
  double sum = 0.0;
  for (std::size_t k = 0; k < band.size(); ++k)
    sum += std::norm(band.w_rel[k] * (frf(model, direction, band.omega[k]) - band.g[k]));
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
      out.model_rms_relative_error > 1.25 * out.rms_relative_error &&
      out.rms_relative_error <= kPoorFit)
    out.warnings.push_back(
        "the modes alone reproduce the table to " + fixed(100.0 * out.model_rms_relative_error, 1) +
        " % RMS (the fit with its residual terms to " + fixed(100.0 * out.rms_relative_error, 1) +
        " %): modes outside the band carry the rest, and the time-domain methods (full "
        "discretization, simulation) do not see them");
}

}  // namespace

namespace {

// E y = c1·m + c0 fitted to squared residuals y of points of squared magnitude m by
// iteratively reweighted least squares (the variance of a squared residual grows as the square
// of its mean), both coefficients >= 0 (§4.1): the fit of eq. (4.1) of
// docs/models/modal-fitting.md.
std::pair<double, double> noise_coefficients(const std::vector<double>& m,
                                             const std::vector<double>& y) {
  const std::size_t n = m.size();
  std::vector<double> ratio;
  for (std::size_t k = 0; k < n; ++k)
    if (m[k] > 0.0) ratio.push_back(y[k] / m[k]);
  double c1 = ratio.empty() ? 0.0 : median(ratio);
  double c0 = 1e-3 * c1 * median(m) + 1e-300;
  for (int iteration = 0; iteration < 8; ++iteration) {
    double s11 = 0, s10 = 0, s00 = 0, t1 = 0, t0 = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const double v = c1 * m[k] + c0;
      if (!(v > 0.0)) continue;
      const double u = 1.0 / (v * v);
      s11 += u * m[k] * m[k];
      s10 += u * m[k];
      s00 += u;
      t1 += u * m[k] * y[k];
      t0 += u * y[k];
    }
    const double det = s11 * s00 - s10 * s10;
    double a = det > 0.0 ? (t1 * s00 - t0 * s10) / det : 0.0;
    double b = det > 0.0 ? (s11 * t0 - s10 * t1) / det : 0.0;
    if (a < 0.0) {  // one coefficient at its bound 0: the other alone
      a = 0.0;
      b = s00 > 0.0 ? t0 / s00 : 0.0;
    } else if (b < 0.0) {
      b = 0.0;
      a = s11 > 0.0 ? t1 / s11 : 0.0;
    }
    if (!(a + b > 0.0) || !std::isfinite(a) || !std::isfinite(b)) break;
    c1 = a;
    c0 = std::max(b, 1e-300);
  }
  return {c1, c0};
}

// The noise of the table before any model (§4.1): each interior point against the straight line
// through its two neighbours, G_k − a·G_(k−1) − b·G_(k+1), a + b = 1 — a difference whose noise
// has 1 + a² + b² times the point's variance and whose smooth part is small wherever the table
// is sampled finely against its peaks' widths [Gasser1986]. The same two coefficients fitted to
// those differences. d_k of eq. FIT-10, then eq. (4.1) (docs/models/modal-fitting.md).
FrfNoise noise_from_differences(const BandData& band) {
  std::vector<double> m, y;
  for (std::size_t k = 1; k + 1 < band.size(); ++k) {
    const double a = (band.omega[k + 1] - band.omega[k]) / (band.omega[k + 1] - band.omega[k - 1]);
    const double b = 1.0 - a;
    const cd d = band.g[k] - a * band.g[k - 1] - b * band.g[k + 1];
    m.push_back(std::norm(band.g[k]));
    y.push_back(std::norm(d) / (1.0 + a * a + b * b));
  }
  FrfNoise noise;
  if (m.size() < 8) return noise;
  const auto [c1, c0] = noise_coefficients(m, y);
  noise.proportional = std::sqrt(c1 / 2.0);
  noise.floor_m_per_n = c0 > 1e-300 ? std::sqrt(c0 / 2.0) : 0.0;
  return noise;
}

// The fall of the weighted squared error from a model of RMS error `before` to one of RMS error
// `after` fitted to `band` with `parameters` parameters, in units of its per-number variance:
// a χ² with as many degrees of freedom as parameters added, on noise alone (§3.1).
double chi2_fall(const BandData& band, double before, double after, std::size_t parameters) {
  const double numbers = 2.0 * static_cast<double>(band.size());
  const double dof = std::max(numbers - static_cast<double>(parameters), 1.0);
  return after > 0.0 ? dof * (before * before - after * after) / (after * after) : 0.0;
}

std::size_t parameters_of(const PoleResidueModel& model) {
  return 4 * model.poles.size() + model.residuals.size();
}

// Modes the diagram missed (§3.2): where the weighted residual, averaged over a run of points,
// stands far above its median (a resonance left in the residual, not noise), a pole is tried
// at that frequency, refined with all the others, and kept on the test of a split (the RMS error
// down by kSignificance or the weighted squared error by kSplitChi2 times its per-number
// variance) when every pole stays physical, the in-band ones in the band and on modes of their
// own. A place whose pole is not kept is not tried again (three such places at most).
void add_missed_modes(const BandData& band, PoleResidueModel& model, int max_modes, FrfFit& out) {
  constexpr std::size_t kHalfRun = 5;   // points each side of the run
  constexpr double kStructured = 10.0;  // the run's mean of r (noise alone: 1 ± 0.3)
  constexpr double kStartDamping = 0.02;
  const std::size_t n = band.size();
  if (n < 4 * kHalfRun) return;
  std::vector<double> tried;  // places tried without a pole kept, rad/s
  const FrfNoise noise = noise_from_differences(band);
  if (!(noise.proportional > 0.0 || noise.floor_m_per_n > 0.0)) return;
  while (fit_detail::rms_relative_error(band, model) >= kExactFit &&  // not fitted to rounding
         static_cast<int>(model.poles.size()) < max_modes && tried.size() < 3) {
    // r_k: the squared residual over the variance the table's noise gives the point (§3.2).
    std::vector<double> r(n, 0.0);
    for (std::size_t k = 0; k < n; ++k) {
      const double variance =
          2.0 * (std::norm(noise.proportional * band.g[k]) + std::norm(noise.floor_m_per_n));
      if (variance > 0.0)
        r[k] = std::norm(fit_detail::evaluate(model, band.omega[k]) - band.g[k]) / variance;
    }
    std::size_t at = 0;
    double largest = 0.0;
    for (std::size_t k = kHalfRun; k + kHalfRun < n; ++k) {
      if (std::any_of(tried.begin(), tried.end(),
                      [&](double w) { return std::abs(band.omega[k] - w) < 0.03 * w; }))
        continue;
      double run = 0.0;
      for (std::size_t j = k - kHalfRun; j <= k + kHalfRun; ++j) run += r[j];
      run /= static_cast<double>(2 * kHalfRun + 1);
      if (run > largest) largest = run, at = k;
    }
    if (!(largest > kStructured)) return;
    const double wn = band.omega[at];
    const auto inside =
        static_cast<std::size_t>(std::count_if(model.poles.begin(), model.poles.end(), [&](cd p) {
          return std::abs(p) >= band.lo_rad_s && std::abs(p) <= band.hi_rad_s;
        }));
    PoleResidueModel trial = model;
    trial.poles.insert(
        trial.poles.begin() + static_cast<std::ptrdiff_t>(inside),
        cd(-kStartDamping * wn, wn * std::sqrt(1.0 - kStartDamping * kStartDamping)));
    fit_detail::fit_residues(band, trial);
    fit_detail::refine(band, trial, kTrialIterations);
    const double before = fit_detail::rms_fit_error(band, model);
    const double after = fit_detail::rms_fit_error(band, trial);
    bool keep = after > 0.0 && (before >= kSignificance * after ||
                                chi2_fall(band, before, after, parameters_of(trial)) > kSplitChi2);
    for (std::size_t q = 0; q < trial.poles.size() && keep; ++q) {
      const double w = std::abs(trial.poles[q]), z = -trial.poles[q].real() / w;
      keep = (q > inside || (w >= band.lo_rad_s && w <= band.hi_rad_s)) && z < 0.5 &&
             std::abs(phase_deg(trial.residues[q])) <= 90.0;
    }
    if (keep) {
      PoleResidueModel in_band = trial;
      in_band.poles.resize(inside + 1);
      in_band.residues.resize(inside + 1);
      keep = duplicate_pole(band, in_band) < 0;
    }
    if (!keep) {
      tried.push_back(wn);
      continue;
    }
    out.notes.push_back(
        "a mode near " + mode_text(trial.poles[inside]) +
        " that the diagram missed: added (RMS error " +
        fixed(100.0 * fit_detail::rms_relative_error(band, model), 2) + " % without it, " +
        fixed(100.0 * fit_detail::rms_relative_error(band, trial), 2) + " % with it)");
    model = std::move(trial);
  }
}

// One fit over `band` with its weights: the diagram, the choice of poles, the refinement and
// the pruning (§2–§4). `out` holds what the band's reading said; the model is returned in
// `model`.
FrfFit fit_pass(const BandData& band, const FrfFitOptions& options, FrfFit out,
                PoleResidueModel& model) {
  const int target = out.automatic ? std::min(options.max_modes, out.points / 4) : options.modes;
  const int max_order = max_order_for(target, out.points);
  out.stabilisation = diagram(fit_detail::lscf_poles(band, max_order));
  Selection sel = select_poles(out.stabilisation, out.automatic ? 0 : target, max_order, out);
  if (static_cast<int>(sel.poles.size()) > target) sel.poles.resize(target);
  model = PoleResidueModel{};
  model.poles = sel.poles;
  model.residuals = residual_terms(options.residuals && out.lo_hz > 0.0, options.residuals);
  fit_detail::RefineStats stats = refine_and_prune(band, model, out.automatic, out);
  if (out.automatic) {
    const std::size_t before = model.poles.size();
    add_missed_modes(band, model, target, out);
    if (model.poles.size() != before) stats = refine_and_prune(band, model, true, out);
  }
  out.iterations = stats.iterations;
  out.converged = stats.converged;
  return out;
}

// The fit again on the band's new weights (§4.1, §4.3). The model before, refined on those
// weights, is kept instead when it fits them better: a new diagram can choose worse poles
// (a wide mode missed, two merged) than the pass before found.
FrfFit fit_again(const BandData& band, const FrfFitOptions& options, const FrfFit& base,
                 FrfFit before, PoleResidueModel& model) {
  PoleResidueModel again;
  FrfFit out = fit_pass(band, options, base, again);
  PoleResidueModel refined = model;
  const fit_detail::RefineStats stats = refine_and_prune(band, refined, base.automatic, before);
  if (!(fit_detail::rms_fit_error(band, refined) < fit_detail::rms_fit_error(band, again)) ||
      (!base.automatic && static_cast<int>(refined.poles.size()) != options.modes)) {
    model = std::move(again);
    return out;
  }
  before.iterations = stats.iterations;
  before.converged = stats.converged;
  model = std::move(refined);
  return before;
}

// The noise of the table about `model` (§4.1): E|G_model − G|² = c1·|G_model|² + c0, scaled by
// the degrees of freedom the fit took. Per part (real or imaginary): proportional sqrt(c1/2),
// floor sqrt(c0/2). Eq. (4.1) of docs/models/modal-fitting.md.
FrfNoise estimate_noise(const BandData& band, const PoleResidueModel& model) {
  const std::size_t n = band.size();
  std::vector<double> m(n), y(n);
  for (std::size_t k = 0; k < n; ++k) {
    const cd model_g = fit_detail::evaluate(model, band.omega[k]);
    m[k] = std::norm(model_g);
    y[k] = std::norm(model_g - band.g[k]);
  }
  const auto [c1, c0] = noise_coefficients(m, y);
  const double parameters = 4.0 * static_cast<double>(model.poles.size()) +
                            static_cast<double>(model.residuals.size());
  const double dof = 2.0 * static_cast<double>(n);
  const double scale = dof > parameters ? dof / (dof - parameters) : 1.0;
  FrfNoise noise;
  noise.proportional = std::sqrt(scale * c1 / 2.0);
  noise.floor_m_per_n = c0 > 1e-300 ? std::sqrt(scale * c0 / 2.0) : 0.0;
  return noise;
}

// The magnitude below which the floor's noise exceeds the proportional noise.
double floor_magnitude(const FrfNoise& noise) {
  return noise.floor_m_per_n / std::max(noise.proportional, 1e-4);
}

// The band reweighted for `noise` (§4.1): w = 1/sqrt(|G_model|² + g0²), g0 = floor_magnitude,
// and the relative error measured against max(|G|, g0). Without a model (nullptr), the
// table's own |G| stands for |G_model|. Eq. (4.2) of docs/models/modal-fitting.md.
BandData reweighted(BandData band, const PoleResidueModel* model, const FrfNoise& noise) {
  const double g0 = floor_magnitude(noise);
  double peak = 0.0;
  for (const cd& g : band.g) peak = std::max(peak, std::abs(g));
  for (std::size_t k = 0; k < band.size(); ++k) {
    const double model_g =
        std::abs(model ? fit_detail::evaluate(*model, band.omega[k]) : band.g[k]);
    band.w[k] = 1.0 / std::max(std::hypot(model_g, g0), 1e-6 * peak);
    band.w_rel[k] = 1.0 / std::max({std::abs(band.g[k]), g0, 1e-6 * peak});
  }
  return band;
}

// The band reweighted by its coherence about `model` (§4.3): w = 1/(|G_model|·sqrt((1 − γ²)/γ²)),
// the magnitude from the model rather than the noisy table (at a point the noise dominates,
// 1/|G_k| would weigh by the noise itself). Eq. (4.4) of docs/models/modal-fitting.md.
BandData coherence_reweighted(BandData band, const PoleResidueModel& model) {
  double peak = 0.0;
  for (const cd& g : band.g) peak = std::max(peak, std::abs(g));
  for (std::size_t k = 0; k < band.size(); ++k) {
    const double model_g = std::abs(fit_detail::evaluate(model, band.omega[k]));
    band.w[k] = 1.0 / (std::max(model_g, 1e-6 * peak) * band.coherence_noise[k]);
    // The relative error measured against the noise's scale where that exceeds |G| (γ² < 0.5),
    // as against the floor in §4.1.
    band.w_rel[k] =
        1.0 / std::max({std::abs(band.g[k]), model_g * band.coherence_noise[k], 1e-6 * peak});
  }
  return band;
}

// Whether the floor matters: at 2 % of the band's points or more the model is below it.
bool floor_matters(const BandData& band, const PoleResidueModel& model, const FrfNoise& noise) {
  const double g0 = floor_magnitude(noise);
  std::size_t below = 0;
  for (std::size_t k = 0; k < band.size(); ++k)
    if (std::abs(fit_detail::evaluate(model, band.omega[k])) < g0) ++below;
  return static_cast<double>(below) >= 0.02 * static_cast<double>(band.size());
}

// The band weighted for a floor the table shows before any model (§4.1): the weights of
// `reweighted` on the table's own magnitude, when the floor of noise_from_differences exceeds
// the proportional noise at 2 % of the points or more. Returns whether it did.
bool weigh_floor_first(BandData& band) {
  const FrfNoise noise = noise_from_differences(band);
  const double g0 = floor_magnitude(noise);
  std::size_t below = 0;
  for (const cd& g : band.g) below += std::abs(g) < g0;
  if (!(static_cast<double>(below) >= 0.02 * static_cast<double>(band.size()))) return false;
  band = reweighted(std::move(band), nullptr, noise);
  return true;
}

// The lowest critical depth's scale of a receptance: 1/(−min Re G) over the band (Tlusty's
// a_lim = −1/(2·Kf·Re G), whose minimum over speeds is at the most negative Re G).
double depth_scale(const BandData& band, const PoleResidueModel& model) {
  double lowest = 0.0;
  for (std::size_t k = 0; k < band.size(); ++k)
    lowest = std::min(lowest, fit_detail::evaluate(model, band.omega[k], false).real());
  return lowest < 0.0 ? -1.0 / lowest : 0.0;
}

// A mode just outside the band (§1.1): the residual series cannot absorb it, and it bends the
// modes inside. A pole is tried above the band (1.15·hi) and, for a band starting above 0 Hz,
// below it (0.85·lo), each refined with all the others; it is kept when it fits clearly better
// (below) and the pole stays outside the band with a positive stiffness (appended to
// `model`'s poles).
struct OutsidePole {
  bool above = false;
  double rms_without = 0.0, rms_with = 0.0;  // RMS relative errors when it was tried
};
std::vector<OutsidePole> add_outside_poles(const BandData& band, PoleResidueModel& model) {
  std::vector<OutsidePole> kept;
  for (const double at : {1.15 * band.hi_rad_s, 0.85 * band.lo_rad_s}) {
    if (!(at > 0.0)) continue;
    const bool above = at > band.hi_rad_s;
    PoleResidueModel trial = model;
    trial.poles.push_back(cd(-0.03 * at, at * std::sqrt(1.0 - 0.03 * 0.03)));
    // The explicit pole takes the job of the residual terms of the series on its side that
    // stand for its nearest terms (iω and −ω² above, i/ω³ below); left in, they share it and
    // the pole converges away from the mode (3630 Hz, ζ 0.06 for a mode at 3500 Hz, ζ 0.03).
    std::erase_if(trial.residuals, [&](const ResidualTerm& t) {
      return above ? (t.kind == ResidualKind::kUpperDamping || t.kind == ResidualKind::kUpperMass)
                   : t.kind == ResidualKind::kLowerDamping;
    });
    fit_detail::fit_residues(band, trial);
    {  // a quick look: the pole where it was put, only the residues fitted (linear)
      const double before = fit_detail::rms_fit_error(band, model);
      const double after = fit_detail::rms_fit_error(band, trial);
      if (!(chi2_fall(band, before, after, parameters_of(trial)) > kSplitChi2Doubt)) continue;
    }
    fit_detail::refine(band, trial, kTrialIterations);
    const cd pole = trial.poles.back();
    const double wn = std::abs(pole), zeta = -pole.real() / wn;
    const bool outside = above ? wn > band.hi_rad_s : wn < band.lo_rad_s;
    // Kept when it fits clearly better: the RMS error down by kSignificance, or the weighted
    // squared error down by kSplitChi2 times its per-number variance (the test of a split, for
    // the same 4 parameters more: a mode below a band starting at 300 Hz that the lower
    // residual terms absorb all but 6 % of still bends the lowest mode by 3σ).
    const double without = fit_detail::rms_fit_error(band, model);
    const double with = fit_detail::rms_fit_error(band, trial);
    const double chi2 = chi2_fall(band, without, with, parameters_of(trial));
    if (!(outside && zeta < 0.5 && std::abs(phase_deg(trial.residues.back())) <= 90.0 &&
          (without >= kSignificance * with || chi2 > kSplitChi2)))
      continue;
    kept.push_back({above, fit_detail::rms_relative_error(band, model),
                    fit_detail::rms_relative_error(band, trial)});
    model = std::move(trial);
  }
  return kept;
}

// The warning of each explicit pole kept (§1.1), at the place the whole refinement left it.
void warn_outside_poles(const std::vector<OutsidePole>& kept, FrfFit& out) {
  for (const OutsidePole& p : kept)
    for (const FittedMode& m : out.outside_modes) {
      if (p.above != (m.natural_hz > out.hi_hz)) continue;
      out.warnings.push_back(std::string("a mode ") + (p.above ? "above" : "below") +
                             " the band, near " + fixed(m.natural_hz, 1) +
                             " Hz, bends the modes inside it: modelled by an explicit pole (RMS "
                             "error " +
                             fixed(100.0 * p.rms_without, 2) + " % without it, " +
                             fixed(100.0 * p.rms_with, 2) +
                             " % with it); the modes near that edge are the less certain, and "
                             "the pole is not one of the modes (it lies outside the table's band)");
    }
}

// Two close modes fitted as one (§3.1): each mode in turn is split into two poles ζ·ωn below
// and above it and refined. Kept when every pole stays physical, in the band and of positive stiffness, no
// two stand for one mode, and the RMS error falls by kSignificance; a split that fits that
// much better but is not kept, or one that fits almost as well (3 %), is a warning with both
// errors and the change of the lowest critical depth's scale.
// Whether two poles about the peak of mode r fit the points near it clearly better than one
// (§3.1): on the points within max(4ζ, 3 %) of ωn, the table less the model's other terms,
// fitted by one pole and by two (poles and residues refined); true when the weighted squared
// error falls by more than kSplitChi2Doubt times its per-number variance. A quick look that
// spares the whole band's refinement where there is nothing to split.
bool split_looks_better(const BandData& band, const PoleResidueModel& model, std::size_t r) {
  const cd pole = model.poles[r];
  const double wn = std::abs(pole), zeta = -pole.real() / wn, delta = std::max(zeta, 0.005);
  PoleResidueModel others = model;
  others.poles.erase(others.poles.begin() + static_cast<std::ptrdiff_t>(r));
  others.residues.erase(others.residues.begin() + static_cast<std::ptrdiff_t>(r));
  BandData local;
  for (std::size_t k = 0; k < band.size(); ++k) {
    if (std::abs(band.omega[k] - wn) > std::max(4.0 * zeta, 0.03) * wn) continue;
    local.omega.push_back(band.omega[k]);
    local.g.push_back(band.g[k] - fit_detail::evaluate(others, band.omega[k]));
    local.w.push_back(band.w[k]);
    local.w_rel.push_back(band.w_rel[k]);
  }
  if (local.size() < 16) return false;
  local.lo_rad_s = local.omega.front();
  local.hi_rad_s = local.omega.back();
  PoleResidueModel one, two;
  one.poles = {pole};
  two.poles = {pole * (1.0 - delta), pole * (1.0 + delta)};
  for (PoleResidueModel* m : {&one, &two}) {
    fit_detail::fit_residues(local, *m);
    fit_detail::refine(local, *m, kTrialIterations);
  }
  const double a = fit_detail::rms_fit_error(local, one), b = fit_detail::rms_fit_error(local, two);
  return chi2_fall(local, a, b, parameters_of(two)) > kSplitChi2Doubt;
}

void split_merged_modes(const BandData& band, PoleResidueModel& model, std::size_t inside,
                        FrfFit& out) {
  // A table fitted to rounding has nothing to split.
  if (fit_detail::rms_relative_error(band, model) < kExactFit) return;
  for (std::size_t r = 0; r < inside; ++r) {
    const double rms = fit_detail::rms_fit_error(band, model);
    const cd pole = model.poles[r];
    const double zeta = -pole.real() / std::abs(pole), delta = std::max(zeta, 0.005);
    if (!split_looks_better(band, model, r)) continue;
    PoleResidueModel trial = model;
    trial.poles[r] = pole * (1.0 - delta);
    trial.poles.insert(trial.poles.begin() + static_cast<std::ptrdiff_t>(inside),
                       pole * (1.0 + delta));
    trial.residues.insert(trial.residues.begin() + static_cast<std::ptrdiff_t>(inside), cd{});
    fit_detail::fit_residues(band, trial);
    fit_detail::refine(band, trial, kTrialIterations);
    const double trial_rms = fit_detail::rms_fit_error(band, trial);
    bool valid = true;
    for (std::size_t q : {r, inside}) {
      const double wn = std::abs(trial.poles[q]), z = -trial.poles[q].real() / wn;
      valid = valid && wn >= band.lo_rad_s && wn <= band.hi_rad_s && z < 0.5 &&
              std::abs(phase_deg(trial.residues[q])) <= 90.0 && std::abs(trial.residues[q]) > 0.0;
    }
    // Both poles of the split must stay at this peak (within 3 ζ or 2 % of ωn): a pole that
    // wandered to another peak is that peak's split, looked at in its turn.
    const double reach = std::max(3.0 * zeta, 0.02) * std::abs(pole);
    if (std::abs(std::abs(trial.poles[r]) - std::abs(pole)) > reach ||
        std::abs(std::abs(trial.poles[inside]) - std::abs(pole)) > reach)
      continue;
    // How much better two poles fit: the RMS ratio, and the fall of the weighted squared error
    // in units of its per-number variance (a χ² with 4 degrees of freedom on noise alone).
    const double gain = rms / trial_rms;
    const double chi2 = chi2_fall(band, rms, trial_rms, parameters_of(trial));
    const bool better = gain >= kSignificance || chi2 > kSplitChi2;
    const std::string at = "the peak at " + mode_text(pole);
    const auto both = [&] {
      const double a = depth_scale(band, model), b = depth_scale(band, trial);
      return "RMS error " + fixed(100.0 * fit_detail::rms_relative_error(band, model), 2) +
             " % with one mode, " + fixed(100.0 * fit_detail::rms_relative_error(band, trial), 2) +
             " % with two; the lowest critical depth changes by " +
             fixed(a > 0.0 ? 100.0 * (b / a - 1.0) : 0.0, 1) + " %";
    };
    {
      PoleResidueModel in_band = trial;  // two poles on one mode? (the modes only)
      in_band.poles.resize(inside + 1);
      in_band.residues.resize(inside + 1);
      valid = valid && duplicate_pole(band, in_band) < 0;
    }
    if (valid && better) {
      out.notes.push_back(at + " holds two modes: split (" + both() + ")");
      model = std::move(trial);
      ++inside;
      r = static_cast<std::size_t>(-1);  // look at every mode again
    } else if (better) {
      out.warnings.push_back(at + " may hold two close modes: two poles fit better but one " +
                             "comes out unphysical; one mode kept (" + both() + ")");
    } else if (valid && chi2 > kSplitChi2Doubt) {
      out.warnings.push_back(at + " fits as one mode or as two almost equally (" + both() +
                             "): the number of modes there is uncertain");
    }
  }
}

}  // namespace

FrfFit fit_modes(const MeasuredFrf& frf, Direction direction, const FrfFitOptions& options) {
  FrfFit base;
  base.direction = direction;
  base.automatic = options.modes == 0;
  BandData band = band_of(frf, options, base);
  if (!base.coherence_weighted) weigh_floor_first(band);
  PoleResidueModel model;
  FrfFit out = fit_pass(band, options, base, model);
  if (base.coherence_weighted) {
    // The coherence's weights on the model's magnitude (§4.3): the fit again.
    band = coherence_reweighted(band, model);
    out = fit_again(band, options, base, out, model);
  }
  out.noise = estimate_noise(band, model);
  // A noise floor (§4.1): the fit again with the weights of the noise, until they settle.
  for (int pass = 0; pass < 2 && !base.coherence_weighted && floor_matters(band, model, out.noise);
       ++pass) {
    const double g0 = floor_magnitude(out.noise);
    band = reweighted(band, &model, out.noise);
    out = fit_again(band, options, base, out, model);
    out.noise = estimate_noise(band, model);
    out.noise_weighted = true;
    if (std::abs(std::log(floor_magnitude(out.noise) / g0)) < std::log(1.5)) break;
  }
  const std::size_t inside = model.poles.size();  // the outside poles follow
  std::vector<OutsidePole> outside_poles;
  if (options.residuals && !model.poles.empty() &&
      fit_detail::rms_relative_error(band, model) >= kExactFit)
    outside_poles = add_outside_poles(band, model);
  // A floor that only a later model shows (a merged pair's error read as noise before its
  // split): the weights of §4.1 and one more refinement.
  const auto weigh_late_floor = [&] {
    out.noise = estimate_noise(band, model);
    if (out.noise_weighted || out.coherence_weighted || !floor_matters(band, model, out.noise))
      return;
    band = reweighted(band, &model, out.noise);
    fit_detail::refine(band, model);
    out.noise = estimate_noise(band, model);
    out.noise_weighted = true;
  };
  if (out.automatic) {
    split_merged_modes(band, model, inside, out);
    if (!out.noise_weighted) {
      weigh_late_floor();
      if (out.noise_weighted) {  // the doubts again, on the right weights
        std::erase_if(out.warnings, [](const std::string& w) {
          return w.find("fits as one mode or as two almost equally") != std::string::npos;
        });
        const auto in_band = std::count_if(model.poles.begin(), model.poles.end(), [&](cd p) {
          return std::abs(p) >= band.lo_rad_s && std::abs(p) <= band.hi_rad_s;
        });
        split_merged_modes(band, model, static_cast<std::size_t>(in_band), out);
      }
    }
  }
  weigh_late_floor();
  out.residuals = reported(model.residuals);
  out.rms_relative_error = fit_detail::rms_relative_error(band, model);
  const Eigen::MatrixXd covariance = fit_detail::parameter_covariance(band, model);
  for (std::size_t r = 0; r < model.poles.size(); ++r) {
    const bool outside =
        std::abs(model.poles[r]) < band.lo_rad_s || std::abs(model.poles[r]) > band.hi_rad_s;
    FittedMode m = fitted_mode(band, model.poles[r], model.residues[r]);
    set_uncertainty(m, covariance.block<4, 4>(4 * static_cast<Eigen::Index>(r),
                                              4 * static_cast<Eigen::Index>(r)));
    (outside ? out.outside_modes : out.modes).push_back(m);
  }
  warn_outside_poles(outside_poles, out);
  std::sort(out.modes.begin(), out.modes.end(),
            [](const FittedMode& a, const FittedMode& b) { return a.natural_hz < b.natural_hz; });
  for (const FittedMode& m : out.modes)
    out.model.modes.push_back(Mode{direction, m.natural_rad_s, m.damping_ratio,
                                   m.stiffness_n_per_m, m.residue_phase_deg * kTwoPi / 360.0});
  out.model_rms_relative_error = model_error(band, out.model, direction);
  // A number of modes asked is met or refused (§3): never fewer without a word.
  if (!out.automatic && static_cast<int>(out.modes.size()) != options.modes) {
    std::vector<std::string> problems{
        "modes = " + std::to_string(options.modes) + ": the band " + fixed(out.lo_hz, 0) + "…" +
        fixed(out.hi_hz, 0) + " Hz holds " + std::to_string(out.modes.size()) +
        " distinct physical mode(s) to fit; ask for " + std::to_string(out.modes.size()) +
        " or fewer, or let the diagram choose (automatic)"};
    for (const std::string& w : out.warnings) problems.push_back("modes: " + w);
    throw InvalidInput(problems, "fit");
  }
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
    // The residual terms and the explicit poles outside the band stand for modes beyond it:
    // inside the band only.
    const bool in_band = f >= fit.lo_hz && f <= fit.hi_hz && f > 0.0;
    cd g = fit_detail::evaluate(model, kTwoPi * f, in_band);
    if (in_band)
      for (const FittedMode& m : fit.outside_modes)
        g += fit_detail::mode_term(m.pole, m.residue, kTwoPi * f);
    out.receptance_m_per_n.push_back(g);
  }
  return out;
}

}  // namespace cutdyn
