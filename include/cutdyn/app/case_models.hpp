// The models of a case: what every job builds from a case file before it computes anything.
// Each throws cutdyn::InvalidInput naming the case (its source) and the key at fault.
#pragma once

#include <string>
#include <string_view>

#include "cutdyn/core/error.hpp"
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

/// The turning process of a case: modes, Kf (given, or predicted by Oxley's theory from
/// [material]) and vibration. Checks that Kf can be had and, with vibration, that the duty
/// cycle can be had at every speed.
TurningProcess turning_process(const io::Case& c, std::string_view command);

/// Oxley's prediction for a case with [material], at its [cutting] speed_m_per_min,
/// uncut_chip_thickness_mm, rake_deg and width_mm (1 mm when absent and `need_width` is
/// false: the coefficients do not depend on it).
struct OxleyPrediction {
  OrthogonalCut cut;
  OxleyResult result;
};
OxleyPrediction predict_with_oxley(const io::Case& c, std::string_view command, bool need_width);

/// The measured structure of the case's [[frf]] tables (tables of one direction added: tool
/// and workpiece), with modes fitted to each direct receptance (the number chosen from the
/// stabilisation diagram); nullopt without [[frf]].
std::optional<MeasuredStructure> measured_structure(const io::Case& c);

/// The milling process of a case for a stability analysis: modes in x and y, [cutting] Kt and
/// Kr, [tool] and [operation]; throws where a key it needs is missing.
MillingProcess milling_process(const io::Case& c, std::string_view command);

/// The case's [[modes]], [tool], [operation], [cutting] and [force_law] as a process, absent
/// tables and keys left at their defaults (unchecked: a job checks what it uses).
MillingProcess milling_process_as_given(const io::Case& c);

/// The speed grid of the case's [lobes] table (validated), on `threads` threads (0: all).
LobesOptions lobes_grid(const io::Case& c, int threads);

/// Adds a problem to `v` unless 0 < depth_m ≤ io::kMaxDepthMm (a depth asked as `name`).
void require_depth(Validator& v, const std::string& name, double depth_m);

/// A warning when `rpm` (asked as `name`) is above the case's spindle_max_rpm: no spindle of
/// the case turns that fast, so the answer describes no cut. Empty otherwise.
std::string spindle_warning(const io::Case& c, double rpm, const std::string& name);

}  // namespace cutdyn::app
