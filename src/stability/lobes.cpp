#include "cutdyn/stability/lobes.hpp"

#include <chrono>
#include <cmath>
#include <limits>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/parallel.hpp"
#include "cutdyn/core/roots.hpp"

namespace cutdyn {

std::vector<std::string> LobesOptions::validate() const {
  Validator v;
  v.require_positive("rpm_min", rpm_min, "rpm");
  v.require(rpm_max > rpm_min, "rpm_max", rpm_max, "rpm",
            "must be greater than rpm_min = " + format_value(rpm_min));
  v.require(rpm_steps >= 2 && rpm_steps <= 100000, "rpm_steps", rpm_steps, "",
            "must be 2 to 100000");
  v.require(threads >= 0, "threads", threads, "", "must not be negative");
  return v.problems();
}

std::vector<double> LobesOptions::speeds_rpm() const {
  std::vector<double> s(static_cast<std::size_t>(rpm_steps));
  for (int i = 0; i < rpm_steps; ++i)
    s[static_cast<std::size_t>(i)] = rpm_min + (rpm_max - rpm_min) * i / (rpm_steps - 1);
  return s;
}

LobesReport trace_lobes(const std::function<LobePoint(double)>& at_speed, const LobesOptions& o,
                        const std::function<void(int, int)>& progress) {
  if (const auto problems = o.validate(); !problems.empty()) throw InvalidInput(problems, "lobes");
  const auto start = std::chrono::steady_clock::now();
  const std::vector<double> speeds = o.speeds_rpm();
  const int n = static_cast<int>(speeds.size());
  LobesReport report;
  report.options = o;
  report.points.resize(speeds.size());
  parallel_for(
      n, o.threads,
      [&](int i) {
        report.points[static_cast<std::size_t>(i)] = at_speed(speeds[static_cast<std::size_t>(i)]);
      },
      progress);
  std::string unresolved, truncated;
  int unresolved_count = 0, truncated_count = 0;
  const auto list = [](std::string& text, int& count, double rpm) {
    if (++count <= 10) text += (text.empty() ? "" : ", ") + format_value(rpm);
  };
  for (const LobePoint& p : report.points) {
    report.evaluations += p.boundary.evaluations;
    if (p.boundary.unresolved > 0) list(unresolved, unresolved_count, p.rpm);
    if (p.boundary.truncated) list(truncated, truncated_count, p.rpm);
  }
  if (unresolved_count > 0) {
    report.status = LobesStatus::kUnresolvedCrossings;
    report.message = std::to_string(unresolved_count) +
                     " speed(s) with a boundary candidate that could not be resolved (the "
                     "critical depth there may be too large): " +
                     unresolved + (unresolved_count > 10 ? ", ..." : "") + " rpm";
  }
  if (truncated_count > 0) {
    if (report.status == LobesStatus::kSuccess) report.status = LobesStatus::kTruncated;
    report.message += (report.message.empty() ? "" : "; ") + std::to_string(truncated_count) +
                      " speed(s) where the method could not cover every mode (the critical "
                      "depth there may be wrong; use the full discretization): " +
                      truncated + (truncated_count > 10 ? ", ..." : "") + " rpm";
  }
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

CriticalDepth critical_depth_by_bracketing(const std::function<double(double)>& margin,
                                           double depth_max_m, int coarse_steps, double rel_tol) {
  CriticalDepth result;
  result.depth_m = depth_max_m;
  double lo = 0.0, hi = -1.0, g_hi = 0.0;
  double g_lo = std::numeric_limits<double>::quiet_NaN();  // not evaluated yet
  for (int i = 1; i <= coarse_steps; ++i) {
    const double w = depth_max_m * i / coarse_steps;
    const double g = margin(w);
    ++result.evaluations;
    if (g >= 0.0) {
      hi = w;
      g_hi = g;
      break;
    }
    lo = w;
    g_lo = g;
  }
  if (hi < 0.0) return result;
  if (std::isnan(g_lo)) {
    g_lo = margin(lo);
    ++result.evaluations;
    if (g_lo >= 0.0) {  // unstable without cutting: nothing to find
      result.depth_m = 0.0;
      result.found = true;
      return result;
    }
  }
  // g_lo < 0 <= g_hi: the bracket changes sign, so Brent's method returns a root.
  const auto root = brent_root(margin, lo, g_lo, hi, g_hi, rel_tol * hi);
  result.found = true;
  result.depth_m = root ? root->x : hi;
  if (root) result.evaluations += root->evaluations;
  return result;
}

}  // namespace cutdyn
