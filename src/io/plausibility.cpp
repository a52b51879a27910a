// Magnitudes that look like a unit slip (docs/case-files.md, "Plausible magnitudes"): a value
// far outside what the quantity takes on any machine, where one common wrong unit would bring
// it into range, is warned about with the value in that unit.
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "cutdyn/io/case_file.hpp"

namespace cutdyn::io {
namespace {

// A quantity's plausible range in the case file's unit, and the unit slip that explains a value
// outside it on either side: the slipped unit's name and the factor from the value as written
// to the value in the file's unit.
struct Slip {
  double factor;
  const char* what;  // "a value in Pa (N/m²)"
};
struct Plausible {
  const char* unit;
  double lo, hi;
  std::optional<Slip> below, above;
};

// The table of docs/case-files.md, "Plausible magnitudes".
const Plausible kCoefficient{"N/mm²", 10.0, 2e4, Slip{1e3, "a value in kN/mm² (GPa)"},
                             Slip{1e-6, "a value in Pa (N/m²)"}};
const Plausible kDiameter{"mm", 0.1, 5000.0, Slip{1e3, "a value in metres"}, std::nullopt};
const Plausible kStiffness{"N/m", 1e4, 1e11, Slip{1e3, "a value in N/mm"}, std::nullopt};
const Plausible kFeed{"mm", 1e-4, 5.0, std::nullopt, Slip{1e-3, "a value in µm"}};
const Plausible kNatural{"Hz", 1.0, 1e5, std::nullopt,
                         Slip{1.0 / (2.0 * M_PI), "a value in rad/s"}};

std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", x);
  return text;
}

void check(std::vector<std::string>& out, const std::string& key, const Plausible& p,
           double value) {
  if (!std::isfinite(value) || value <= 0.0) return;
  const bool low = value<p.lo, high = value> p.hi;
  if (!low && !high) return;
  const std::optional<Slip>& slip = low ? p.below : p.above;
  if (!slip) return;
  out.push_back(key + " = " + number(value) + " " + p.unit + " is far " +
                (low ? "below" : "above") + " what it is on a machine (" + number(p.lo) + " to " +
                number(p.hi) + " " + p.unit + "): " + slip->what + "? In " + p.unit + " that is " +
                number(value * slip->factor));
}

}  // namespace

std::vector<std::string> plausibility_warnings(const Case& c) {
  std::vector<std::string> out;
  const double per_mm2 = 1e-6;  // Pa → N/mm²
  const auto coefficient = [&](const char* key, const std::optional<double>& pa) {
    if (pa) check(out, std::string("cutting.") + key, kCoefficient, *pa * per_mm2);
  };
  coefficient("kt_n_per_mm2", c.cutting.kt_pa);
  coefficient("kr_n_per_mm2", c.cutting.kr_pa);
  coefficient("kf_n_per_mm2", c.cutting.kf_pa);
  coefficient("kc_n_per_mm2", c.cutting.kc_pa);
  if (c.tool && c.tool->diameter_m > 0.0)
    check(out, "tool.diameter_mm", kDiameter, c.tool->diameter_m * 1e3);
  if (c.operation && c.operation->feed_per_tooth_m)
    check(out, "operation.feed_per_tooth_mm", kFeed, *c.operation->feed_per_tooth_m * 1e3);
  for (std::size_t i = 0; i < c.modal.modes.size(); ++i) {
    const Mode& m = c.modal.modes[i];
    const std::string at = "modes[" + std::to_string(i) + "].";
    if (i >= c.mode_mass_kg.size() || !c.mode_mass_kg[i])
      check(out, at + "stiffness_n_per_m", kStiffness, m.stiffness_n_per_m);
    check(out, at + "natural_hz", kNatural, m.natural_rad_s / (2.0 * M_PI));
  }
  return out;
}

}  // namespace cutdyn::io
