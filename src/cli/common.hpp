// Pieces every command shares: loading the case, requiring keys, progress, formatting.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>

#include "cutdyn/io/case_file.hpp"
#include "cutdyn/stability/turning.hpp"

namespace cutdyn::cli {

/// The case at `path`, or the embedded example `default_example` when path is empty.
io::Case load_case(const std::string& path, std::string_view default_example);

/// Throws InvalidInput(where = case source) unless the case is a turning case.
void require_turning(const io::Case& c, std::string_view command);

/// The turning model of a case: modes, Kt and vibration. Checks that [cutting].kt_n_per_mm2
/// is there and, with vibration, that the duty cycle can be had at every speed.
TurningModel turning_model(const io::Case& c, std::string_view command);

/// Progress on stderr while it is a terminal ("lobes: 120/200 speeds"); silent otherwise.
std::function<void(int, int)> progress_reporter(std::ostream& err, std::string label);

/// A fixed-precision number for people: `digits` significant digits.
std::string human(double value, int digits = 4);

}  // namespace cutdyn::cli
