#include "cutdyn/app/identify.hpp"

#include <fmt/format.h>

#include <cmath>
#include <string>

#include "cutdyn/app/case_models.hpp"
#include "cutdyn/app/detail/text.hpp"
#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/io/force_file.hpp"
#include "cutdyn/io/output.hpp"

namespace cutdyn::app {
namespace {

constexpr const char* kWhy = "required by `cutdyn identify`";

void require_keys(const io::Case& c) {
  Validator v;
  if (c.process != io::Process::kMilling) {
    v.add("process = \"" + std::string(io::to_string(c.process)) +
          "\": `cutdyn identify` identifies the coefficients of milling and needs a milling case "
          "(process = \"milling\") with [tool] and [operation]");
  } else {
    if (!c.tool)
      v.add(std::string("tool: missing (") + kWhy +
            ": tool.teeth, the number of teeth of the cutter of the test cuts)");
    if (!c.operation)
      v.add(std::string("operation: missing (") + kWhy +
            ": the engagement of the test cuts, radial_immersion and direction, or entry_deg "
            "and exit_deg)");
  }
  v.throw_if_any(c.source);
}

std::string joined(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : ", ") + s;
  return out;
}

// A coefficient in another unit: value, standard error and interval times `scale`.
IdentifiedCoefficient scaled(const IdentifiedCoefficient& k, double scale) {
  IdentifiedCoefficient out = k;
  out.value *= scale;
  out.std_error *= scale;
  out.ci95_low *= scale;
  out.ci95_high *= scale;
  return out;
}

std::vector<IdentifiedValue> values_of(const io::Case& c, const CoefficientFit& f) {
  const double per_mm2 = units::pa_to_n_per_mm2(1.0), per_mm = 1e-3;  // from Pa, N/m
  const auto mm2 = [&](const std::optional<double>& pa) -> std::optional<double> {
    if (!pa) return std::nullopt;
    return *pa * per_mm2;
  };
  const auto mm = [&](const std::optional<double>& n_per_m) -> std::optional<double> {
    if (!n_per_m) return std::nullopt;
    return *n_per_m * per_mm;
  };
  std::vector<IdentifiedValue> v = {
      {"Kt", "kt_n_per_mm2", true, "N/mm²", scaled(f.kt, per_mm2), mm2(c.cutting.kt_pa)},
      {"Kr", "kr_n_per_mm2", true, "N/mm²", scaled(f.kr, per_mm2), mm2(c.cutting.kr_pa)},
      {"Kte", "kte_n_per_mm", true, "N/mm", scaled(f.kte, per_mm), mm(c.cutting.kte_n_per_m)},
      {"Kre", "kre_n_per_mm", true, "N/mm", scaled(f.kre, per_mm), mm(c.cutting.kre_n_per_m)}};
  if (f.ka) v.push_back({"Ka", "ka_n_per_mm2", false, "N/mm²", scaled(*f.ka, per_mm2), {}});
  if (f.kae) v.push_back({"Kae", "kae_n_per_mm", false, "N/mm", scaled(*f.kae, per_mm), {}});
  return v;
}

std::vector<std::string> notes_of(const io::Case& c) {
  std::vector<std::string> notes;
  const MillingTool& tool = *c.tool;
  if (!tool.even_pitch())
    notes.push_back(
        "tool.pitch_deg (uneven pitch) is not used: every tooth passes the window once per "
        "revolution, so the mean force over a revolution is the same as with even pitch");
  if (tool.helix_rad > 0.0)
    notes.push_back("tool.helix_deg = " + human(units::rad_to_deg(tool.helix_rad)) +
                    " is not used: each axial slice of a helical flute passes the same window, "
                    "only at another time, so the mean force over a revolution is that of "
                    "straight teeth");
  if (c.force_law)
    notes.push_back(
        "the case has a [force_law]: its simulation uses the S1 law, and the case file takes "
        "kte_n_per_mm and kre_n_per_mm only without it (the [cutting] table gives them as "
        "comments)");
  return notes;
}

}  // namespace

IdentifyJobReport run_identify(const io::Case& c, const IdentifyRequest& request) {
  require_keys(c);
  if (request.force_files.empty())
    throw InvalidInput({"no force files: give at least one (mean forces, or one force record "
                        "per feed; docs/models/identification.md)"},
                       request.names.where);
  IdentifyJobReport r;
  const MillingProcess process = milling_process_as_given(c);
  const EngagementWindow window = process.engagement.window();
  r.cut = IdentifyCut{process.tool.teeth, window.entry_rad, window.exit_rad};
  for (const auto& path : request.force_files) r.force_files.push_back(path.string());
  const std::vector<MeanForce> samples = io::read_force_files(request.force_files);
  try {
    r.fit = identify_coefficients(r.cut, samples);
  } catch (const InvalidInput& e) {
    // The problems name the samples by file and line; say which files they came from.
    throw InvalidInput(e.problems(), joined(r.force_files));
  }
  r.values = values_of(c, r.fit);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    IdentifiedSample s;
    s.measured = samples[i];
    s.residual = r.fit.residuals[i];
    s.fitted_fx_n = s.measured.fx_n - s.residual.fx_n;
    s.fitted_fy_n = s.measured.fy_n - s.residual.fy_n;
    if (s.measured.fz_n && s.residual.fz_n) s.fitted_fz_n = *s.measured.fz_n - *s.residual.fz_n;
    r.samples.push_back(std::move(s));
  }
  r.notes = notes_of(c);
  r.warnings = r.fit.warnings;
  return r;
}

namespace {

// "# 95 %: 584.8 … 638.4 N/mm² (± 26.8)", or why there is no interval.
std::string interval_comment(const IdentifiedValue& v, int dof) {
  const IdentifiedCoefficient& k = v.value;
  if (!k.uncertainty_known) return "no interval: no residual degrees of freedom";
  return fmt::format("95 %: {} … {} {} (± {}, {} degrees of freedom)", human(k.ci95_low),
                     human(k.ci95_high), v.unit, human(k.ci95_high - k.value, 3), dof);
}

// Why the case file would refuse this value here (empty: it takes it).
std::string refusal(const io::Case& c, const IdentifiedValue& v) {
  if (!v.case_key) return "the axial pair has no case key (the models of cutdyn do not use it)";
  const bool edge = v.name == "Kte" || v.name == "Kre";
  if (edge && c.force_law) return "the case file takes " + v.key + " only without [force_law]";
  if (v.name == "Kt" && !(v.value.value > 0.0)) return "the case file takes " + v.key + " > 0 only";
  if (v.value.value < 0.0) return "the case file takes " + v.key + " ≥ 0 only";
  return "";
}

}  // namespace

std::string cutting_table_toml(const io::Case& c, const IdentifyJobReport& r) {
  std::string out = fmt::format(
      "# [cutting] identified by `cutdyn identify` for {}:\n#   {} teeth, window {}° … {}°, {} "
      "test cuts at {} feeds from\n#   {}\n",
      c.source, r.cut.teeth, human(units::rad_to_deg(r.cut.entry_rad)),
      human(units::rad_to_deg(r.cut.exit_rad)), r.fit.samples, r.fit.distinct_feeds,
      joined(r.force_files));
  out += "# Each value's 95 % interval (value ± t·standard error) is in its comment.\n";
  if (!r.warnings.empty())
    out += "# The fit gave " + std::to_string(r.warnings.size()) +
           " warning(s): see the report of the command.\n";
  out += "[cutting]\n";
  for (const IdentifiedValue& v : r.values) {
    const std::string line = v.key + " = " + io::format_number(v.value.value);
    const std::string comment = interval_comment(v, r.fit.degrees_of_freedom);
    const std::string why = refusal(c, v);
    if (why.empty())
      out += line + "  # " + comment + "\n";
    else
      out += "# " + line + "  # " + comment + "; not set: " + why + "\n";
  }
  return out;
}

}  // namespace cutdyn::app
