#include "cutdyn/stability/method.hpp"

#include <array>
#include <utility>

namespace cutdyn {
namespace {

constexpr std::array<std::pair<StabilityMethod, std::string_view>, 6> kNames = {{
    {StabilityMethod::kAuto, "auto"},
    {StabilityMethod::kZeroOrder, "zero-order"},
    {StabilityMethod::kClosedForm, "closed-form"},
    {StabilityMethod::kMultiFrequency, "multi-frequency"},
    {StabilityMethod::kFullDiscretization, "full-discretization"},
    {StabilityMethod::kFullDiscretizationDense, "full-discretization-dense"},
}};

}  // namespace

const char* to_string(StabilityMethod method) {
  for (const auto& [m, name] : kNames)
    if (m == method) return name.data();
  return "auto";
}

std::optional<StabilityMethod> parse_stability_method(std::string_view name) {
  for (const auto& [m, n] : kNames)
    if (n == name) return m;
  return std::nullopt;
}

}  // namespace cutdyn
