#include "cutdyn/stability/advice.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

namespace cutdyn {

namespace {

// The runs of points deeper than depth_m; `end(i, j)` places the end between the run's point i
// and the point j beyond it.
template <typename End>
std::vector<SpeedRange> runs_above(const std::vector<LobePoint>& p, double depth_m, End end) {
  std::vector<SpeedRange> ranges;
  const auto above = [&](std::size_t i) { return p[i].boundary.depth_m > depth_m; };
  for (std::size_t i = 0; i < p.size();) {
    if (!above(i)) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j + 1 < p.size() && above(j + 1)) ++j;
    ranges.push_back(
        {i == 0 ? p[0].rpm : end(i, i - 1), j + 1 == p.size() ? p[j].rpm : end(j, j + 1)});
    i = j + 1;
  }
  return ranges;
}

}  // namespace

std::vector<SpeedRange> stable_ranges(const std::vector<LobePoint>& p, double depth_m) {
  // Where the depth, linear between the two points, equals the target.
  return runs_above(p, depth_m, [&](std::size_t i, std::size_t j) {
    const double d0 = p[i].boundary.depth_m, d1 = p[j].boundary.depth_m;
    const double t = (depth_m - d0) / (d1 - d0);
    return p[i].rpm + std::clamp(t, 0.0, 1.0) * (p[j].rpm - p[i].rpm);
  });
}

std::vector<std::size_t> stable_pockets(const std::vector<LobePoint>& p, std::size_t count) {
  // The depth must fall by kPocketProminence of the peak on each side before the curve rises
  // above the peak again or ends: the searches' tolerance (0.1 %) lets the depths of a fine
  // grid wobble at a peak, and each wobble is a local maximum, not a pocket.
  const auto depth = [&](std::size_t i) { return p[i].boundary.depth_m; };
  const auto falls = [&](std::size_t i, int step) {
    const double floor = depth(i) * (1.0 - kPocketProminence);
    for (auto j = static_cast<std::ptrdiff_t>(i) + step;
         j >= 0 && j < static_cast<std::ptrdiff_t>(p.size()); j += step) {
      const double d = depth(static_cast<std::size_t>(j));
      if (d < floor) return true;
      if (d > depth(i)) return false;
    }
    return false;
  };
  std::vector<std::size_t> peaks;
  for (std::size_t i = 1; i + 1 < p.size(); ++i) {
    const double d = depth(i);
    if (d >= depth(i - 1) && d > depth(i + 1) && falls(i, -1) && falls(i, 1)) peaks.push_back(i);
  }
  std::stable_sort(peaks.begin(), peaks.end(), [&](std::size_t a, std::size_t b) {
    return p[a].boundary.depth_m > p[b].boundary.depth_m;
  });
  if (peaks.size() > count) peaks.resize(count);
  return peaks;
}

SpeedRange pocket_width(const std::vector<LobePoint>& p, std::size_t peak) {
  // The stable range at kPocketKeep of the peak's depth that holds the peak.
  for (const SpeedRange& r : stable_ranges(p, kPocketKeep * p[peak].boundary.depth_m))
    if (r.rpm_from <= p[peak].rpm && p[peak].rpm <= r.rpm_to) return r;
  return {p[peak].rpm, p[peak].rpm};
}

namespace {

// The margin ε of speed p[i] read off the points alone (0 or less: not stable at depth_m): the
// largest ε for which eq. MS-12 (docs/models/milling-stability.md) holds at every point.
double margin_on_points(const std::vector<LobePoint>& p, std::size_t i, double depth_m) {
  const double first = p.front().rpm, last = p.back().rpm;
  // ε allowed by point j seen from speed n: j is further than ε away in speed, or deep enough.
  const auto headroom = [&](std::size_t j) { return p[j].boundary.depth_m / depth_m - 1.0; };
  const double n = p[i].rpm;
  double eps = headroom(i);
  if (!(eps > 0.0)) return eps;
  eps = std::min({eps, (n - first) / n, (last - n) / n});
  // Walk outwards; once a neighbour is further than the ε found, none beyond can lower it.
  for (std::size_t j = i; j-- > 0;) {
    const double delta = (n - p[j].rpm) / n;
    if (delta >= eps) break;
    eps = std::min(eps, std::max(delta, headroom(j)));
  }
  for (std::size_t j = i + 1; j < p.size(); ++j) {
    const double delta = (p[j].rpm - n) / n;
    if (delta >= eps) break;
    eps = std::min(eps, std::max(delta, headroom(j)));
  }
  return eps;
}

}  // namespace

SpeedAdvice recommend_speed(const std::vector<LobePoint>& p, double depth_m) {
  SpeedAdvice best;
  if (p.empty() || !(depth_m > 0.0)) return best;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double n = p[i].rpm;
    const double eps = margin_on_points(p, i, depth_m);
    if (!(eps > 0.0)) continue;
    const bool better =
        !best.found || eps > best.margin ||
        (eps == best.margin && p[i].boundary.depth_m > p[best.index].boundary.depth_m);
    if (better) {
      best.found = true;
      best.index = i;
      best.rpm = n;
      best.margin = eps;
    }
  }
  if (best.found) {
    for (const SpeedRange& r : stable_ranges(p, depth_m))
      if (r.rpm_from <= best.rpm && best.rpm <= r.rpm_to) best.range = r;
  }
  return best;
}

// ---- the advice with its ends found (depths evaluated between the traced speeds) ----------

namespace {

LobePoint depth_point(double rpm, double depth_m) {
  LobePoint q;
  q.rpm = rpm;
  q.boundary.depth_m = depth_m;
  q.boundary.found = true;
  return q;
}

// The lowest depth over [lo, hi] by golden section, to rpm_tol·hi in speed: the cusp where two
// lobes meet (the depth falls to it from both sides: one minimum in the bracket).
LobePoint lowest_between(const CriticalDepthAt& depth_at, double lo, double hi, double rpm_tol) {
  const double inv_phi = (std::sqrt(5.0) - 1.0) / 2.0;
  double a = lo, b = hi;
  double x1 = b - inv_phi * (b - a), x2 = a + inv_phi * (b - a);
  double f1 = depth_at(x1), f2 = depth_at(x2);
  while (b - a > rpm_tol * hi) {
    if (f1 <= f2) {
      b = x2;
      x2 = x1;
      f2 = f1;
      x1 = b - inv_phi * (b - a);
      f1 = depth_at(x1);
    } else {
      a = x1;
      x1 = x2;
      f1 = f2;
      x2 = a + inv_phi * (b - a);
      f2 = depth_at(x2);
    }
  }
  return f1 <= f2 ? depth_point(x1, f1) : depth_point(x2, f2);
}

// The points with the cusp of every local minimum above depth_m added (a minimum at or below
// it is unstable already), ascending in speed; `traced[k]` tells the given points.
struct Resolved {
  std::vector<LobePoint> points;
  std::vector<std::size_t> index;  // into the given points; SIZE_MAX for an added one
};

Resolved with_cusps(const std::vector<LobePoint>& p, double depth_m,
                    const CriticalDepthAt& depth_at, double rpm_tol) {
  const auto depth = [&](std::size_t i) { return p[i].boundary.depth_m; };
  std::vector<LobePoint> added;
  for (std::size_t i = 0; i < p.size() && p.size() >= 2; ++i) {
    const bool left = i == 0 || depth(i) <= depth(i - 1);
    const bool right = i + 1 == p.size() || depth(i) <= depth(i + 1);
    const bool flat =
        (i == 0 || depth(i) == depth(i - 1)) && (i + 1 == p.size() || depth(i) == depth(i + 1));
    if (!(depth(i) > depth_m) || !left || !right || flat) continue;
    added.push_back(lowest_between(depth_at, p[i == 0 ? 0 : i - 1].rpm,
                                   p[i + 1 == p.size() ? i : i + 1].rpm, rpm_tol));
  }
  Resolved r;
  std::size_t a = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (; a < added.size() && added[a].rpm < p[i].rpm; ++a) {
      if (!r.points.empty() && r.points.back().rpm >= added[a].rpm) continue;
      r.points.push_back(added[a]);
      r.index.push_back(SIZE_MAX);
    }
    r.points.push_back(p[i]);
    r.index.push_back(i);
  }
  return r;
}

// The speed between a stable one (depth above depth_m) and an unstable one where the depth
// falls to depth_m, by bisection to rpm_tol of the speed: its stable side.
double crossing_between(const CriticalDepthAt& depth_at, double depth_m, double stable_rpm,
                        double unstable_rpm, double rpm_tol) {
  double s = stable_rpm, u = unstable_rpm;
  while (std::abs(u - s) > rpm_tol * std::max(s, u)) {
    const double m = 0.5 * (s + u);
    (depth_at(m) > depth_m ? s : u) = m;
  }
  return s;
}

std::vector<SpeedRange> ranges_found(const std::vector<LobePoint>& p, double depth_m,
                                     const CriticalDepthAt& depth_at, double rpm_tol) {
  return runs_above(p, depth_m, [&](std::size_t i, std::size_t j) {
    return crossing_between(depth_at, depth_m, p[i].rpm, p[j].rpm, rpm_tol);
  });
}

}  // namespace

std::vector<SpeedRange> stable_ranges(const std::vector<LobePoint>& points, double depth_m,
                                      const CriticalDepthAt& depth_at, double rpm_tol) {
  if (points.empty()) return {};
  return ranges_found(with_cusps(points, depth_m, depth_at, rpm_tol).points, depth_m, depth_at,
                      rpm_tol);
}

SpeedAdvice recommend_speed(const std::vector<LobePoint>& points, double depth_m,
                            const CriticalDepthAt& depth_at, double rpm_tol) {
  // The candidates are the traced speeds, best first by the margin the points alone give; the
  // margin of each is then found — the largest ε at which the depths at n·(1 ± ε), and at
  // every point between (the cusps included), are at least depth_m·(1 + ε), eq. MS-12
  // (docs/models/milling-stability.md) — until no candidate left can beat the best found (the
  // points' margin is about an upper bound: it does not see a flank falling between two
  // points).
  constexpr int kMaxCandidates = 8;
  SpeedAdvice best;
  if (points.empty() || !(depth_m > 0.0)) return best;
  const Resolved r = with_cusps(points, depth_m, depth_at, rpm_tol);
  const std::vector<LobePoint>& p = r.points;
  const double first = p.front().rpm, last = p.back().rpm;
  std::vector<std::pair<double, std::size_t>> candidates;
  for (std::size_t k = 0; k < p.size(); ++k)
    if (r.index[k] != SIZE_MAX)
      if (const double eps = margin_on_points(p, k, depth_m); eps > 0.0)
        candidates.emplace_back(eps, k);
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const auto& x, const auto& y) { return x.first > y.first; });
  // Whether eq. MS-12 holds for ε at n = p[k]: every point within n·(1 ± ε), and the depths
  // at both ends, at least depth_m·(1 + ε).
  const auto holds = [&](std::size_t k, double eps) {
    const double n = p[k].rpm, floor = depth_m * (1.0 + eps);
    for (const LobePoint& q : p)
      if (std::abs(q.rpm - n) <= eps * n && q.boundary.depth_m < floor) return false;
    return depth_at(n * (1.0 - eps)) >= floor && depth_at(n * (1.0 + eps)) >= floor;
  };
  int tried = 0;
  for (const auto& [traced, k] : candidates) {
    if ((best.found && traced <= best.margin) || tried++ == kMaxCandidates) break;
    const double n = p[k].rpm;
    double lo = 0.0;
    double hi = std::min({p[k].boundary.depth_m / depth_m - 1.0, (n - first) / n, (last - n) / n});
    if (holds(k, hi)) {
      lo = hi;
    } else {
      while (hi - lo > rpm_tol) {
        const double mid = 0.5 * (lo + hi);
        (holds(k, mid) ? lo : hi) = mid;
      }
    }
    const bool better =
        !best.found || lo > best.margin ||
        (lo == best.margin && p[k].boundary.depth_m > points[best.index].boundary.depth_m);
    if (lo > 0.0 && better) {
      best.found = true;
      best.index = r.index[k];
      best.rpm = n;
      best.margin = lo;
    }
  }
  if (best.found) {
    for (const SpeedRange& range : ranges_found(p, depth_m, depth_at, rpm_tol))
      if (range.rpm_from <= best.rpm && best.rpm <= range.rpm_to) best.range = range;
  }
  return best;
}

}  // namespace cutdyn
