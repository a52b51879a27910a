// The module's monitor (`cutdyn monitor calibrate | estimate | teach`): the same jobs on the
// same files, and on logs given as columns of numbers (numpy arrays, lists, a pandas
// DataFrame). Columns are written into the CSV form the jobs read (numbers in shortest
// round-trip form, so exactly; NaN as "nan"), so that every rule of a log — its columns, finite
// numbers, time increasing per axis, the bad-line policy — is the file reader's.
#include "cutdyn/app/monitor.hpp"

#include <pybind11/stl.h>

#include <cmath>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include "common.hpp"
#include "cutdyn/core/error.hpp"
#include "cutdyn/drive/equivalent_current.hpp"
#include "cutdyn/io/output.hpp"

namespace cutdyn::python {
namespace {

bool is_path(const py::handle& o) {
  return py::isinstance<py::str>(o) || py::hasattr(o, "__fspath__");
}

std::string path_of(const py::handle& o) {
  return py::module_::import("os").attr("fspath")(o).cast<std::string>();
}

// A log given as columns, as the CSV text a log file holds: a header of the column names,
// then one line per row. A str value is the same in every row (e.g. axis="x"); the "axis"
// column holds text, every other column numbers. Throws InvalidInput naming `name` and the
// column for a column that is not numbers or lengths that differ.
std::string log_text(const py::handle& columns, const std::string& name) {
  using Column = std::variant<std::string, std::vector<std::string>, std::vector<double>>;
  std::vector<std::pair<std::string, Column>> cols;
  std::optional<std::size_t> rows;
  Validator v;
  for (const py::handle item : columns.attr("items")()) {
    const auto pair = item.cast<py::tuple>();
    const std::string key = py::str(pair[0]).cast<std::string>();
    const py::handle value = pair[1];
    const std::string& where = key;
    Column column;
    if (py::isinstance<py::str>(value)) {
      column = value.cast<std::string>();
    } else if (key == "axis") {
      std::vector<std::string> text;
      for (const py::handle a : value) text.push_back(py::str(a).cast<std::string>());
      column = std::move(text);
    } else {
      const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
      if (!a || a.ndim() != 1) {
        v.add(where + ": must be a sequence of numbers (one per row) or a str");
        continue;
      }
      std::vector<double> numbers(a.data(), a.data() + a.size());
      column = std::move(numbers);
    }
    const auto check_text = [&](const std::string& text, const std::string& at) {
      if (text.find_first_of(",\r\n") == std::string::npos) return true;
      v.add(at + " = \"" + text + "\": must not hold a comma or a line end");
      return false;
    };
    if (const auto* text = std::get_if<std::string>(&column)) {
      check_text(*text, where);
    } else {
      const std::size_t n = std::holds_alternative<std::vector<double>>(column)
                                ? std::get<std::vector<double>>(column).size()
                                : std::get<std::vector<std::string>>(column).size();
      if (rows && n != *rows)
        v.add(where + ": " + std::to_string(n) + " values, the columns before it " +
              std::to_string(*rows));
      if (!rows) rows = n;
    }
    if (const auto* texts = std::get_if<std::vector<std::string>>(&column))
      for (std::size_t i = 0; i < texts->size(); ++i)
        if (!check_text((*texts)[i], where + "[" + std::to_string(i) + "]")) break;
    if (key.find_first_of(",\r\n") != std::string::npos)
      v.add(where + ": a column name must not hold a comma or a line end");
    cols.emplace_back(key, std::move(column));
  }
  if (cols.empty()) v.add("no columns");
  v.throw_if_any(name);
  std::string text;
  for (std::size_t k = 0; k < cols.size(); ++k) text += (k ? "," : "") + cols[k].first;
  text += '\n';
  for (std::size_t i = 0; i < rows.value_or(0); ++i) {
    for (std::size_t k = 0; k < cols.size(); ++k) {
      if (k) text += ',';
      const Column& c = cols[k].second;
      if (const auto* s = std::get_if<std::string>(&c))
        text += *s;
      else if (const auto* t = std::get_if<std::vector<std::string>>(&c))
        text += (*t)[i];
      else
        append_number(text, std::get<std::vector<double>>(c)[i]);
    }
    text += '\n';
  }
  return text;
}

// Logs given as paths or columns: the names a job's options take, and the texts of those
// given as columns (named "ARGUMENT[i]").
void add_logs(const py::handle& logs, const std::string& argument, std::vector<std::string>& names,
              app::LogTexts& texts) {
  if (logs.is_none()) return;
  if (is_path(logs) || py::hasattr(logs, "items")) {  // one log, not a list of them
    py::list one;
    one.append(logs);
    add_logs(one, argument, names, texts);
    return;
  }
  std::size_t i = 0;
  for (const py::handle log : logs) {
    const std::string name = argument + "[" + std::to_string(i++) + "]";
    if (is_path(log)) {
      names.push_back(path_of(log));
    } else if (py::hasattr(log, "items")) {
      texts[name] = log_text(log, name);
      names.push_back(name);
    } else {
      throw InvalidInput({"must be a log file's path or a mapping of columns"}, name);
    }
  }
}

bool stop_at_bad_line(const std::string& policy) {
  if (policy == "stop") return true;
  if (policy == "skip") return false;
  throw InvalidInput({"on_bad_line = \"" + policy + "\": must be stop or skip"}, "request");
}

// kt / inertia: a number for every axis, or {axis: number}.
std::vector<app::AxisValue> axis_values(const py::handle& given, const std::string& argument) {
  std::vector<app::AxisValue> out;
  if (given.is_none()) return out;
  try {
    if (py::hasattr(given, "items")) {
      for (const py::handle item : given.attr("items")()) {
        const auto pair = item.cast<py::tuple>();
        out.push_back({py::str(pair[0]).cast<std::string>(), pair[1].cast<double>()});
      }
    } else {
      out.push_back({"", given.cast<double>()});
    }
  } catch (const py::cast_error&) {
    throw InvalidInput({argument + ": must be a number, or {axis: number}"}, "request");
  }
  return out;
}

app::RequestNames monitor_names() {
  app::RequestNames n;  // the Python arguments' names
  n.torque_constant = "kt";
  n.inertia = "inertia";
  return n;
}

std::vector<std::string> warning_texts(const std::vector<app::MonitorWarning>& warnings) {
  std::vector<std::string> out;
  for (const app::MonitorWarning& w : warnings) out.push_back(app::warning_text(w));
  return out;
}

std::string json_file_text(const nlohmann::json& doc) {
  std::ostringstream out;
  io::write_json(out, doc);
  return out.str();
}

// A calibration given as a file's path, "zheng2012", or a calibration document (a dict):
// the calibration and its name.
std::pair<app::Calibration, std::string> calibration_of(const py::handle& calib) {
  if (is_path(calib)) {
    const std::string path = path_of(calib);
    return {app::read_calibration(path), path};
  }
  return {app::calibration_from_json(to_json(calib, "calib", "a calibration"), "calib"), "calib"};
}

template <typename Options>
void set_if(std::optional<double> given, Options& options, double Options::*field) {
  if (given) options.*field = *given;
}

py::dict calibrate(const py::object& idle, const py::object& loaded, const std::string& base,
                   const py::object& kt, const py::object& inertia, const std::string& measure,
                   const std::string& force_column, std::optional<double> window_s,
                   std::optional<double> steady_tolerance, std::optional<double> standstill_rad_s,
                   const std::string& on_bad_line) {
  app::CalibrateOptions o;
  add_logs(idle, "idle", o.idle, o.texts);
  add_logs(loaded, "loaded", o.loaded, o.texts);
  o.base = base;
  o.torque_constant_nm_per_a = axis_values(kt, "kt");
  o.inertia_kg_m2 = axis_values(inertia, "inertia");
  if (!measure.empty()) {
    o.measure = parse_current_measure(measure);
    if (!o.measure)
      throw InvalidInput({"measure = \"" + measure + "\": must be rms or space-vector"}, "request");
  }
  o.force_column = force_column;
  set_if(window_s, o.fit, &CalibrationOptions::window_s);
  set_if(steady_tolerance, o.fit, &CalibrationOptions::steady_tolerance);
  set_if(standstill_rad_s, o.fit, &CalibrationOptions::standstill_rad_s);
  o.stop_at_bad_line = stop_at_bad_line(on_bad_line);
  o.names = monitor_names();
  const auto report = run_interruptible<app::CalibrateReport>(
      [&](const std::atomic<bool>&) { return app::calibrate(o); });
  const nlohmann::json doc = app::calibration_json(report.axes);
  py::dict out = result_of(doc, report);
  out["file_text"] = json_file_text(doc);
  out["warnings"] = warning_texts(report.warnings);
  return out;
}

// The estimate's rows as they come, for the arrays.
struct EstimateRows {
  std::vector<double> time_s, force_n, force_sigma_n, speed_rad_s, accel_rad_s2;
  std::vector<std::string> axis;
  std::vector<double> level_n, upper_n, lower_n;
  std::vector<std::string> alarm;

  void add(const app::EstimatedRow& r) {
    time_s.push_back(r.row.time_s);
    axis.push_back(r.axis);
    force_n.push_back(r.estimate.force_n);
    force_sigma_n.push_back(r.estimate.sigma_known ? r.estimate.force_sigma_n : std::nan(""));
    speed_rad_s.push_back(r.estimate.speed_rad_s);
    accel_rad_s2.push_back(r.estimate.accel_rad_s2);
    level_n.push_back(r.alarm ? r.alarm->level_n : std::nan(""));
    upper_n.push_back(r.alarm ? r.alarm->upper_n : std::nan(""));
    lower_n.push_back(r.alarm ? r.alarm->lower_n : std::nan(""));
    alarm.push_back(r.alarm ? alarm_text(r.alarm->active) : "");
  }
};

py::dict estimate(const py::object& log, const py::object& calib, const py::object& band,
                  std::optional<double> bandwidth_hz, std::optional<double> standstill_rad_s,
                  double tooth_frequency_hz, std::optional<double> persist_s,
                  std::optional<double> wear_fraction, std::optional<double> wear_time_constant_s,
                  const std::string& on_bad_line) {
  app::EstimateOptions o;
  set_if(bandwidth_hz, o.estimator, &EstimatorOptions::bandwidth_hz);
  set_if(standstill_rad_s, o.estimator, &EstimatorOptions::standstill_rad_s);
  o.tooth_frequency_hz = tooth_frequency_hz;
  set_if(persist_s, o.alarms, &AlarmOptions::persist_s);
  set_if(wear_fraction, o.alarms, &AlarmOptions::wear_fraction);
  set_if(wear_time_constant_s, o.alarms, &AlarmOptions::wear_time_constant_s);
  o.stop_at_bad_line = stop_at_bad_line(on_bad_line);
  o.names = monitor_names();
  if (const auto p = o.validate(); !p.empty()) throw InvalidInput(p, "request");
  auto [calibration, calibration_name] = calibration_of(calib);
  std::optional<app::BandFile> band_file;
  std::string band_name;
  if (!band.is_none()) {
    band_name = is_path(band) ? path_of(band) : "band";
    band_file = is_path(band) ? app::read_band(band_name)
                              : app::band_from_json(to_json(band, "band", "a band"), "band");
  }
  std::unique_ptr<app::LogInput> in;
  if (is_path(log))
    in = std::make_unique<app::LogInput>(path_of(log));
  else if (py::hasattr(log, "items"))
    in = std::make_unique<app::LogInput>("log", log_text(log, "log"));
  else
    throw InvalidInput({"must be a log file's path or a mapping of columns"}, "log");

  EstimateRows rows;
  const bool banded = band_file.has_value();
  const auto report = run_interruptible<app::EstimateReport>([&](const std::atomic<bool>& cancel) {
    app::EstimateJob job(std::move(calibration), calibration_name, o, std::move(band_file),
                         band_name, in->name(),
                         {{}, [&rows](const app::EstimatedRow& r) { rows.add(r); }});
    for (std::string_view chunk = in->read(); !chunk.empty(); chunk = in->read()) {
      if (cancel) throw Cancelled();
      job.feed(chunk);
    }
    return job.finish();
  });
  py::dict out = result_of(app::to_json(report), report);
  py::dict columns;
  columns["time_s"] = array_of(rows.time_s);
  columns["axis"] = rows.axis;
  columns["force_n"] = array_of(rows.force_n);
  columns["force_sigma_n"] = array_of(rows.force_sigma_n);
  columns["speed_rad_s"] = array_of(rows.speed_rad_s);
  columns["accel_rad_s2"] = array_of(rows.accel_rad_s2);
  if (banded) {
    columns["level_n"] = array_of(rows.level_n);
    columns["upper_n"] = array_of(rows.upper_n);
    columns["lower_n"] = array_of(rows.lower_n);
    columns["alarm"] = rows.alarm;
  }
  out["columns"] = columns;
  py::list alarms;  // as `--alarms` writes them
  for (const auto& [axis, a] : report.alarms) {
    py::dict event;
    event["time_s"] = a.time_s;
    event["axis"] = axis;
    event["alarm"] = std::string(to_string(a.kind));
    event["detected_s"] = a.detected_s;
    event["level"] = a.level_n;
    event["limit"] = a.limit_n;
    alarms.append(event);
  }
  out["alarms"] = alarms;
  out["warnings"] = warning_texts(report.warnings);
  return out;
}

py::dict teach(const py::object& references, const py::object& calib,
               std::optional<double> bandwidth_hz, std::optional<double> standstill_rad_s,
               std::optional<double> bin_s, std::optional<double> rpm, std::optional<int> teeth,
               std::optional<double> smoothing_s, std::optional<double> k_sigma,
               std::optional<double> relative_margin, std::optional<double> absolute_margin_n,
               std::optional<double> peak_margin, std::optional<double> phase_tolerance_s,
               std::optional<double> average_s, std::optional<double> cutting_fraction,
               const std::string& on_bad_line) {
  app::TeachOptions o;
  add_logs(references, "references", o.references, o.texts);
  if (is_path(calib)) {
    o.calibration = path_of(calib);
  } else {
    o.calibration = "calib";
    o.calibration_given =
        app::calibration_from_json(to_json(calib, "calib", "a calibration"), "calib");
  }
  set_if(bandwidth_hz, o.estimator, &EstimatorOptions::bandwidth_hz);
  set_if(standstill_rad_s, o.estimator, &EstimatorOptions::standstill_rad_s);
  set_if(bin_s, o.band, &BandOptions::bin_s);
  set_if(k_sigma, o.band, &BandOptions::k_sigma);
  set_if(relative_margin, o.band, &BandOptions::relative_margin);
  set_if(absolute_margin_n, o.band, &BandOptions::absolute_margin_n);
  set_if(peak_margin, o.band, &BandOptions::peak_margin);
  set_if(cutting_fraction, o.band, &BandOptions::cutting_fraction);
  o.rpm = rpm;
  o.teeth = teeth;
  o.smoothing_s = smoothing_s;
  o.phase_tolerance_s = phase_tolerance_s;
  o.average_s = average_s;
  o.stop_at_bad_line = stop_at_bad_line(on_bad_line);
  const auto report =
      run_interruptible<app::TeachReport>([&](const std::atomic<bool>&) { return app::teach(o); });
  const nlohmann::json doc = app::band_json(report.band);
  py::dict out = result_of(doc, report);
  out["file_text"] = json_file_text(doc);
  out["warnings"] = warning_texts(report.warnings);
  return out;
}

}  // namespace

void add_monitor(py::module_& m) {
  m.def("monitor_calibrate", &calibrate, py::arg("idle") = py::none(),
        py::arg("loaded") = py::none(), py::arg("base") = "", py::arg("kt") = py::none(),
        py::arg("inertia") = py::none(), py::arg("measure") = "",
        py::arg("force_column") = "force_n", py::arg("window_s") = py::none(),
        py::arg("steady_tolerance") = py::none(), py::arg("standstill_rad_s") = py::none(),
        py::arg("on_bad_line") = "stop");
  m.def("monitor_estimate", &estimate, py::arg("log"), py::arg("calib"),
        py::arg("band") = py::none(), py::arg("bandwidth_hz") = py::none(),
        py::arg("standstill_rad_s") = py::none(), py::arg("tooth_frequency_hz") = 0.0,
        py::arg("persist_s") = py::none(), py::arg("wear_fraction") = py::none(),
        py::arg("wear_time_constant_s") = py::none(), py::arg("on_bad_line") = "stop");
  m.def("monitor_teach", &teach, py::arg("references"), py::arg("calib"),
        py::arg("bandwidth_hz") = py::none(), py::arg("standstill_rad_s") = py::none(),
        py::arg("bin_s") = py::none(), py::arg("rpm") = py::none(), py::arg("teeth") = py::none(),
        py::arg("smoothing_s") = py::none(), py::arg("k_sigma") = py::none(),
        py::arg("relative_margin") = py::none(), py::arg("absolute_margin_n") = py::none(),
        py::arg("peak_margin") = py::none(), py::arg("phase_tolerance_s") = py::none(),
        py::arg("average_s") = py::none(), py::arg("cutting_fraction") = py::none(),
        py::arg("on_bad_line") = "stop");
}

}  // namespace cutdyn::python
