#include "cutdyn/app/case_models.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "cutdyn/core/error.hpp"
#include "cutdyn/modal/frf_fit.hpp"

namespace cutdyn::app {

io::Case load_case(const std::string& path, std::string_view default_example) {
  if (path.empty()) return io::load_example(default_example);
  // A built-in example may be named instead of a file (a file of that name comes first).
  std::error_code error;
  if (!std::filesystem::exists(path, error) && io::example_text(path))
    return io::load_example(path);
  return io::load_case_file(path);
}

void require_turning(const io::Case& c, std::string_view command) {
  if (c.process != io::Process::kTurning) {
    throw InvalidInput(
        {"process = \"" + std::string(io::to_string(c.process)) +
         "\": the turning model of `cutdyn " + std::string(command) + "` needs a turning case"},
        c.source);
  }
}

OxleyPrediction predict_with_oxley(const io::Case& c, std::string_view command, bool need_width) {
  Validator v;
  const io::CuttingSection& cs = c.cutting;
  const std::string why = "required by `cutdyn " + std::string(command) +
                          "` to predict the force coefficients from [material]";
  const auto need = [&](bool present, const char* key) {
    if (!present) v.add(std::string("cutting.") + key + ": missing (" + why + ")");
  };
  need(cs.speed_m_per_s.has_value(), "speed_m_per_min");
  need(cs.uncut_chip_thickness_m.has_value(), "uncut_chip_thickness_mm");
  need(cs.rake_rad.has_value(), "rake_deg");
  if (need_width) need(cs.width_m.has_value(), "width_mm");
  v.throw_if_any(c.source);
  OxleyPrediction p;
  const WorkMaterial& material = *c.material;
  p.cut.speed_m_per_s = *cs.speed_m_per_s;
  p.cut.uncut_chip_thickness_m = *cs.uncut_chip_thickness_m;
  p.cut.width_m = cs.width_m.value_or(1e-3);
  p.cut.rake_rad = *cs.rake_rad;
  p.cut.workpiece_temperature_c =
      cs.workpiece_temperature_c.value_or(material.flow.reference_temperature_c);
  try {
    p.result = oxley_orthogonal(material, p.cut, c.oxley);
  } catch (const InvalidInput& e) {
    std::vector<std::string> problems;
    for (const std::string& problem : e.problems())
      problems.push_back("[material] " + material.name + " with [cutting]: " + problem);
    throw InvalidInput(problems, c.source);
  }
  return p;
}

TurningProcess turning_process(const io::Case& c, std::string_view command) {
  require_turning(c, command);
  Validator v;
  if (c.modal.modes.empty() && c.frfs.empty())
    v.add("modes: missing (required by `cutdyn " + std::string(command) +
          "`: at least one [[modes]] or [[frf]] table)");
  if (!c.cutting.kf_pa && !c.material)
    v.add("cutting.kf_n_per_mm2: missing (required by `cutdyn " + std::string(command) + "`)");
  if (c.vibration && !c.vibration->duty_cycle && !c.vibration->workpiece_diameter_m)
    v.add(
        "vibration.workpiece_diameter_mm: missing (required to compute the duty cycle at each "
        "spindle speed; or give vibration.duty_cycle)");
  v.throw_if_any(c.source);
  TurningProcess m;
  m.modal = c.modal;
  m.measured = measured_structure(c);
  // Given, or predicted from [material] (the loader allows only one of the two).
  m.kf_pa = c.cutting.kf_pa ? *c.cutting.kf_pa : predict_with_oxley(c, command, false).result.kt_pa;
  m.vibration = c.vibration;
  // The loader checked ranges in the user's units; this catches what only the model knows
  // (an undamped mode cannot be analysed for stability).
  if (const auto problems = m.validate(); !problems.empty()) throw InvalidInput(problems, c.source);
  return m;
}

MillingProcess milling_process(const io::Case& c, std::string_view command) {
  Validator v;
  if (c.process != io::Process::kMilling)
    v.add("process = \"" + std::string(io::to_string(c.process)) +
          "\": this is not a milling case");
  if (c.modal.modes.empty() && c.frfs.empty())
    v.add("modes: missing (required by `cutdyn " + std::string(command) +
          "`: at least one [[modes]] or [[frf]] table)");
  if (!c.cutting.kt_pa)
    v.add("cutting.kt_n_per_mm2: missing (required by `cutdyn " + std::string(command) + "`)");
  if (!c.tool)
    v.add("tool: missing (required for milling: at least tool.teeth and tool.diameter_mm)");
  v.throw_if_any(c.source);
  MillingProcess m = milling_process_as_given(c);
  if (const auto problems = m.validate_for_stability(); !problems.empty())
    throw InvalidInput(problems, c.source);
  return m;
}

std::optional<MeasuredStructure> measured_structure(const io::Case& c) {
  if (c.frfs.empty()) return std::nullopt;
  MeasuredStructure s;
  for (std::size_t i = 0; i < c.frfs.size(); ++i) {
    const io::FrfTable& t = c.frfs[i];
    std::optional<MeasuredFrf>& slot = t.direction == "x" ? s.xx : t.direction == "y" ? s.yy : s.xy;
    rethrow_as(c.source, "frf[" + std::to_string(i) + "] (" + t.path.string() + ")",
               [&] { slot = slot ? add_frf(*slot, t.data) : t.data; });
  }
  for (const auto& entry : {std::pair{Direction::kX, &s.xx}, std::pair{Direction::kY, &s.yy}}) {
    // Named, not a structured binding: the lambda below captures them (clang 14, the fuzz
    // build's compiler, cannot capture a structured binding).
    const Direction direction = entry.first;
    const std::optional<MeasuredFrf>* table = entry.second;
    if (!*table) continue;
    FrfFit fit;
    rethrow_as(c.source, std::string("the fit of the measured FRF in ") + to_string(direction),
               [&] { fit = fit_modes(**table, direction); });
    s.fitted.modes.insert(s.fitted.modes.end(), fit.model.modes.begin(), fit.model.modes.end());
    std::string modes;
    for (const FittedMode& m : fit.modes) {
      modes += fmt::format("{}{:.5g} Hz ζ {:.3g} k {:.3g} N/m", modes.empty() ? "" : ", ",
                           m.natural_hz, m.damping_ratio, m.stiffness_n_per_m);
      if (std::abs(m.residue_phase_deg) >= 0.05)
        modes += fmt::format(" φ {:.2g}°", m.residue_phase_deg);
    }
    // The error of the modes every time-domain method uses, not the fit's with its residual
    // terms (docs/models/modal-fitting.md §10).
    s.fit_notes.push_back(fmt::format(
        "{}: {} (fitted over {:.5g}–{:.5g} Hz; the modes reproduce the table to {:.2g} % RMS)",
        to_string(direction), modes.empty() ? "no mode" : modes, fit.lo_hz, fit.hi_hz,
        100.0 * fit.model_rms_relative_error));
    for (const std::string& w : fit.warnings)
      s.fit_warnings.push_back(std::string("fit of the measured FRF in ") + to_string(direction) +
                               ": " + w);
  }
  return s;
}

MillingProcess milling_process_as_given(const io::Case& c) {
  MillingProcess m;
  m.modal = c.modal;
  m.measured = measured_structure(c);
  if (c.tool) m.tool = *c.tool;
  if (c.operation) m.engagement = c.operation->engagement;
  m.cutting.kt_pa = c.cutting.kt_pa.value_or(0.0);
  m.cutting.kr_pa = c.cutting.kr_pa.value_or(0.0);
  m.cutting.kte_n_per_m = c.cutting.kte_n_per_m.value_or(0.0);
  m.cutting.kre_n_per_m = c.cutting.kre_n_per_m.value_or(0.0);
  m.s1_law = c.force_law;
  return m;
}

void require_depth(Validator& v, const std::string& name, double depth_m) {
  const double mm = depth_m * 1e3;
  if (!(mm > 0.0 && mm <= io::kMaxDepthMm))
    v.add(fmt::format("{} = {:.6g} mm: must be greater than 0 and at most {:.0f} mm", name, mm,
                      io::kMaxDepthMm));
}

std::string spindle_warning(const io::Case& c, double rpm, const std::string& name) {
  if (!(rpm > c.spindle_max_rpm)) return {};
  return fmt::format(
      "{} = {:.6g} rpm is above the spindle limit of {:.6g} rpm (spindle_max_rpm{}): the "
      "answer is for a speed no spindle of this case reaches; if yours does, raise "
      "spindle_max_rpm",
      name, rpm, c.spindle_max_rpm,
      c.spindle_max_rpm == io::kDefaultSpindleMaxRpm ? ", the default" : "");
}

LobesOptions lobes_grid(const io::Case& c, int threads) {
  LobesOptions grid = c.lobes.grid;
  grid.threads = threads;
  // The refinement's budget is not a case key: a grid finer than it may still double.
  grid.refine_max_points = std::max(grid.refine_max_points, 2 * grid.rpm_steps);
  if (const auto problems = grid.validate(); !problems.empty())
    throw InvalidInput(problems, c.source);
  return grid;
}

}  // namespace cutdyn::app
