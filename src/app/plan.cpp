#include "cutdyn/app/plan.hpp"

#include <algorithm>
#include <cmath>

#include "cutdyn/app/detail/text.hpp"
#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn::app {
namespace {

PlanTradeOff trade_off(const BoreMillingCase& b, const BoreMillingLimits& l, double s0) {
  PlanTradeOff t;
  for (int i = 1; i <= 200; ++i) {
    const double s = std::min(b.cutter_diameter_m, 3.0 * s0) * i / 200.0;
    if (const double time = bore_milling_main_time(b, l, b.offset_m, s); std::isfinite(time)) {
      t.time_against_feed.x.push_back(s);
      t.time_against_feed.y.push_back(time);
    }
    try {
      const double d1 = straightness_error(b, s);
      t.straightness_against_feed.x.push_back(s);
      t.straightness_against_feed.y.push_back(d1);
    } catch (const InvalidInput&) {
      // beyond the cutter: no point
    }
    const double h = l.offset_min_m + (l.offset_max_m - l.offset_min_m) * (i - 1) / 199.0;
    if (const double time = bore_milling_main_time(b, l, h, s0); std::isfinite(time)) {
      t.time_against_offset.x.push_back(h);
      t.time_against_offset.y.push_back(time);
    }
  }
  return t;
}

}  // namespace

PlanJobReport run_plan(const io::Case& c, const PlanRequest& request) {
  if (!c.bore) {
    throw InvalidInput({"process = \"" + std::string(io::to_string(c.process)) +
                        "\": `cutdyn plan` takes a bore-milling case ([bore], [cutter] and a "
                        "[process] table)"},
                       c.source);
  }
  PlanJobReport r;
  double s0 = c.axial_feed_m.value_or(0.0);
  r.where = c.source;
  if (request.axial_feed_m) {
    if (!(*request.axial_feed_m > 0.0))
      throw InvalidInput({request.axial_feed_name + " = " +
                          human(units::m_to_mm(*request.axial_feed_m)) + ": must be positive"},
                         request.names.where);
    s0 = *request.axial_feed_m;
    r.where = request.names.where;
  }
  r.feed_given = s0 > 0.0;
  r.chosen = *c.bore;
  if (c.bore_limits && s0 == 0.0) {
    // [limits]: choose h, S0, n_u and n_o for the shortest main time.
    rethrow_as(c.source, "plan", [&] { r.plan = optimise_bore_milling(r.chosen, *c.bore_limits); });
    if (!r.plan->feasible) throw InvalidInput({"limits: " + r.plan->reason}, c.source);
    r.chosen = r.plan->chosen;
    r.result = r.plan->result;
  } else {
    rethrow_as(r.where, "plan", [&] { r.result = bore_milling(r.chosen, s0); });
  }
  const BoreMillingResult& b = r.result;
  r.printed_form_difference_percent =
      100.0 * (b.max_axial_feed_printed_form_m - b.max_axial_feed_m) / b.max_axial_feed_m;
  r.warnings = b.warnings;
  // [limits] with a fixed feed: the optimiser does not run (the plan is at the case's h and
  // speeds); said, not left silent. The trade-off is still drawn within the limits.
  if (c.bore_limits && !r.plan)
    r.warnings.push_back(
        "[limits] not used to optimise: the axial feed is given (" +
        (request.axial_feed_m ? request.axial_feed_name : std::string("process.axial_feed_mm")) +
        "), so the plan is at the case's offset h and cutting speed; leave the feed out to "
        "optimise");
  if (c.bore_limits) r.trade_off = trade_off(r.chosen, *c.bore_limits, b.axial_feed_m);
  return r;
}

}  // namespace cutdyn::app
