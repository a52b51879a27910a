// The module's feed-drive, planning, force, FRF-fitting and identification jobs: the same
// jobs, requests and reports as `cutdyn drive`, `plan`, `force`, `fit` and `identify`.
#include <pybind11/complex.h>
#include <pybind11/stl.h>

#include <complex>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "common.hpp"
#include "cutdyn/app/drive.hpp"
#include "cutdyn/app/fit.hpp"
#include "cutdyn/app/force.hpp"
#include "cutdyn/app/identify.hpp"
#include "cutdyn/app/plan.hpp"
#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn::python {
namespace {

// `cutdyn drive`: the traces of every axis (the columns of its --out), the report and text;
// with `currents`, the motor current log its --currents writes, as text.
py::dict drive(const io::Case& c, std::optional<double> rpm, std::optional<double> depth_mm,
               std::optional<int> seed, bool currents) {
  const app::SimulateRequest request = simulate_request(rpm, depth_mm, std::nullopt);
  const auto run = run_interruptible<app::DriveReport>([&](const std::atomic<bool>& cancel) {
    return app::run_drive(c, stoppable(request, cancel), {seed});
  });
  if (currents) app::require_motors(run, c.source);
  py::dict out = result_of(app::to_json(c, run), c, run);
  out["columns"] = columns_of(app::trace_table(run));
  if (currents) {
    std::ostringstream log;
    app::write_current_log(log, run, c.source);
    out["current_log"] = log.str();
  }
  return out;
}

// `cutdyn drive --sweep`: one row per value and axis, the metrics as float64 arrays (NaN
// where a drive has none).
py::dict drive_sweep(const io::Case& c, const std::string& key, const std::vector<double>& values,
                     const std::string& metric, std::optional<double> rpm,
                     std::optional<double> depth_mm, std::optional<int> seed, int threads) {
  const auto& names = app::drive_metric_names();
  const std::size_t column = app::metric_index(names, metric, "epsilon_um", "metric", "request");
  const app::SimulateRequest request = simulate_request(rpm, depth_mm, std::nullopt);
  const auto sweep = run_interruptible<app::DriveSweepReport>([&](const std::atomic<bool>& cancel) {
    return app::run_drive_sweep(c, app::Sweep{key, values}, stoppable(request, cancel), {seed},
                                threads, stop_on(cancel));
  });
  py::dict out = result_of(app::to_json(c, sweep, names[column]), c, sweep, column);
  out["columns"] = columns_of(app::sweep_table(sweep));
  return out;
}

py::dict plan(const io::Case& c, std::optional<double> axial_feed_mm) {
  app::PlanRequest request;
  if (axial_feed_mm) request.axial_feed_m = units::mm_to_m(*axial_feed_mm);
  const auto job = run_interruptible<app::PlanJobReport>(
      [&](const std::atomic<bool>&) { return app::run_plan(c, request); });
  return result_of(app::to_json(c, job), c, job);
}

py::dict force(const io::Case& c) {
  const app::ForceJobReport r = app::run_force(c);
  return result_of(app::to_json(c, r), c, r);
}

// The request of `cutdyn fit` from the Python arguments; every bad one named.
app::FitRequest fit_request(const std::string& path, int modes, std::optional<double> lo_hz,
                            std::optional<double> hi_hz, const std::string& direction,
                            const std::string& format, const std::string& units) {
  app::FitRequest r;
  r.file = path;
  Validator v;
  if (modes < 0) v.add("modes = " + std::to_string(modes) + ": must be 'auto' or at least 1");
  r.fit.modes = modes;
  r.fit.lo_hz = lo_hz;
  r.fit.hi_hz = hi_hz;
  if (!format.empty()) {
    r.file_options.format = parse_frf_format(format);
    if (!r.file_options.format) v.add("format = \"" + format + "\": must be frf, csv or uff");
  }
  if (!units.empty()) r.file_options.units = units;
  if (direction == "x" || direction == "y")
    r.direction = direction == "y" ? Direction::kY : Direction::kX;
  else if (!direction.empty())
    v.add("direction = \"" + direction + "\": must be x or y");
  v.throw_if_any("request");
  return r;
}

py::array_t<std::complex<double>> complex_array(const std::vector<std::complex<double>>& values) {
  py::array_t<std::complex<double>> a(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), a.mutable_data());
  return a;
}

// `cutdyn fit`: the report and text, the [[modes]] tables its --out writes, and the measured
// and fitted FRFs as arrays.
py::dict fit(const std::string& path, int modes, std::optional<double> lo_hz,
             std::optional<double> hi_hz, const std::string& direction, const std::string& format,
             const std::string& units) {
  const app::FitRequest request =
      fit_request(path, modes, lo_hz, hi_hz, direction, format, units);
  const auto r = run_interruptible<app::FitJobReport>(
      [&](const std::atomic<bool>&) { return app::run_fit(request); });
  py::dict out = result_of(app::to_json(r), r);
  out["modes_toml"] = app::modes_toml(r);
  py::dict columns;
  columns["frequency_hz"] = array_of(r.read.frf.frequency_hz);
  columns["receptance_m_per_n"] = complex_array(r.read.frf.receptance_m_per_n);
  if (!r.read.frf.coherence.empty()) columns["coherence"] = array_of(r.read.frf.coherence);
  columns["fitted_frequency_hz"] = array_of(r.fitted.frequency_hz);
  columns["fitted_receptance_m_per_n"] = complex_array(r.fitted.receptance_m_per_n);
  out["columns"] = columns;
  return out;
}

// `cutdyn identify`: the report and text, and the [cutting] table its --out writes.
py::dict identify(const io::Case& c, const std::vector<std::string>& force_files) {
  app::IdentifyRequest request;
  for (const std::string& f : force_files) request.force_files.emplace_back(f);
  request.names.where = "force_files";
  const auto r = run_interruptible<app::IdentifyJobReport>(
      [&](const std::atomic<bool>&) { return app::run_identify(c, request); });
  py::dict out = result_of(app::to_json(c, r), c, r);
  out["cutting_toml"] = app::cutting_table_toml(c, r);
  return out;
}

}  // namespace

void add_jobs(py::module_& m) {
  m.def("drive", &drive, py::arg("case"), py::arg("rpm") = py::none(),
        py::arg("depth_mm") = py::none(), py::arg("seed") = py::none(),
        py::arg("currents") = false);
  m.def("drive_sweep", &drive_sweep, py::arg("case"), py::arg("key"), py::arg("values"),
        py::arg("metric") = "", py::arg("rpm") = py::none(), py::arg("depth_mm") = py::none(),
        py::arg("seed") = py::none(), py::arg("threads") = 0);
  m.def("plan", &plan, py::arg("case"), py::arg("axial_feed_mm") = py::none());
  m.def("force", &force, py::arg("case"));
  m.def("fit", &fit, py::arg("path"), py::arg("modes") = 0, py::arg("lo_hz") = py::none(),
        py::arg("hi_hz") = py::none(), py::arg("direction") = "", py::arg("format") = "",
        py::arg("units") = "");
  m.def("identify", &identify, py::arg("case"), py::arg("force_files"));
}

}  // namespace cutdyn::python
