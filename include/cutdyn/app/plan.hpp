// The plan job: two-edge face milling of a large bore — the largest axial feed for the
// straightness limit, the allowance split, the chip, the main time; with [limits], the
// offset, feed and speeds of the shortest main time, and the trade-off around the plan.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cutdyn/app/request.hpp"
#include "cutdyn/io/case_file.hpp"
#include "cutdyn/plan/bore_milling.hpp"

namespace cutdyn::app {

struct PlanRequest {
  std::optional<double> axial_feed_m;  // a fixed S0 (else the case's, else the largest)
  RequestNames names;
  std::string axial_feed_name = "axial_feed_mm";  // how the front end calls it
};

/// A curve of the trade-off: x (m) against y (s for the main time, m for Δ1); infeasible
/// points are left out.
struct PlanCurve {
  std::vector<double> x, y;
};
struct PlanTradeOff {
  PlanCurve time_against_feed;          // t0(S0) at the chosen h, S0 up to min(D, 3·S0)
  PlanCurve time_against_offset;        // t0(h) at the chosen S0, h over the [limits] range
  PlanCurve straightness_against_feed;  // Δ1(S0)
};

struct PlanJobReport {
  BoreMillingCase chosen;  // the case's, or the optimiser's choice within [limits]
  BoreMillingResult result;
  std::optional<BoreMillingPlan> plan;  // when [limits] optimised it
  bool feed_given = false;              // S0 from the request or the case
  std::string where;                    // where the warnings belong (the case or the request)
  // (printed − corrected)/corrected of the largest axial feed, percent (docs/models/
  // bore-milling.md: eq. 4 as printed against its correction).
  double printed_form_difference_percent = 0.0;
  std::vector<std::string> warnings;
  std::optional<PlanTradeOff> trade_off;  // with [limits]
};

/// Throws cutdyn::InvalidInput naming the case or the request.
PlanJobReport run_plan(const io::Case& c, const PlanRequest& request);

}  // namespace cutdyn::app
