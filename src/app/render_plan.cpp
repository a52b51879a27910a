// The bore plan's report rendered: the text and figure of `cutdyn plan` (two-edge face
// milling of a large bore, [Zenkin2012]; docs/models/bore-milling.md).
#include <fmt/format.h>

#include <algorithm>

#include "cutdyn/app/detail/text.hpp"
#include "cutdyn/app/render.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/plan/bore_milling.hpp"

namespace cutdyn::app {
namespace {

using units::m_to_mm;

std::string mm(double m) { return human(m_to_mm(m), 5); }

constexpr const char* kChosenColour = "#000000";  // the plan's point, black on both panels
constexpr const char* kDelta1Colour = "#D55E00";  // Δ1 and its limit, solid and dashed

}  // namespace

void write_text(std::ostream& out, const io::Case& c, const PlanJobReport& job) {
  out << "cutdyn plan: " << c.source << "\n";
  const BoreMillingCase& b = job.chosen;
  const BoreMillingResult& r = job.result;
  out << fmt::format(
      "  bore {} mm × {} mm, allowance {} mm; cutter {} mm, {} teeth, h = {} mm, φ = {}°\n",
      mm(b.bore_diameter_m), mm(b.length_m), mm(b.allowance_m), mm(b.cutter_diameter_m), b.teeth,
      mm(b.offset_m), human(units::rad_to_deg(b.lead_angle_rad)));
  out << fmt::format(
      "  largest axial feed (Δ1 = k·t = {} mm)   {} mm   (eq. 4 corrected: {} mm; as printed, "
      "with d²k²t²: {} mm, {:+.2f} %)\n",
      mm(b.accuracy_coefficient * b.allowance_m), mm(r.max_axial_feed_m),
      mm(r.max_axial_feed_closed_form_m), mm(r.max_axial_feed_printed_form_m),
      job.printed_form_difference_percent);
  out << fmt::format(
      "  allowance split: inner edges {} mm, outer edges {} mm (even at h* = {} mm)\n",
      mm(r.inner_depth_m), mm(r.outer_depth_m), mm(r.balanced_offset_m));
  out << fmt::format("  axial feed S0                          {} mm{}\n", mm(r.axial_feed_m),
                     job.feed_given ? " (given)" : "");
  out << fmt::format("  width of cut q / of milling bф         {} mm / {} mm\n", mm(r.q_m),
                     mm(r.milling_width_m));
  out << fmt::format("  cutter / workpiece speed               {} / {} rpm\n",
                     human(60.0 * r.cutter_rev_per_s), human(60.0 * r.workpiece_rev_per_s, 4));
  out << fmt::format("  chip: a_max {} mm, a_cp {} mm, feed per tooth {} mm, width {} mm\n",
                     mm(r.max_chip_thickness_m), mm(r.mean_chip_thickness_m),
                     mm(r.feed_per_tooth_m), mm(r.chip_width_m));
  out << fmt::format("  teeth in cut z' = {} (p = {}), contact arc {} mm, edge path {} m\n",
                     r.teeth_in_cut, human(r.engaged_fraction, 3), mm(r.contact_arc_m),
                     human(r.path_per_edge_m, 4));
  out << fmt::format("  straightness error Δ1 {} mm, faceting Δ2 {} mm\n",
                     mm(r.straightness_error_m), human(m_to_mm(r.faceting_m), 3));
  out << fmt::format("  main time t0 {} min, removal rate {} cm³/min\n",
                     human(r.main_time_s / 60.0, 4), human(r.removal_rate_m3_per_s * 6e7, 4));
  for (const std::string& w : job.warnings) out << "  warning: " << w << "\n";
  if (job.plan) {
    std::string binding;
    for (const std::string& name : job.plan->binding)
      binding += (binding.empty() ? "" : ", ") + name;
    out << fmt::format("  optimised within [limits]: h = {} mm, v = {} m/min; binding: {}\n",
                       mm(b.offset_m), human(60.0 * b.cutting_speed_m_per_s), binding);
  }
}

// Two panels: t0 and Δ1 against the axial feed S0 at the chosen h, with the limit
// Δ1 = k·t; t0 against the offset h at the chosen S0. Each marks the chosen point.
io::PlotFigure figure(const PlanJobReport& job) {
  const PlanTradeOff& t = *job.trade_off;
  const BoreMillingCase& b = job.chosen;
  const BoreMillingResult& r = job.result;
  const double s0 = m_to_mm(r.axial_feed_m), h = m_to_mm(b.offset_m);
  const double t0 = r.main_time_s / 60.0;
  const double limit = m_to_mm(b.accuracy_coefficient * b.allowance_m);
  const auto series = [](const PlanCurve& curve, std::string name, double y_scale, bool y2) {
    io::PlotSeries s{std::move(name), {}, {}, "lines", y2};
    for (std::size_t i = 0; i < curve.x.size(); ++i) {
      s.x.push_back(m_to_mm(curve.x[i]));
      s.y.push_back(curve.y[i] * y_scale);
    }
    return s;
  };
  const std::string point = fmt::format("S0 = {} mm, h = {} mm, t0 = {} min", mm(r.axial_feed_m),
                                        mm(b.offset_m), human(t0, 4));
  const std::string chosen = "chosen: " + point;
  io::PlotFigure figure;
  figure.title = "Main time t0 of the bore around the plan: " + point;

  io::PlotSpec feed;
  feed.title = fmt::format("Against the axial feed S0, at h = {} mm (infeasible feeds left out)",
                           mm(b.offset_m));
  feed.x_label = "axial feed S0 (mm)";
  feed.y_label = "main time t0 (min, logarithmic)";
  feed.y_log = true;  // t0 ∝ 1/S0: hours at the smallest feeds, minutes near the plan
  feed.y2_label = "straightness error Δ1 (mm)";
  feed.series.push_back(series(t.time_against_feed, "t0", 1.0 / 60.0, false));
  feed.series.push_back(series(t.straightness_against_feed, "Δ1 (right axis)", 1e3, true));
  feed.series.back().color = kDelta1Colour;
  const std::vector<double>& fx = feed.series.back().x;
  if (!fx.empty()) {
    const auto [lo, hi] = std::minmax_element(fx.begin(), fx.end());
    const std::string title = fmt::format("limit Δ1 = k·t = {} mm (right axis)", human(limit, 4));
    feed.series.push_back(
        io::PlotSeries{title, {*lo, *hi}, {limit, limit}, "dashed", true, kDelta1Colour});
  }
  feed.series.push_back(io::PlotSeries{chosen, {s0}, {t0}, "marker", false, kChosenColour});
  feed.x_marks.push_back({s0, fmt::format("S0 = {} mm", mm(r.axial_feed_m))});

  io::PlotSpec offset;
  offset.title = fmt::format("Against the offset h, at S0 = {} mm", mm(r.axial_feed_m));
  offset.x_label = "offset h (mm)";
  offset.y_label = "main time t0 (min)";
  offset.series.push_back(series(t.time_against_offset, "t0", 1.0 / 60.0, false));
  offset.series.push_back(io::PlotSeries{chosen, {h}, {t0}, "marker", false, kChosenColour});
  offset.x_marks.push_back({h, fmt::format("h = {} mm", mm(b.offset_m))});
  figure.panels = {std::move(feed), std::move(offset)};
  return figure;
}

}  // namespace cutdyn::app
