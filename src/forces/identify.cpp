// Cutting coefficients from mean milling forces; docs/models/identification.md.
#include "cutdyn/forces/identify.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn {

using units::kPi;
using units::kTwoPi;

std::vector<std::string> IdentifyCut::validate() const {
  Validator v("cut");
  v.require(teeth >= 1, "teeth", teeth, "", "must be at least 1");
  v.require(std::isfinite(entry_rad) && entry_rad >= 0.0 && entry_rad <= kPi, "entry_rad",
            entry_rad, "rad", "must be in [0, π]");
  v.require(std::isfinite(exit_rad) && exit_rad >= 0.0 && exit_rad <= kPi, "exit_rad", exit_rad,
            "rad", "must be in [0, π]");
  if (std::isfinite(entry_rad) && std::isfinite(exit_rad) && !(entry_rad < exit_rad))
    v.add("cut.entry_rad = " + format_value(entry_rad) + " rad, cut.exit_rad = " +
          format_value(exit_rad) + " rad: the entry must come before the exit");
  return v.problems();
}

// [Altintas2012, ch. 2] in cutdyn's convention (docs/models/identification.md, "Closed
// forms"): the integrals of sinφ·cosφ, sin²φ, cosφ and sinφ over the window.
WindowIntegrals window_integrals(double entry_rad, double exit_rad) {
  const double a = entry_rad, b = exit_rad;
  WindowIntegrals w;
  w.isc = 0.5 * (std::sin(b) * std::sin(b) - std::sin(a) * std::sin(a));
  w.iss = 0.5 * (b - a) - 0.25 * (std::sin(2.0 * b) - std::sin(2.0 * a));
  w.ic = std::sin(b) - std::sin(a);
  w.is = std::cos(a) - std::cos(b);
  w.width_rad = b - a;
  return w;
}

Eigen::Matrix2d WindowIntegrals::chip_matrix() const {
  Eigen::Matrix2d m;
  m << -isc, -iss, iss, -isc;
  return m;
}

Eigen::Matrix2d WindowIntegrals::edge_matrix() const {
  Eigen::Matrix2d m;
  m << -ic, -is, is, -ic;
  return m;
}

Eigen::Vector3d mean_milling_force(const IdentifyCut& cut, const CuttingCoefficients& k,
                                   double feed_per_tooth_m, double depth_m) {
  const WindowIntegrals w = window_integrals(cut.entry_rad, cut.exit_rad);
  const double scale = cut.teeth * depth_m / kTwoPi;
  const Eigen::Vector2d planar =
      scale * (feed_per_tooth_m * w.chip_matrix() * Eigen::Vector2d(k.kt_pa, k.kr_pa) +
               w.edge_matrix() * Eigen::Vector2d(k.kte_n_per_m, k.kre_n_per_m));
  const double axial = scale * (feed_per_tooth_m * k.ka_pa * w.is + k.kae_n_per_m * w.width_rad);
  return {planar.x(), planar.y(), axial};
}

namespace {

// `digits` significant digits, for warnings.
std::string num(double value, int digits = 3) {
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, value);
  return buffer;
}

std::string sample_name(const std::vector<MeanForce>& samples, std::size_t i) {
  const std::string& label = samples[i].label;
  return "samples[" + std::to_string(i) + "]" + (label.empty() ? "" : " (" + label + ")");
}

std::vector<std::string> sample_problems(const std::vector<MeanForce>& samples) {
  Validator v;
  const bool axial = !samples.empty() && samples.front().fz_n.has_value();
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const MeanForce& s = samples[i];
    Validator one;
    one.require_positive("feed_per_tooth_m", s.feed_per_tooth_m, "m");
    one.require_positive("depth_m", s.depth_m, "m");
    one.require(std::isfinite(s.fx_n), "fx_n", s.fx_n, "N", "must be a finite number");
    one.require(std::isfinite(s.fy_n), "fy_n", s.fy_n, "N", "must be a finite number");
    if (s.fz_n)
      one.require(std::isfinite(*s.fz_n), "fz_n", *s.fz_n, "N", "must be a finite number");
    if (s.fz_n.has_value() != axial)
      one.add(std::string(axial ? "no fz_n" : "fz_n given") + " but " +
              (axial ? "samples[0] has one" : "not for samples[0]") +
              ": give the axial force for every sample or for none");
    for (const std::string& p : one.problems()) v.add(sample_name(samples, i) + ": " + p);
  }
  return v.problems();
}

// Ordinary least squares y = intercept + slope·x with the usual variances, s² = SSR/(n − 2).
struct LineFit {
  double slope = 0.0, intercept = 0.0;
  double var_slope = 0.0, var_intercept = 0.0;
  double ssr = 0.0, sst = 0.0, s2 = 0.0;
  std::vector<double> residuals;
  double r_squared() const { return sst > 0.0 ? 1.0 - ssr / sst : 1.0; }
};

LineFit fit_line(const std::vector<double>& x, const std::vector<double>& y) {
  const auto n = static_cast<double>(x.size());
  double mx = 0.0, my = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    mx += x[i] / n;
    my += y[i] / n;
  }
  double sxx = 0.0, sxy = 0.0;
  LineFit f;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
    f.sst += (y[i] - my) * (y[i] - my);
  }
  f.slope = sxy / sxx;
  f.intercept = my - f.slope * mx;
  for (std::size_t i = 0; i < x.size(); ++i) {
    f.residuals.push_back(y[i] - (f.intercept + f.slope * x[i]));
    f.ssr += f.residuals.back() * f.residuals.back();
  }
  if (x.size() > 2) {
    f.s2 = f.ssr / (n - 2.0);
    f.var_slope = f.s2 / sxx;
    f.var_intercept = f.s2 * (1.0 / n + mx * mx / sxx);
  }
  return f;
}

// value = row·(a, b) with a and b from independent fits: var = row0²·var_a + row1²·var_b.
IdentifiedCoefficient combine(const Eigen::RowVector2d& row, double a, double var_a, double b,
                              double var_b, double t) {
  IdentifiedCoefficient c;
  c.value = row(0) * a + row(1) * b;
  if (t > 0.0) {
    c.uncertainty_known = true;
    c.std_error = std::sqrt(row(0) * row(0) * var_a + row(1) * row(1) * var_b);
    c.ci95_low = c.value - t * c.std_error;
    c.ci95_high = c.value + t * c.std_error;
  }
  return c;
}

int distinct_feeds(const std::vector<MeanForce>& samples) {
  std::vector<double> feeds;
  for (const MeanForce& s : samples) feeds.push_back(s.feed_per_tooth_m);
  std::sort(feeds.begin(), feeds.end());
  int count = feeds.empty() ? 0 : 1;
  for (std::size_t i = 1; i < feeds.size(); ++i)
    if (feeds[i] - feeds[i - 1] > 1e-9 * feeds[i]) ++count;
  return count;
}

struct Named {
  const char* name;
  const IdentifiedCoefficient* c;
  bool chip;  // N/mm² (else N/mm)
};

std::string shown(const Named& n, double value_si) {
  return num(n.chip ? units::pa_to_n_per_mm2(value_si) : value_si / 1e3) +
         (n.chip ? " N/mm²" : " N/mm");
}

void warn_coefficients(CoefficientFit& fit) {
  std::vector<Named> all = {{"Kt", &fit.kt, true},
                            {"Kr", &fit.kr, true},
                            {"Kte", &fit.kte, false},
                            {"Kre", &fit.kre, false}};
  if (fit.ka) all.push_back({"Ka", &*fit.ka, true});
  if (fit.kae) all.push_back({"Kae", &*fit.kae, false});
  for (const Named& n : all) {
    const IdentifiedCoefficient& c = *n.c;
    if (c.uncertainty_known && !c.determined())
      fit.warnings.push_back(std::string(n.name) +
                             " is not determined by these samples: " + shown(n, c.value) + " ± " +
                             shown(n, c.ci95_high - c.value) + " (95 %) includes zero");
    // The axial pair's sign depends on the helix hand and on which way +z points.
    const bool planar = n.c == &fit.kt || n.c == &fit.kr || n.c == &fit.kte || n.c == &fit.kre;
    if (planar && c.value < 0.0)
      fit.warnings.push_back(std::string(n.name) + " = " + shown(n, c.value) +
                             " is negative: a cutting force that pulls the tooth forward or the "
                             "cutter outward; check the force signs (forces on the cutter, x "
                             "the feed direction), the window and the samples");
  }
}

void warn_window(CoefficientFit& fit, bool axial) {
  constexpr double kNarrow = 0.05;
  if (fit.chip_gain_ratio < kNarrow)
    fit.warnings.push_back("narrow window: the chip matrix's gain is " +
                           num(100.0 * fit.chip_gain_ratio, 2) +
                           " % of slotting's, so the chip forces are small and Kt, Kr" +
                           (axial ? ", Ka" : "") + " carry the force errors amplified " +
                           num(1.0 / fit.chip_gain_ratio, 2) + "× compared with slotting");
  if (fit.edge_gain_ratio < kNarrow)
    fit.warnings.push_back("narrow window: the edge matrix's gain is " +
                           num(100.0 * fit.edge_gain_ratio, 2) +
                           " % of slotting's, so the edge forces are small and Kte, Kre" +
                           (axial ? ", Kae" : "") + " carry the force errors amplified " +
                           num(1.0 / fit.edge_gain_ratio, 2) + "× compared with slotting");
}

void warn_samples(CoefficientFit& fit, const std::vector<MeanForce>& samples) {
  double lo = samples.front().feed_per_tooth_m, hi = lo;
  for (const MeanForce& s : samples) {
    lo = std::min(lo, s.feed_per_tooth_m);
    hi = std::max(hi, s.feed_per_tooth_m);
  }
  if (fit.distinct_feeds < 3)
    fit.warnings.push_back("only " + std::to_string(fit.distinct_feeds) +
                           " distinct feeds: the straight line in the feed cannot be checked "
                           "(use at least 3)");
  else if ((hi - lo) < 0.2 * hi)
    fit.warnings.push_back("the feeds span only " + num(100.0 * (hi - lo) / hi, 2) +
                           " % of the largest: slope (Kt, Kr) and intercept (Kte, Kre) are hard "
                           "to tell apart; spread the feeds wider");
  if (fit.degrees_of_freedom == 0)
    fit.warnings.push_back(
        "2 samples for 2 unknowns per direction: no residual degrees of freedom, so no "
        "standard errors or intervals");
  constexpr double kPoorFit = 0.05;
  if (fit.relative_residual > kPoorFit)
    fit.warnings.push_back("poor fit: the residuals are " + num(100.0 * fit.relative_residual, 2) +
                           " % of the mean force (R² x " + num(fit.r_squared_x, 3) + ", y " +
                           num(fit.r_squared_y, 3) +
                           "): the forces do not follow a straight line in the feed; check the "
                           "residuals for a bad sample");
}

}  // namespace

CoefficientFit identify_coefficients(const IdentifyCut& cut,
                                     const std::vector<MeanForce>& samples) {
  Validator v;
  v.merge(cut.validate());
  v.merge(sample_problems(samples));
  v.throw_if_any("identify");
  CoefficientFit fit;
  fit.samples = static_cast<int>(samples.size());
  fit.distinct_feeds = distinct_feeds(samples);
  if (fit.distinct_feeds < 2)
    throw InvalidInput({"samples: " + std::to_string(samples.size()) + " sample(s) at " +
                        std::to_string(fit.distinct_feeds) +
                        " distinct feed(s): need at least 2 distinct feeds per tooth to separate "
                        "the cutting (slope) from the edge (intercept) coefficients"},
                       "identify");
  const bool axial = samples.front().fz_n.has_value();
  std::vector<double> c, yx, yy, yz;
  for (const MeanForce& s : samples) {
    c.push_back(s.feed_per_tooth_m);
    yx.push_back(s.fx_n / s.depth_m);
    yy.push_back(s.fy_n / s.depth_m);
    if (axial) yz.push_back(*s.fz_n / s.depth_m);
  }
  const LineFit fx = fit_line(c, yx), fy = fit_line(c, yy);
  fit.degrees_of_freedom = fit.samples - 2;
  fit.t_quantile =
      fit.degrees_of_freedom > 0 ? student_t_quantile(0.975, fit.degrees_of_freedom) : 0.0;
  const double t = fit.t_quantile;
  // Slopes = (z/2π)·A·(Kt, Kr), intercepts = (z/2π)·B·(Kte, Kre) (identify.hpp).
  const WindowIntegrals w = window_integrals(cut.entry_rad, cut.exit_rad);
  const double factor = kTwoPi / cut.teeth;
  const Eigen::Matrix2d mc = factor * w.chip_matrix().inverse();
  const Eigen::Matrix2d me = factor * w.edge_matrix().inverse();
  fit.kt = combine(mc.row(0), fx.slope, fx.var_slope, fy.slope, fy.var_slope, t);
  fit.kr = combine(mc.row(1), fx.slope, fx.var_slope, fy.slope, fy.var_slope, t);
  fit.kte = combine(me.row(0), fx.intercept, fx.var_intercept, fy.intercept, fy.var_intercept, t);
  fit.kre = combine(me.row(1), fx.intercept, fx.var_intercept, fy.intercept, fy.var_intercept, t);
  fit.r_squared_x = fx.r_squared();
  fit.r_squared_y = fy.r_squared();
  std::optional<LineFit> fz;
  if (axial) {
    fz = fit_line(c, yz);
    const Eigen::RowVector2d ka_row(factor / w.is, 0.0), kae_row(factor / w.width_rad, 0.0);
    fit.ka = combine(ka_row, fz->slope, fz->var_slope, 0.0, 0.0, t);
    fit.kae = combine(kae_row, fz->intercept, fz->var_intercept, 0.0, 0.0, t);
    fit.r_squared_z = fz->r_squared();
  }
  double force2 = 0.0;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    SampleResidual r{samples[i].label, fx.residuals[i] * samples[i].depth_m,
                     fy.residuals[i] * samples[i].depth_m, std::nullopt};
    if (fz) r.fz_n = fz->residuals[i] * samples[i].depth_m;
    fit.residuals.push_back(r);
    force2 += (yx[i] * yx[i] + yy[i] * yy[i]) / static_cast<double>(samples.size());
  }
  fit.relative_residual = force2 > 0.0 ? std::sqrt(0.5 * (fx.s2 + fy.s2) / force2) : 0.0;
  fit.chip_gain_ratio = std::sqrt(w.chip_matrix().determinant()) / (0.5 * kPi);
  fit.edge_gain_ratio = std::sqrt(w.edge_matrix().determinant()) / 2.0;
  warn_samples(fit, samples);
  warn_window(fit, axial);
  warn_coefficients(fit);
  return fit;
}

CuttingCoefficients CoefficientFit::coefficients() const {
  CuttingCoefficients c;
  c.kt_pa = kt.value;
  c.kr_pa = kr.value;
  c.kte_n_per_m = kte.value;
  c.kre_n_per_m = kre.value;
  if (ka) c.ka_pa = ka->value;
  if (kae) c.kae_n_per_m = kae->value;
  return c;
}

}  // namespace cutdyn
