// The models of a case: what every job builds from a case file before it computes anything.
// Each throws cutdyn::InvalidInput naming the case (its source) and the key at fault.
#pragma once

#include <string>
#include <string_view>

#include "cutdyn/forces/oxley.hpp"
#include "cutdyn/io/case_file.hpp"
#include "cutdyn/stability/lobes.hpp"
#include "cutdyn/stability/milling.hpp"
#include "cutdyn/stability/turning.hpp"

namespace cutdyn::app {

/// The case at `path`, or the embedded example `default_example` when path is empty; a path
/// that names no file but a built-in example loads that example.
io::Case load_case(const std::string& path, std::string_view default_example);

/// Throws unless the case is a turning case; `command` names the job in the message.
void require_turning(const io::Case& c, std::string_view command);

/// The turning model of a case: modes, Kt (given, or predicted by Oxley's theory from
/// [material]) and vibration. Checks that Kt can be had and, with vibration, that the duty
/// cycle can be had at every speed.
TurningModel turning_model(const io::Case& c, std::string_view command);

/// Oxley's prediction for a case with [material], at its [cutting] speed_m_per_min,
/// uncut_chip_thickness_mm, rake_deg and width_mm (1 mm when absent and `need_width` is
/// false: the coefficients do not depend on it).
struct OxleyPrediction {
  OrthogonalCut cut;
  OxleyResult result;
};
OxleyPrediction predict_with_oxley(const io::Case& c, std::string_view command, bool need_width);

/// The milling model of a case: modes in x and y, Kt and Kr, [tool] and [operation].
MillingModel milling_model(const io::Case& c, std::string_view command);

/// The speed grid of the case's [lobes] table (validated), on `threads` threads (0: all).
LobesOptions lobes_grid(const io::Case& c, int threads);

}  // namespace cutdyn::app
