// Numbers in the words of a report: what the jobs put in their descriptions and messages.
#pragma once

#include <string>

namespace cutdyn::app {

/// A number for people: `digits` significant digits, never scientific notation for the
/// magnitudes machinists read (20000 Hz, not 2e+04).
std::string human(double value, int digits = 4);

}  // namespace cutdyn::app
