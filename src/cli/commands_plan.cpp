// `cutdyn plan`: two-edge face milling of a large bore (models.md S2;
// docs/models/bore-milling.md).
#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/io/output.hpp"
#include "cutdyn/io/plot.hpp"
#include "cutdyn/plan/bore_milling.hpp"

namespace cutdyn::cli {

int run_plan(const PlanArgs& args, std::ostream& out, std::ostream& err) {
  check_outputs({"", args.json, args.plot});
  const io::Case c = load_case(args.case_path, "bore-plan", err);
  if (!c.bore) {
    throw InvalidInput({"process = \"" + std::string(io::to_string(c.process)) +
                        "\": `cutdyn plan` takes a bore-milling case ([bore], [cutter] and a "
                        "[process] table)"},
                       c.source);
  }
  double s0 = c.axial_feed_m.value_or(0.0);
  std::string where = c.source;
  if (args.axial_feed_mm) {
    if (!(*args.axial_feed_mm > 0.0))
      throw InvalidInput({"--axial-feed-mm = " + human(*args.axial_feed_mm) + ": must be positive"},
                         "command line");
    s0 = units::mm_to_m(*args.axial_feed_mm);
    where = "command line";
  }
  BoreMillingResult r;
  BoreMillingCase b = *c.bore;
  std::optional<BoreMillingPlan> plan;
  if (c.bore_limits && s0 == 0.0) {
    // [limits]: choose h, S0, n_u and n_o for the shortest main time.
    rethrow_as(c.source, "plan", [&] { plan = optimise_bore_milling(b, *c.bore_limits); });
    if (!plan->feasible) {
      throw InvalidInput({"limits: " + plan->reason}, c.source);
    }
    b = plan->chosen;
    r = plan->result;
  } else {
    rethrow_as(where, "plan", [&] { r = bore_milling(b, s0); });
  }
  const auto mm = [](double m) { return human(units::m_to_mm(m), 5); };
  const double diff =
      100.0 * (r.max_axial_feed_printed_form_m - r.max_axial_feed_m) / r.max_axial_feed_m;

  out << "cutdyn plan: " << c.source << "\n";
  out << fmt::format(
      "  bore {} mm × {} mm, allowance {} mm; cutter {} mm, {} teeth, h = {} mm, φ = {}°\n",
      mm(b.bore_diameter_m), mm(b.length_m), mm(b.allowance_m), mm(b.cutter_diameter_m), b.teeth,
      mm(b.offset_m), human(units::rad_to_deg(b.lead_angle_rad)));
  out << fmt::format(
      "  largest axial feed (Δ1 = k·t = {} mm)   {} mm   (eq. 4 corrected: {} mm; as printed, "
      "with d²k²t²: {} mm, {:+.2f} %)\n",
      mm(b.accuracy_coefficient * b.allowance_m), mm(r.max_axial_feed_m),
      mm(r.max_axial_feed_closed_form_m), mm(r.max_axial_feed_printed_form_m), diff);
  out << fmt::format("  allowance split: inner edges {} mm, outer edges {} mm (even at h* = {} mm)\n",
                     mm(r.inner_depth_m), mm(r.outer_depth_m), mm(r.balanced_offset_m));
  out << fmt::format("  axial feed S0                          {} mm{}\n", mm(r.axial_feed_m),
                     s0 > 0.0 ? " (given)" : "");
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
                     mm(r.straightness_error_m), human(units::m_to_mm(r.faceting_m), 3));
  out << fmt::format("  main time t0 {} min, removal rate {} cm³/min\n",
                     human(r.main_time_s / 60.0, 4), human(r.removal_rate_m3_per_s * 6e7, 4));
  // [limits] with a fixed feed: the optimiser does not run (the plan is at the case's h and
  // speeds); said, not left silent. --plot still draws the trade-off within the limits.
  if (c.bore_limits && !plan)
    r.warnings.push_back(
        "[limits] not used to optimise: the axial feed is given (" +
        std::string(args.axial_feed_mm ? "--axial-feed-mm" : "process.axial_feed_mm") +
        "), so the plan is at the case's offset h and cutting speed; leave the feed out to "
        "optimise");
  for (const std::string& w : r.warnings) {
    out << "  warning: " << w << "\n";
    err << "cutdyn: warning: " << where << ": " << w << "\n";
  }
  std::string binding;
  if (plan) {
    for (const std::string& name : plan->binding) binding += (binding.empty() ? "" : ", ") + name;
    out << fmt::format("  optimised within [limits]: h = {} mm, v = {} m/min; binding: {}\n",
                       mm(b.offset_m), human(60.0 * b.cutting_speed_m_per_s), binding);
  }

  io::OutputTransaction outputs;
  if (!args.json.empty()) {
    using units::m_to_mm;
    nlohmann::json doc{{"command", "plan"},
                       {"case", io::to_json(c)},
                       {"source", c.source},
                       {"q_mm", m_to_mm(r.q_m)},
                       {"axial_feed_mm", m_to_mm(r.axial_feed_m)},
                       {"max_axial_feed_mm", m_to_mm(r.max_axial_feed_m)},
                       {"max_axial_feed_closed_form_mm", m_to_mm(r.max_axial_feed_closed_form_m)},
                       {"max_axial_feed_printed_form_mm", m_to_mm(r.max_axial_feed_printed_form_m)},
                       {"printed_form_difference_percent", diff},
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
                       {"offset_mm", m_to_mm(b.offset_m)},
                       {"cutting_speed_m_per_min", 60.0 * b.cutting_speed_m_per_s},
                       {"optimised", plan.has_value()},
                       {"accuracy_met", r.accuracy_met},
                       {"warnings", r.warnings}};
    if (plan) doc["binding_constraints"] = plan->binding;
    io::write_json(outputs.open(args.json), doc);
  }
  if (!args.plot.empty()) {
    if (!c.bore_limits)
      throw InvalidInput({"--plot: the trade-off needs the [limits] table"}, c.source);
    // t0 against S0 at the chosen h and against h at the chosen S0; Δ1 beside it.
    io::PlotSpec spec;
    spec.title =
        fmt::format("Main time against the axial feed (h = {} mm) and the offset", mm(b.offset_m));
    spec.x_label = "axial feed S0 (mm) | offset h (mm)";
    spec.y_label = "main time t0 (min; infeasible points left out)";
    spec.y2_label = "straightness error Δ1 (mm)";
    io::PlotSeries t_s{"t0 against S0", {}, {}, "lines"}, t_h{"t0 against h", {}, {}, "lines"},
        d_s{"Δ1 against S0 (right)", {}, {}, "lines", true};
    const BoreMillingLimits& l = *c.bore_limits;
    for (int i = 1; i <= 200; ++i) {
      const double s = std::min(b.cutter_diameter_m, 3.0 * r.axial_feed_m) * i / 200.0;
      const double t = bore_milling_main_time(b, l, b.offset_m, s);
      if (std::isfinite(t)) {
        t_s.x.push_back(units::m_to_mm(s));
        t_s.y.push_back(t / 60.0);
      }
      try {
        const double d1 = straightness_error(b, s);
        d_s.x.push_back(units::m_to_mm(s));
        d_s.y.push_back(units::m_to_mm(d1));
      } catch (const InvalidInput&) {
      }
      const double h = l.offset_min_m + (l.offset_max_m - l.offset_min_m) * (i - 1) / 199.0;
      const double th = bore_milling_main_time(b, l, h, r.axial_feed_m);
      if (std::isfinite(th)) {
        t_h.x.push_back(units::m_to_mm(h));
        t_h.y.push_back(th / 60.0);
      }
    }
    spec.series = {t_s, t_h, d_s};
    io::write_plot(spec, args.plot, outputs);
  }
  commit_outputs(outputs, {"", args.json, args.plot}, out);
  return 0;
}

}  // namespace cutdyn::cli
