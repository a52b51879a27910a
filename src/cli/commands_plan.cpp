// `cutdyn plan`: two-edge face milling of a large bore ([Zenkin2012];
// docs/models/bore-milling.md).
#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cutdyn/app/plan.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/io/output.hpp"
#include "cutdyn/io/plot.hpp"
#include "cutdyn/plan/bore_milling.hpp"

namespace cutdyn::cli {

namespace {

using units::m_to_mm;

std::string mm(double m) { return human(m_to_mm(m), 5); }

void print_plan(const app::PlanJobReport& job, std::ostream& out, std::ostream& err) {
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
  out << fmt::format("  allowance split: inner edges {} mm, outer edges {} mm (even at h* = {} mm)\n",
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
  for (const std::string& w : job.warnings) {
    out << "  warning: " << w << "\n";
    err << "cutdyn: warning: " << job.where << ": " << w << "\n";
  }
  if (job.plan) {
    std::string binding;
    for (const std::string& name : job.plan->binding)
      binding += (binding.empty() ? "" : ", ") + name;
    out << fmt::format("  optimised within [limits]: h = {} mm, v = {} m/min; binding: {}\n",
                       mm(b.offset_m), human(60.0 * b.cutting_speed_m_per_s), binding);
  }
}

nlohmann::json plan_json(const io::Case& c, const app::PlanJobReport& job) {
  const BoreMillingResult& r = job.result;
  nlohmann::json doc{{"command", "plan"}, {"schema_version", kJsonSchemaVersion},
                     {"case", io::to_json(c)},
                     {"source", c.source},
                     {"q_mm", m_to_mm(r.q_m)},
                     {"axial_feed_mm", m_to_mm(r.axial_feed_m)},
                     {"max_axial_feed_mm", m_to_mm(r.max_axial_feed_m)},
                     {"max_axial_feed_closed_form_mm", m_to_mm(r.max_axial_feed_closed_form_m)},
                     {"max_axial_feed_printed_form_mm", m_to_mm(r.max_axial_feed_printed_form_m)},
                     {"printed_form_difference_percent", job.printed_form_difference_percent},
                     {"inner_depth_mm", m_to_mm(r.inner_depth_m)},
                     {"outer_depth_mm", m_to_mm(r.outer_depth_m)},
                     {"balanced_offset_mm", m_to_mm(r.balanced_offset_m)},
                     {"milling_width_mm", m_to_mm(r.milling_width_m)},
                     {"straightness_error_mm", m_to_mm(r.straightness_error_m)},
                     {"faceting_mm", m_to_mm(r.faceting_m)},
                     {"cutter_rpm", 60.0 * r.cutter_rev_per_s},
                     {"workpiece_rpm", 60.0 * r.workpiece_rev_per_s},
                     {"feed_per_tooth_mm", m_to_mm(r.feed_per_tooth_m)},
                     {"max_chip_thickness_mm", m_to_mm(r.max_chip_thickness_m)},
                     {"mean_chip_thickness_mm", m_to_mm(r.mean_chip_thickness_m)},
                     {"contact_arc_mm", m_to_mm(r.contact_arc_m)},
                     {"chip_width_mm", m_to_mm(r.chip_width_m)},
                     {"path_per_edge_m", r.path_per_edge_m},
                     {"edge_width_mm", m_to_mm(r.edge_width_m)},
                     {"engaged_fraction", r.engaged_fraction},
                     {"teeth_in_cut", r.teeth_in_cut},
                     {"total_edge_width_mm", m_to_mm(r.total_edge_width_m)},
                     {"main_time_min", r.main_time_s / 60.0},
                     {"removal_rate_cm3_per_min", r.removal_rate_m3_per_s * 6e7},
                     {"offset_mm", m_to_mm(job.chosen.offset_m)},
                     {"cutting_speed_m_per_min", 60.0 * job.chosen.cutting_speed_m_per_s},
                     {"optimised", job.plan.has_value()},
                     {"accuracy_met", r.accuracy_met},
                     {"warnings", job.warnings}};
  if (job.plan) doc["binding_constraints"] = job.plan->binding;
  return doc;
}

// t0 against S0 at the chosen h and against h at the chosen S0; Δ1 beside it.
io::PlotSpec plan_plot(const app::PlanJobReport& job) {
  const app::PlanTradeOff& t = *job.trade_off;
  io::PlotSpec spec;
  spec.title = fmt::format("Main time against the axial feed (h = {} mm) and the offset",
                           mm(job.chosen.offset_m));
  spec.x_label = "axial feed S0 (mm) | offset h (mm)";
  spec.y_label = "main time t0 (min; infeasible points left out)";
  spec.y2_label = "straightness error Δ1 (mm)";
  const auto series = [](const app::PlanCurve& curve, const char* name, double y_scale, bool y2) {
    io::PlotSeries s{name, {}, {}, "lines", y2};
    for (std::size_t i = 0; i < curve.x.size(); ++i) {
      s.x.push_back(m_to_mm(curve.x[i]));
      s.y.push_back(curve.y[i] * y_scale);
    }
    return s;
  };
  spec.series = {series(t.time_against_feed, "t0 against S0", 1.0 / 60.0, false),
                 series(t.time_against_offset, "t0 against h", 1.0 / 60.0, false),
                 series(t.straightness_against_feed, "Δ1 against S0 (right)", 1e3, true)};
  return spec;
}

}  // namespace

int run_plan(const PlanArgs& args, std::ostream& out, std::ostream& err) {
  check_outputs({"", args.json, args.plot});
  const io::Case c = load_case(args.case_path, "bore-plan", err);
  if (!args.plot.empty() && c.bore && !c.bore_limits)
    throw InvalidInput({"--plot: the trade-off needs the [limits] table"}, c.source);
  app::PlanRequest request;
  if (args.axial_feed_mm) request.axial_feed_m = units::mm_to_m(*args.axial_feed_mm);
  request.names = flag_names();
  request.axial_feed_name = "--axial-feed-mm";
  const app::PlanJobReport job = app::run_plan(c, request);
  out << "cutdyn plan: " << c.source << "\n";
  print_plan(job, out, err);
  io::OutputTransaction outputs;
  if (!args.json.empty()) io::write_json(outputs.open(args.json), plan_json(c, job));
  if (!args.plot.empty()) io::write_plot(plan_plot(job), args.plot, outputs);
  commit_outputs(outputs, {"", args.json, args.plot}, out);
  return 0;
}

}  // namespace cutdyn::cli
