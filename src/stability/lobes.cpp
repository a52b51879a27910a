#include "cutdyn/stability/lobes.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <limits>
#include <mutex>

#include "cutdyn/core/detail/parallel.hpp"
#include "cutdyn/core/detail/roots.hpp"
#include "cutdyn/core/error.hpp"

namespace cutdyn {

// 0 to kMaxThreads, with the rule the other front ends print for threads.
constexpr FieldRange threads_range() {
  static_assert(kMaxThreads == 1024, "the rule text below names the limit");
  FieldRange r = FieldRange::closed(0, kMaxThreads);
  r.rule_text = "must be 0 (all cores) to 1024";
  return r;
}

std::span<const Field<LobesOptions>> LobesOptions::fields() {
  using R = FieldRange;
  static const Field<LobesOptions> list[] = {
      {"rpm_min", FieldType::kNumber, fields::unit("rpm"), R::positive(), &LobesOptions::rpm_min,
       "lowest spindle speed", ""},
      {"rpm_max", FieldType::kNumber, fields::unit("rpm"), R::positive(), &LobesOptions::rpm_max,
       "highest spindle speed", "greater than `rpm_min`"},
      {"rpm_steps", FieldType::kInteger, fields::kNone, R::closed(2, 100000),
       &LobesOptions::rpm_steps, "spindle speeds", ""},
      {"threads", FieldType::kInteger, fields::kNone, threads_range(), &LobesOptions::threads,
       "threads", "0: all cores"},
      {"refine", FieldType::kBoolean, fields::kNone, R::any(), &LobesOptions::refine, "",
       "add speeds where lobes meet or are narrower than the grid (adaptive tracing); false: "
       "the uniform grid only"},
      {"refine_levels", FieldType::kInteger, fields::kNone, R::closed(0, 20),
       &LobesOptions::refine_levels, "refinement levels",
       "how many times the refinement may halve a grid interval (the finest spacing is the "
       "grid's over 2^levels); 0: the uniform grid only"},
      {"refine_change", FieldType::kNumber, fields::kNone, R::open_closed(0.0, 10.0),
       &LobesOptions::refine_change, "refinement threshold",
       "relative change of the depth between neighbours that refines"},
      {"refine_max_points", FieldType::kInteger, fields::kNone, R::closed(2, 10000000),
       &LobesOptions::refine_max_points, "speeds at most", "at least `rpm_steps` when refining"},
  };
  return list;
}

std::vector<std::string> LobesOptions::validate() const {
  Validator v;
  check_fields(*this, fields(), v);
  v.require(rpm_max > rpm_min, "rpm_max", rpm_max, "rpm",
            "must be greater than rpm_min = " + format_value(rpm_min));
  v.require(!refine || refine_max_points >= rpm_steps, "refine_max_points", refine_max_points,
            "", "must be at least rpm_steps when refining");
  return v.problems();
}

std::vector<double> LobesOptions::speeds_rpm() const {
  std::vector<double> s(static_cast<std::size_t>(rpm_steps));
  for (int i = 0; i < rpm_steps; ++i)
    s[static_cast<std::size_t>(i)] = rpm_min + (rpm_max - rpm_min) * i / (rpm_steps - 1);
  return s;
}

namespace {

// Whether the boundary between two neighbouring speeds needs a speed in between: a change of
// lobe or of bifurcation type (a cusp — the peak of a stable pocket — lies between them), or a
// relative change of the critical depth larger than `change` (a lobe narrower than the step).
bool needs_refinement(const LobePoint& a, const LobePoint& b, double change) {
  if (a.boundary.found != b.boundary.found) return true;
  if (!a.boundary.found) return false;  // stable to the limit on both sides
  if (a.lobe != b.lobe || a.boundary.bifurcation != b.boundary.bifurcation) return true;
  const double da = a.boundary.depth_m, db = b.boundary.depth_m;
  return std::abs(da - db) > change * std::min(da, db);
}

}  // namespace

namespace {

void add_points(const std::function<LobePoint(double)>& at_speed, const std::vector<double>& rpm,
                int threads, std::vector<LobePoint>& points) {
  std::vector<LobePoint> fresh(rpm.size());
  parallel_for(static_cast<int>(rpm.size()), threads, [&](int i) {
    fresh[static_cast<std::size_t>(i)] = at_speed(rpm[static_cast<std::size_t>(i)]);
  });
  std::vector<LobePoint> merged;
  merged.reserve(points.size() + fresh.size());
  std::merge(points.begin(), points.end(), fresh.begin(), fresh.end(), std::back_inserter(merged),
             [](const LobePoint& x, const LobePoint& y) { return x.rpm < y.rpm; });
  points = std::move(merged);
}

}  // namespace

void complete_lobes(const std::function<LobePoint(double)>& at_speed,
                    const std::vector<LobePoint>& other, std::vector<LobePoint>& points,
                    int threads) {
  std::vector<double> missing;
  std::size_t k = 0;
  for (const LobePoint& q : other) {
    while (k < points.size() && points[k].rpm < q.rpm) ++k;
    if (k == points.size() || points[k].rpm != q.rpm) missing.push_back(q.rpm);
  }
  if (!missing.empty()) add_points(at_speed, missing, threads, points);
}

namespace {

// The refinement with each added speed computed by `add(rpm, a, b)` from its two neighbours.
void refine_with(const std::function<LobePoint(double, const LobePoint&, const LobePoint&)>& add,
                 const LobesOptions& o, std::vector<LobePoint>& points) {
  // Narrowest interval worth halving: 1e-5 of the speed (a cusp located to that).
  constexpr double kNarrowest = 1e-5;
  for (int level = 0; level < o.refine_levels; ++level) {
    std::vector<std::size_t> left;  // index of the left neighbour of each added speed
    for (std::size_t i = 0; i + 1 < points.size(); ++i) {
      const LobePoint& a = points[i];
      const LobePoint& b = points[i + 1];
      if (b.rpm - a.rpm > kNarrowest * b.rpm && needs_refinement(a, b, o.refine_change))
        left.push_back(i);
    }
    const std::size_t room = static_cast<std::size_t>(o.refine_max_points) - points.size();
    if (left.empty() || room == 0) return;
    if (left.size() > room) left.resize(room);
    std::vector<LobePoint> fresh(left.size());
    parallel_for(static_cast<int>(left.size()), o.threads, [&](int k) {
      const LobePoint& a = points[left[static_cast<std::size_t>(k)]];
      const LobePoint& b = points[left[static_cast<std::size_t>(k)] + 1];
      fresh[static_cast<std::size_t>(k)] = add(0.5 * (a.rpm + b.rpm), a, b);
    });
    std::vector<LobePoint> merged;
    merged.reserve(points.size() + fresh.size());
    std::merge(points.begin(), points.end(), fresh.begin(), fresh.end(), std::back_inserter(merged),
               [](const LobePoint& x, const LobePoint& y) { return x.rpm < y.rpm; });
    points = std::move(merged);
  }
}

// Totals, warnings and time of a traced report.
void finish_report(LobesReport& report, std::chrono::steady_clock::time_point start) {
  std::string unresolved, truncated, unconverged;
  int unresolved_count = 0, truncated_count = 0, unconverged_count = 0;
  const auto list = [](std::string& text, int& count, double rpm) {
    if (++count <= 10) text += (text.empty() ? "" : ", ") + format_value(rpm);
  };
  for (const LobePoint& p : report.points) {
    report.evaluations += p.boundary.evaluations;
    if (p.boundary.unresolved > 0) list(unresolved, unresolved_count, p.rpm);
    if (p.boundary.truncated) list(truncated, truncated_count, p.rpm);
    if (p.boundary.unconverged) list(unconverged, unconverged_count, p.rpm);
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
  if (unconverged_count > 0) {
    if (report.status == LobesStatus::kSuccess) report.status = LobesStatus::kTruncated;
    report.message += (report.message.empty() ? "" : "; ") + std::to_string(unconverged_count) +
                      " speed(s) where the critical depth still moved by more than the "
                      "tolerance when the time step was halved (it may be off by more; raise "
                      "the refinements or lower the step): " +
                      unconverged + (unconverged_count > 10 ? ", ..." : "") + " rpm";
  }
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

void refine_lobes(const std::function<LobePoint(double)>& at_speed, const LobesOptions& o,
                  std::vector<LobePoint>& points) {
  refine_with([&](double rpm, const LobePoint&, const LobePoint&) { return at_speed(rpm); }, o,
              points);
}

namespace {

// The report of the options' speeds, its points to be filled.
LobesReport empty_report(const LobesOptions& o, const std::vector<double>& speeds) {
  LobesReport report;
  report.options = o;
  report.points.resize(speeds.size());
  return report;
}

}  // namespace

LobesReport trace_lobes(const std::function<LobePoint(double)>& at_speed, const LobesOptions& o,
                        const std::function<void(int, int)>& progress) {
  if (const auto problems = o.validate(); !problems.empty()) throw InvalidInput(problems, "lobes");
  const auto start = std::chrono::steady_clock::now();
  const std::vector<double> speeds = o.speeds_rpm();
  const int n = static_cast<int>(speeds.size());
  LobesReport report = empty_report(o, speeds);
  parallel_for(
      n, o.threads,
      [&](int i) {
        report.points[static_cast<std::size_t>(i)] = at_speed(speeds[static_cast<std::size_t>(i)]);
      },
      progress);
  if (o.refine) refine_lobes(at_speed, o, report.points);
  finish_report(report, start);
  return report;
}

std::vector<int> warm_run_starts(const std::vector<double>& speeds_rpm) {
  const int n = static_cast<int>(speeds_rpm.size());
  const int runs = std::clamp(n / kWarmRunLength, 1, std::max(n, 1));
  double total = 0.0;
  for (double rpm : speeds_rpm) total += 1.0 / rpm;
  // The cumulative shares where runs end: equal ones, the last cut in kWarmTailRuns (the
  // threads take the runs in order as they come free, and short last runs let them finish
  // together: the runs' true costs differ by up to 3× on the default milling lobes).
  std::vector<double> ends;
  for (int k = 1; k < runs; ++k) ends.push_back(static_cast<double>(k) / runs);
  if (runs > 1) {
    for (int k = 1; k < kWarmTailRuns; ++k)
      ends.push_back((runs - 1 + static_cast<double>(k) / kWarmTailRuns) / runs);
  }
  std::vector<int> starts{0};
  double sum = 0.0;
  std::size_t next = 0;
  for (int i = 0; i + 1 < n && next < ends.size(); ++i) {
    sum += 1.0 / speeds_rpm[static_cast<std::size_t>(i)];
    if (sum >= total * ends[next]) {
      starts.push_back(i + 1);
      while (next < ends.size() && sum >= total * ends[next]) ++next;
    }
  }
  starts.push_back(n);
  return starts;
}

LobesReport trace_lobes_warm(const WarmSpeedFunction& at_speed, const LobesOptions& o,
                             const std::function<void(int, int)>& progress) {
  if (const auto problems = o.validate(); !problems.empty()) throw InvalidInput(problems, "lobes");
  const auto start = std::chrono::steady_clock::now();
  const std::vector<double> speeds = o.speeds_rpm();
  const int n = static_cast<int>(speeds.size());
  LobesReport report = empty_report(o, speeds);
  // Runs of consecutive speeds, cut where the estimated cost (the period, 1/rpm) reaches equal
  // shares, from the speeds alone: the points never depend on the number of threads.
  const std::vector<int> starts = warm_run_starts(speeds);
  const int runs = static_cast<int>(starts.size()) - 1;
  std::mutex mutex;
  int done = 0;
  parallel_for(runs, o.threads, [&](int run) {
    const int first = starts[static_cast<std::size_t>(run)];
    const int last = starts[static_cast<std::size_t>(run + 1)];
    std::vector<const LobePoint*> near;
    for (int i = first; i < last; ++i) {
      near.clear();
      if (i - 1 >= first) near.push_back(&report.points[static_cast<std::size_t>(i - 1)]);
      if (i - 2 >= first) near.push_back(&report.points[static_cast<std::size_t>(i - 2)]);
      if (i - 3 >= first) near.push_back(&report.points[static_cast<std::size_t>(i - 3)]);
      report.points[static_cast<std::size_t>(i)] =
          at_speed(speeds[static_cast<std::size_t>(i)], near);
      if (progress) {
        std::lock_guard<std::mutex> lock(mutex);
        progress(++done, n);
      }
    }
  });
  if (o.refine) {
    refine_with(
        [&](double rpm, const LobePoint& a, const LobePoint& b) {
          return at_speed(rpm, std::vector<const LobePoint*>{&a, &b});
        },
        o, report.points);
  }
  finish_report(report, start);
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
  // g_lo < 0 <= g_hi: the bracket changes sign, so Brent's method returns a root, to rel_tol
  // times the grid point hi above it (eq. MS-15, docs/models/milling-stability.md).
  auto root = brent_root(margin, lo, g_lo, hi, g_hi, rel_tol * hi);
  result.found = true;
  result.depth_m = root ? root->x : hi;
  if (root) result.evaluations += root->evaluations;
  // A boundary far below the first grid point gets only the cell's absolute tolerance,
  // rel_tol·hi: a structure of 20 N/m, whose boundary is at 1e-9 m in a first cell of 6e-5 m,
  // came back as 0. Below hi/8 the bracket is narrowed by factors of 8 from the top until its
  // lower end is stable, and searched again to rel_tol of that lower end (so to rel_tol of
  // the boundary); boundary_tolerance() states the same rule for the warm-started search.
  if (lo == 0.0 && result.depth_m < hi / 8.0) {
    double top = hi, g_top = g_hi;
    while (top > std::numeric_limits<double>::min()) {
      const double w = top / 8.0;
      const double g = margin(w);
      ++result.evaluations;
      if (g >= 0.0) {
        top = w;
        g_top = g;
        continue;
      }
      root = brent_root(margin, w, g, top, g_top, rel_tol * w);
      result.depth_m = root ? root->x : top;
      if (root) result.evaluations += root->evaluations;
      return result;
    }
    result.depth_m = 0.0;  // unstable down to the smallest double: as unstable without cutting
  }
  return result;
}

// Eq. MS-15 (docs/models/milling-stability.md) from an eighth of the first grid point up; below
// it, rel_tol times the lower end of the bracket narrowed by factors of 8.
double boundary_tolerance(double depth_m, double depth_max_m, int coarse_steps, double rel_tol) {
  const double cell = depth_max_m / coarse_steps;
  if (depth_m >= cell / 8.0) return rel_tol * cell * std::ceil(depth_m / cell - 1e-9);
  double top = cell / 8.0;
  while (top / 8.0 >= depth_m && top > std::numeric_limits<double>::min()) top /= 8.0;
  return rel_tol * top / 8.0;
}

}  // namespace cutdyn
