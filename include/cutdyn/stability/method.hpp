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

}  // namespace cutdyn
