// The calibrate job (docs/models/monitor.md §3).
#include <set>

#include "cutdyn/app/monitor.hpp"
#include "cutdyn/io/output.hpp"
#include "monitor_stream.hpp"

namespace cutdyn::app {
namespace {

// The logs of one kind, per axis, and per file the measures its comments record.
struct Logs {
  std::map<std::string, std::vector<AxisRun>> idle, loaded;
  std::set<std::string> axes;
  std::vector<std::pair<std::string, detail::RecordedMeasures>> recorded;
};

Logs read_logs(const CalibrateOptions& o, const MonitorListener& listener,
               std::vector<MonitorWarning>& warnings) {
  Logs logs;
  const auto read = [&](const std::vector<std::string>& files, const std::string& column,
                        std::map<std::string, std::vector<AxisRun>>& into) {
    for (const std::string& f : files) {
      logs.recorded.emplace_back(f, detail::RecordedMeasures{});
      const auto in = LogInput::open(f, o.texts);
      for (auto& [axis, run] : detail::read_log(*in, column, o.stop_at_bad_line, listener, warnings,
                                                &logs.recorded.back().second)) {
        into[axis].push_back(std::move(run));
        logs.axes.insert(axis);
      }
    }
  };
  read(o.idle, "", logs.idle);
  read(o.loaded, o.force_column, logs.loaded);
  return logs;
}

// The given constants per axis: the base, then the measure, KT and J of the options. Throws
// unless KT and J are known for every axis.
void apply_given(const CalibrateOptions& o, const Calibration& base, const Logs& logs,
                 std::map<std::string, CalibratedAxis>& axes) {
  std::map<std::string, bool> kt_given, j_given;
  for (const std::string& axis : logs.axes) {
    AxisCalibration c;
    if (const auto it = base.find(axis); it != base.end()) {
      c = it->second;
      kt_given[axis] = j_given[axis] = true;
    }
    if (o.measure) c.model.measure = *o.measure;
    axes[axis].calibration = c;
  }
  // A log whose recorded measure is not the calibration's is refused (its KT would be off √2).
  for (const auto& [file, m] : logs.recorded)
    for (const auto& [axis, logged] : m) {
      const CurrentMeasure used = axes[axis].calibration.model.measure;
      if (logged.first != used)
        throw detail::measure_mismatch(o.names.measure, file, logged.second, axis, logged.first,
                                       used);
    }
  const auto apply = [&](const std::vector<AxisValue>& values, const std::string& flag, bool kt) {
    for (const AxisValue& v : values) {
      if (!v.axis.empty() && !logs.axes.count(v.axis))
        throw InvalidInput({flag + " = \"" + v.axis + "=" + io::format_number(v.value) +
                            "\": no log has the axis " + v.axis},
                           o.names.where);
      for (auto& [name, a] : axes) {
        if (!v.axis.empty() && name != v.axis) continue;
        AxisCalibration& c = a.calibration;
        (kt ? c.model.torque_constant_nm_per_a : c.model.inertia_kg_m2) = v.value;
        (kt ? c.sigma.torque_constant_nm_per_a : c.sigma.inertia_kg_m2) = 0.0;
        (kt ? kt_given : j_given)[name] = true;
      }
    }
  };
  const RequestNames& n = o.names;
  apply(o.torque_constant_nm_per_a, n.torque_constant, true);
  apply(o.inertia_kg_m2, n.inertia, false);
  Validator v;
  for (const std::string& axis : logs.axes) {
    if (!kt_given[axis])
      v.add("axis " + axis + ": the torque constant is unknown: give " + n.torque_constant + " " +
            axis + "=VALUE (N·m/A) or " + n.base);
    if (!j_given[axis])
      v.add("axis " + axis + ": the inertia is unknown: give " + n.inertia + " " + axis +
            "=VALUE (kg·m²) or " + n.base);
  }
  v.throw_if_any(n.where);
}

// Steps 1 and 2 of one axis on its given constants; what is missing goes to `v`.
void fit_axis(const CalibrateOptions& o, const std::string& axis, const Logs& logs, bool in_base,
              CalibratedAxis& a, Validator& v, const MonitorListener& listener,
              std::vector<MonitorWarning>& warnings) {
  AxisCalibration& c = a.calibration;
  if (const auto it = logs.idle.find(axis); it != logs.idle.end()) {
    IdleFit f = fit_idle(c.model, it->second, o.fit);
    if (f.report.status != CalibrationStatus::kSuccess)
      throw InvalidInput({"axis " + axis + ": " + f.report.message}, "calibration");
    for (const std::string& w : f.report.warnings)
      detail::warn(listener, warnings,
                   {MonitorWarning::Kind::kFit, "calibration", axis, 0, 0, 0.0, 0.0, 0.0, w});
    c.model.friction_nm = f.friction_nm;
    c.model.viscous_nm_s_per_rad = f.viscous_nm_s_per_rad;
    c.sigma.friction_nm = f.friction_sigma_nm;
    c.sigma.viscous_nm_s_per_rad = f.viscous_sigma;
    c.sigma.friction_viscous_covariance = f.covariance;
    c.current_noise_a = f.current_noise_a;
    c.speed_noise_rad_s = f.speed_noise_rad_s;
    a.idle = std::move(f);
  } else if (!in_base) {
    v.add("axis " + axis + ": no " + o.names.idle + " log and no " + o.names.base +
          ": Tnzm and X are unknown");
  }
  if (const auto it = logs.loaded.find(axis); it != logs.loaded.end()) {
    LoadFit f = fit_load(c, it->second, o.fit);
    if (f.report.status != CalibrationStatus::kSuccess)
      throw InvalidInput({"axis " + axis + ": " + f.report.message}, "calibration");
    c.model.force_gain_m = f.force_gain_m;
    c.sigma.force_gain_m = f.force_gain_sigma_m;
    a.load = std::move(f);
  } else if (!in_base) {
    v.add("axis " + axis + ": no " + o.names.loaded + " log and no " + o.names.base +
          ": KBlf is unknown");
  }
  // Tnzm, X and KBlf fitted here carry their uncertainties; one kept from a base whose
  // uncertainty is unknown (the literature coefficients) keeps it unknown.
  if (a.idle && a.load) c.uncertainty_known = true;
  if (v.ok())
    rethrow_as("calibration", "axis " + axis, [&] {
      if (const auto p = c.validate(); !p.empty()) throw InvalidInput(p);
    });
}

}  // namespace

std::vector<std::string> CalibrateOptions::validate() const {
  Validator v;
  v.merge(fit.validate());
  if (force_column.empty()) v.add("force_column: must name the reference force column");
  return v.problems();
}

Calibration CalibrateReport::calibration() const {
  Calibration c;
  for (const auto& [axis, a] : axes) c[axis] = a.calibration;
  return c;
}

CalibrateReport calibrate(const CalibrateOptions& options, const MonitorListener& listener) {
  if (const auto p = options.validate(); !p.empty()) throw InvalidInput(p, "options");
  CalibrateReport report;
  report.options = options;
  Calibration base;
  if (!options.base.empty()) base = read_calibration(options.base);
  Logs logs = read_logs(options, listener, report.warnings);
  if (logs.axes.empty())
    for (const auto& [axis, c] : base) logs.axes.insert(axis);
  if (logs.axes.empty())
    throw InvalidInput({"nothing to calibrate: give " + options.names.idle + " and/or " +
                        options.names.loaded + " logs, or " + options.names.base},
                       options.names.where);
  apply_given(options, base, logs, report.axes);
  Validator v;
  for (const std::string& axis : logs.axes)
    fit_axis(options, axis, logs, base.count(axis) > 0, report.axes[axis], v, listener,
             report.warnings);
  v.throw_if_any("calibration");
  return report;
}

}  // namespace cutdyn::app
