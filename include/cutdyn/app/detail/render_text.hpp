// Pieces of wording the renderers of the reports share (cutdyn/app/render.hpp): the
// critical depth in words and the axis of a swept metric in a figure.
#pragma once

#include <string>

#include "cutdyn/stability/critical_depth.hpp"

namespace cutdyn::app {

/// "6.736 mm", or "> 30 mm" when no boundary was found below the limit.
std::string depth_text(const CriticalDepth& b);

/// A metric's axis in a figure: its name in words, the unit it is drawn in ("" for a
/// number without one) and the factor from the metric's value to that unit.
struct MetricAxis {
  std::string name, unit;
  double scale = 1.0;
  std::string label() const { return unit.empty() ? name : name + " (" + unit + ")"; }
};

}  // namespace cutdyn::app
