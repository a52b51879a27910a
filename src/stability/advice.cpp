#include "cutdyn/stability/advice.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cutdyn {

std::vector<SpeedRange> stable_ranges(const std::vector<LobePoint>& p, double depth_m) {
  std::vector<SpeedRange> ranges;
  const auto above = [&](std::size_t i) { return p[i].boundary.depth_m > depth_m; };
  // Where the depth, linear between points i and i + 1, equals the target.
  const auto crossing = [&](std::size_t i) {
    const double d0 = p[i].boundary.depth_m, d1 = p[i + 1].boundary.depth_m;
    const double t = (depth_m - d0) / (d1 - d0);
    return p[i].rpm + std::clamp(t, 0.0, 1.0) * (p[i + 1].rpm - p[i].rpm);
  };
  for (std::size_t i = 0; i < p.size();) {
    if (!above(i)) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j + 1 < p.size() && above(j + 1)) ++j;
    ranges.push_back(
        {i == 0 ? p[0].rpm : crossing(i - 1), j + 1 == p.size() ? p[j].rpm : crossing(j)});
    i = j + 1;
  }
  return ranges;
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

SpeedAdvice recommend_speed(const std::vector<LobePoint>& p, double depth_m) {
  SpeedAdvice best;
  if (p.empty() || !(depth_m > 0.0)) return best;
  const double first = p.front().rpm, last = p.back().rpm;
  // ε allowed by point j seen from speed n: j is further than ε away in speed, or deep enough.
  const auto headroom = [&](std::size_t j) { return p[j].boundary.depth_m / depth_m - 1.0; };
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double n = p[i].rpm;
    double eps = headroom(i);
    if (!(eps > 0.0)) continue;
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

}  // namespace cutdyn
