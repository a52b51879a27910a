// The stability method a user asks for: one name set for the case file (`[lobes] method`), the
// command line (`--method`) and the output, for both processes.
//
//   auto                  turning: the closed form without vibration, else the full
//                         discretization; milling: the full discretization
//   zero-order            milling: the averaged (zero-order) solution [Altintas1995];
//                         turning: the closed form, which is the zero-order solution there
//                         (exact for conventional turning, the averaged theory with vibration)
//   closed-form           the same as zero-order, in both processes
//   multi-frequency       Hill's / the multi-frequency method
//   full-discretization   the full discretization (matrix-free): in milling with the
//                         quadratic interpolation (order 2), in turning the first-order one
//   full-discretization-dense   the same with the dense transition matrix (slow; checks)
#pragma once

#include <optional>
#include <string_view>

#include "cutdyn/core/fields.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn {

enum class StabilityMethod {
  kAuto,
  kZeroOrder,
  kClosedForm,
  kMultiFrequency,
  kFullDiscretization,
  kFullDiscretizationDense,
};

/// "auto", "zero-order", "closed-form", "multi-frequency", "full-discretization",
/// "full-discretization-dense".
const char* to_string(StabilityMethod method);

/// The method of that name, or nothing.
std::optional<StabilityMethod> parse_stability_method(std::string_view name);

/// Every name, for messages and help: "auto, zero-order, closed-form, …".
inline constexpr const char* kStabilityMethodNames =
    "auto, zero-order, closed-form, multi-frequency, full-discretization, "
    "full-discretization-dense";

/// The deepest cut any key or request may ask for (10 m): beyond it no number means a cut.
/// No stability search goes deeper either (a check's margin search, a search extended to a
/// requested depth stop there).
inline constexpr double kMaxDepthMm = 10000.0;
inline constexpr double kMaxDepthM = kMaxDepthMm / 1000.0;

/// The keys every stability method's options share, spelled once (core/fields.hpp): the
/// milling and turning options list them, and the case file's `[lobes]` rows are theirs.
namespace stability_fields {
inline constexpr FieldSpec kDepthMax{"depth_max_mm",
                                     FieldType::kNumber,
                                     {"mm", units::mm_to_m, units::m_to_mm},
                                     FieldRange::open_closed(0.0, kMaxDepthMm),
                                     "depth limit",
                                     ""};
inline constexpr FieldSpec kHarmonics{
    "harmonics",
    FieldType::kInteger,
    fields::kNone,
    FieldRange::closed(0, 100),
    "least harmonics kept",
    "multi-frequency: the least number of harmonics kept each side (more are used until the "
    "window covers every mode and the contact pulse; docs/models/milling-stability.md)"};
}  // namespace stability_fields

}  // namespace cutdyn
