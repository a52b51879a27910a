#include "cutdyn/stability/critical_depth.hpp"

#include <cmath>

#include "cutdyn/core/units.hpp"

namespace cutdyn {

const char* to_string(Bifurcation b) {
  switch (b) {
    case Bifurcation::kNone:
      return "none";
    case Bifurcation::kHopf:
      return "hopf";
    case Bifurcation::kFlip:
      return "flip";
    case Bifurcation::kFold:
      return "fold";
  }
  return "?";
}

Bifurcation classify_multiplier(double theta) {
  constexpr double kTolerance = 1e-6;  // rad: a real multiplier up to rounding
  const double a = std::abs(theta);
  if (a < kTolerance) return Bifurcation::kFold;
  if (a > units::kPi - kTolerance) return Bifurcation::kFlip;
  return Bifurcation::kHopf;
}

}  // namespace cutdyn
