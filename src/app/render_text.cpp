#include "cutdyn/app/detail/render_text.hpp"

#include "cutdyn/app/detail/text.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn::app {

std::string depth_text(const CriticalDepth& b) {
  const std::string mm = human(units::m_to_mm(b.depth_m)) + " mm";
  return b.found ? mm : "> " + mm;
}

}  // namespace cutdyn::app
