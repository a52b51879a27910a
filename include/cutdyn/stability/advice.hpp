// What a process engineer reads off the lobes: the speed ranges stable at a target depth,
// the stable pockets, and the speed to recommend. Rules live here, so every front end gives
// the same advice; docs/models/milling-stability.md ("Advice").
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "cutdyn/stability/lobes.hpp"

namespace cutdyn {

struct SpeedRange {
  double rpm_from = 0.0;
  double rpm_to = 0.0;
};

/// Speed ranges where the critical depth exceeds `depth_m`, ascending. An end between two
/// speeds of the lobes is placed where the depth, linear between them, equals `depth_m`; a
/// range that runs to the first or last speed ends there.
std::vector<SpeedRange> stable_ranges(const std::vector<LobePoint>& points, double depth_m);

/// How far (relative) the critical depth must fall on both sides of a local maximum for it to
/// be a stable pocket: 10 %. A smaller dip is a notch in a lobe's flank (or the wobble of the
/// depth searches' 0.1 % tolerance at a peak), not a pocket: the cut there is as deep a little
/// faster or slower.
inline constexpr double kPocketProminence = 0.10;

/// The width a pocket is stated with: the speeds around it where the critical depth is at
/// least kPocketKeep of the peak's.
inline constexpr double kPocketKeep = 0.9;

/// Indices of the stable pockets — local maxima of the critical depth, the peaks between two
/// lobes, from which the depth falls by kPocketProminence on each side before it rises above
/// the peak again or the speeds end — deepest first, at most `count`.
std::vector<std::size_t> stable_pockets(const std::vector<LobePoint>& points, std::size_t count);

/// The speeds around point `peak` where the critical depth, linear between the points, is at
/// least kPocketKeep of the peak's (up to the first or last speed).
SpeedRange pocket_width(const std::vector<LobePoint>& points, std::size_t peak);

/// The recommended speed for a target depth a and its margin ε: the largest ε such that
/// every speed within n·(1 ± ε) has a critical depth of at least a·(1 + ε) — the cut stays
/// stable with the speed (or the lobes, through the natural frequency) off by ε either way
/// and the depth (or the cutting coefficient) ε larger. Speeds outside the lobes' range are
/// unknown, so ε never reaches past it. The recommended speed maximises ε (ties: the deeper
/// critical depth). A speed just inside a narrow band, or next to a cliff, has a small ε.
struct SpeedAdvice {
  bool found = false;     // false: no speed of the lobes is stable at the target depth
  std::size_t index = 0;  // into the points
  double rpm = 0.0;
  double margin = 0.0;  // ε
  SpeedRange range;     // the stable range that holds it
};

SpeedAdvice recommend_speed(const std::vector<LobePoint>& points, double depth_m);

/// The critical depth at any speed, m, computed as the lobes' points were (their search's
/// limit where it finds no boundary): what the advice below asks between the traced speeds.
using CriticalDepthAt = std::function<double(double rpm)>;

/// The advice with its ends found rather than read off the traced speeds (docs/models/
/// milling-stability.md, "Advice"): between two traced speeds the depth is not linear — a cusp
/// between two lobes dips below both neighbours. Every local minimum of the traced depths above
/// `depth_m` is searched on the speeds about it (golden section), each end of a stable range
/// where the depth equals `depth_m` by bisection on the speed, and the recommended speed's ε by
/// bisection on ε with the depths at n·(1 ± ε) evaluated; each to a relative `rpm_tol` of the
/// speed. The margin then holds over the whole interval up to the depth searches' tolerance.
std::vector<SpeedRange> stable_ranges(const std::vector<LobePoint>& points, double depth_m,
                                      const CriticalDepthAt& depth_at, double rpm_tol = 1e-4);
SpeedAdvice recommend_speed(const std::vector<LobePoint>& points, double depth_m,
                            const CriticalDepthAt& depth_at, double rpm_tol = 1e-4);

}  // namespace cutdyn
