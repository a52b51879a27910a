#include "cutdyn/app/detail/text.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace cutdyn::app {

std::string human(double value, int digits) {
  const double magnitude = std::abs(value);
  if (magnitude >= 1.0 && magnitude < 1e9)
    digits = std::max(digits, static_cast<int>(std::floor(std::log10(magnitude))) + 1);
  std::ostringstream s;
  s << std::setprecision(digits) << value;
  return s.str();
}

}  // namespace cutdyn::app
