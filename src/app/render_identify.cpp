// The identification's report rendered: the text and figure of `cutdyn identify` (the
// average-force method of [Altintas2012, ch. 2]; docs/models/identification.md).
#include <fmt/format.h>

#include <algorithm>

#include "cutdyn/app/detail/text.hpp"
#include "cutdyn/app/render.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn::app {
namespace {

using units::m_to_mm;

std::string joined(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : ", ") + s;
  return out;
}

// The cut and the spread of the test cuts.
void print_cut(const IdentifyJobReport& r, std::ostream& out) {
  double c_lo = 1e300, c_hi = 0.0, a_lo = 1e300, a_hi = 0.0;
  for (const IdentifiedSample& s : r.samples) {
    c_lo = std::min(c_lo, s.measured.feed_per_tooth_m);
    c_hi = std::max(c_hi, s.measured.feed_per_tooth_m);
    a_lo = std::min(a_lo, s.measured.depth_m);
    a_hi = std::max(a_hi, s.measured.depth_m);
  }
  const auto range = [](double lo, double hi) {
    return lo == hi ? human(m_to_mm(lo)) : human(m_to_mm(lo)) + "–" + human(m_to_mm(hi));
  };
  out << fmt::format(
      "  {} teeth, engagement {}° … {}°; feeds per tooth {} mm ({} distinct), depth {} mm\n",
      r.cut.teeth, human(units::rad_to_deg(r.cut.entry_rad)),
      human(units::rad_to_deg(r.cut.exit_rad)), range(c_lo, c_hi), r.fit.distinct_feeds,
      range(a_lo, a_hi));
}

void print_coefficients(const IdentifyJobReport& r, std::ostream& out) {
  out << fmt::format("  {:<14}{:>11}   {:<32}{}\n", "coefficient", "identified", "95 % interval",
                     "in the case");
  for (const IdentifiedValue& v : r.values) {
    const IdentifiedCoefficient& k = v.value;
    const std::string interval =
        k.uncertainty_known ? fmt::format("{} … {} (± {})", human(k.ci95_low), human(k.ci95_high),
                                          human(k.ci95_high - k.value, 3))
                            : "–";
    const std::string name = v.name + " (" + v.unit + ")";
    out << fmt::format("  {:<14}{:>11}   {:<32}{}\n", name, human(k.value), interval,
                       v.case_value ? human(*v.case_value) : std::string("–"));
  }
  const CoefficientFit& f = r.fit;
  std::string r2 = "R² x " + human(f.r_squared_x, 5) + ", y " + human(f.r_squared_y, 5);
  if (f.r_squared_z) r2 += ", z " + human(*f.r_squared_z, 5);
  out << "  " << r2 << "; residuals " << human(100.0 * f.relative_residual, 3)
      << " % of the mean force; " << f.degrees_of_freedom << " degrees of freedom";
  if (f.degrees_of_freedom > 0) out << " (t = " << human(f.t_quantile) << ")";
  out << "\n";
}

// Measured, fitted and residual mean force of each test cut.
void print_samples(const IdentifyJobReport& r, std::ostream& out) {
  const bool axial = !r.samples.empty() && r.samples.front().fitted_fz_n.has_value();
  out << "  mean forces (N): measured, fitted, residual = measured − fitted\n";
  std::string head =
      fmt::format("  {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9}", "feed mm", "depth mm", "fx",
                  "fitted", "residual", "fy", "fitted", "residual");
  if (axial) head += fmt::format(" {:>9} {:>9} {:>9}", "fz", "fitted", "residual");
  out << head << "   test cut\n";
  for (const IdentifiedSample& s : r.samples) {
    const MeanForce& m = s.measured;
    std::string line = fmt::format("  {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9}",
                                   human(m_to_mm(m.feed_per_tooth_m)), human(m_to_mm(m.depth_m)),
                                   human(m.fx_n), human(s.fitted_fx_n), human(s.residual.fx_n, 3),
                                   human(m.fy_n), human(s.fitted_fy_n), human(s.residual.fy_n, 3));
    if (axial)
      line += fmt::format(" {:>9} {:>9} {:>9}", human(*m.fz_n), human(*s.fitted_fz_n),
                          human(*s.residual.fz_n, 3));
    out << line << "   " << m.label;
    if (m.revolutions > 0) out << " (mean of " << m.revolutions << " revolutions)";
    out << "\n";
  }
}

constexpr const char* kColours[] = {"#0072B2", "#D55E00", "#009E73"};  // x, y, z

}  // namespace

void write_text(std::ostream& out, const io::Case& c, const IdentifyJobReport& r) {
  out << "cutdyn identify: " << c.source << " with " << r.fit.samples << " cuts from "
      << joined(r.force_files) << "\n";
  print_cut(r, out);
  print_coefficients(r, out);
  print_samples(r, out);
  for (const std::string& n : r.notes) out << "  note: " << n << "\n";
}

// Mean force per unit depth against the feed per tooth: the measured points and the fitted
// lines, from zero feed (the intercept: the edge forces) to beyond the largest feed.
io::PlotSpec figure(const IdentifyJobReport& r) {
  const bool axial = !r.samples.empty() && r.samples.front().fitted_fz_n.has_value();
  const CuttingCoefficients k = r.fit.coefficients();
  double c_max = 0.0;
  for (const IdentifiedSample& s : r.samples) c_max = std::max(c_max, s.measured.feed_per_tooth_m);
  io::PlotSpec spec;
  spec.title = fmt::format(
      "Mean force per unit depth: Kt {}, Kr {} N/mm², Kte {}, Kre {} N/mm ({} teeth, engagement "
      "{}° … {}°)",
      human(r.values[0].value.value), human(r.values[1].value.value),
      human(r.values[2].value.value), human(r.values[3].value.value), r.cut.teeth,
      human(units::rad_to_deg(r.cut.entry_rad)), human(units::rad_to_deg(r.cut.exit_rad)));
  spec.x_label = "feed per tooth (mm)";
  spec.y_label = "mean force on the cutter per unit axial depth (N/mm)";
  const char* names[] = {"x (feed direction)", "y", "z (axial)"};
  for (int d = 0; d < (axial ? 3 : 2); ++d) {
    io::PlotSeries measured{
        std::string("F") + names[d] + " measured", {}, {}, "points", false, kColours[d]};
    for (const IdentifiedSample& s : r.samples) {
      const MeanForce& m = s.measured;
      const double f = d == 0 ? m.fx_n : d == 1 ? m.fy_n : *m.fz_n;
      measured.x.push_back(m_to_mm(m.feed_per_tooth_m));
      measured.y.push_back(f / m_to_mm(m.depth_m));
    }
    io::PlotSeries fitted{
        std::string("F") + names[d] + " fitted", {}, {}, "lines", false, kColours[d]};
    for (double c : {0.0, 1.1 * c_max}) {  // a straight line: two points
      fitted.x.push_back(m_to_mm(c));
      fitted.y.push_back(mean_milling_force(r.cut, k, c, 1e-3)[d]);  // per mm of depth
    }
    spec.series.push_back(std::move(measured));
    spec.series.push_back(std::move(fitted));
  }
  return spec;
}

}  // namespace cutdyn::app
