// The Python module's native part, `cutdyn._cutdyn` (docs/python.md): cases in, the job
// layer's reports out — the same jobs and the same JSON as the command line, so that no rule
// is written twice. Tables come back as numpy arrays (float64 for numbers, int64 for counts).
// `cutdyn/__init__.py` wraps these functions in result classes.
//
// Long jobs run with the GIL released on a worker thread; the calling thread checks for
// signals every 50 ms and, on Ctrl-C, asks the job to stop at its next progress report
// (KeyboardInterrupt once it has).
#include <pybind11/stl.h>

#include <atomic>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "common.hpp"
#include "cutdyn/app/render.hpp"
#include "cutdyn/app/report_json.hpp"
#include "cutdyn/app/simulate.hpp"
#include "cutdyn/app/stability.hpp"
#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/io/case_file.hpp"

namespace cutdyn::python {
namespace {

py::dict lobes(const io::Case& c, const std::string& method, std::optional<double> target_depth_mm,
               int threads, py::object progress) {
  app::LobesRequest request;
  request.method = method;
  request.threads = threads;
  if (target_depth_mm) request.target_depth_m = units::mm_to_m(*target_depth_mm);
  request.names.depth = "target_depth_mm";
  ProgressRelay relay(std::move(progress));
  const app::LobesJobReport r = run_interruptible<app::LobesJobReport>(
      [&](const std::atomic<bool>& cancel) {
        app::LobesRequest stoppable = request;
        stoppable.progress = relay.reporter(cancel);
        return app::run_lobes(c, stoppable);
      },
      &relay);
  py::dict out;
  out["columns"] = columns_of(app::lobes_table(r));
  out["report"] = to_python(app::to_json(c, r));
  out["text"] = text_of(c, r);
  return out;
}

py::dict check(const io::Case& c, double rpm, double depth_mm, const std::string& method) {
  app::CheckRequest request;
  request.rpm = rpm;
  request.depth_m = units::mm_to_m(depth_mm);
  request.method = method;
  // (The request's names default to the Python argument names: rpm, depth_mm, method.)
  const app::CheckJobReport r = run_interruptible<app::CheckJobReport>(
      [&](const std::atomic<bool>&) { return app::run_check(c, request); });
  py::dict out;
  out["report"] = to_python(app::to_json(c, r));
  out["text"] = text_of(c, r);
  return out;
}

// One simulation (`cutdyn simulate`): the traces as arrays (the columns of its --out), its
// report and text; milling or turning, as the case says.
py::dict simulate(const io::Case& c, std::optional<double> rpm, std::optional<double> depth_mm,
                  std::optional<double> duration_s) {
  const app::SimulateRequest request = simulate_request(rpm, depth_mm, duration_s);
  py::dict out;
  if (c.process == io::Process::kMilling) {
    const auto job =
        run_interruptible<app::MillingSimulationJobReport>([&](const std::atomic<bool>& cancel) {
          return app::simulate_milling_case(c, stoppable(request, cancel));
        });
    out["columns"] = columns_of(app::trace_table(job));
    out["report"] = to_python(app::to_json(c, job));
    out["text"] = text_of(c, job);
  } else {
    const auto job =
        run_interruptible<app::TurningSimulationJobReport>([&](const std::atomic<bool>& cancel) {
          return app::simulate_turning_case(c, stoppable(request, cancel));
        });
    out["columns"] = columns_of(app::trace_table(job));
    out["report"] = to_python(app::to_json(c, job));
    out["text"] = text_of(c, job);
  }
  return out;
}

// A milling sweep (`cutdyn simulate --sweep KEY=FROM:STEP:TO`): one row per value, the
// metrics as float64 arrays (NaN where a cut has none), its report and text.
py::dict sweep(const io::Case& c, const std::string& key, const std::vector<double>& values,
               const std::string& metric, std::optional<double> rpm, std::optional<double> depth_mm,
               std::optional<double> duration_s, int threads, py::object progress) {
  const auto& names = app::milling_metric_names();
  const std::size_t column = app::metric_index(names, metric, names.front(), "metric", "request");
  const app::SimulateRequest request = simulate_request(rpm, depth_mm, duration_s);
  // (The job refuses a case that is not milling, naming it.)
  ProgressRelay relay(std::move(progress));
  const auto job = run_interruptible<app::MillingSweepJobReport>(
      [&](const std::atomic<bool>& cancel) {
        return app::sweep_milling_case(c, app::Sweep{key, values}, stoppable(request, cancel),
                                       threads, relay.reporter(cancel));
      },
      &relay);
  py::dict out;
  out["columns"] = columns_of(app::sweep_table(job));
  out["report"] = to_python(app::to_json(c, job, names[column]));
  std::ostringstream text;
  app::write_text(text, c, job, column);
  out["text"] = text.str();
  return out;
}

}  // namespace

PYBIND11_MODULE(_cutdyn, m) {
  m.doc() = "cutdyn's native part: cases and the jobs of the command line (docs/python.md)";

  // cutdyn.CaseError(ValueError): the command line's message, one "where: problem" per line,
  // and the problems themselves as `.problems`, the place as `.where`.
  static py::exception<InvalidInput> case_error(m, "CaseError", PyExc_ValueError);
  case_error.attr("__doc__") =
      "Bad input: a case, a file or a request the command line would refuse (exit 2). The "
      "message is the command line's, one 'where: problem' line per problem; .problems lists "
      "them, .where names the file, 'dict' or 'request'.";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InvalidInput& e) {
      const std::string where = e.where().empty() ? "input" : e.where();
      std::string message;
      for (const std::string& problem : e.problems())
        message += (message.empty() ? "" : "\n") + where + ": " + problem;
      py::gil_scoped_acquire gil;
      py::object error = py::reinterpret_borrow<py::object>(case_error.ptr())(message);
      error.attr("problems") = py::cast(e.problems());
      error.attr("where") = py::str(where);
      PyErr_SetObject(case_error.ptr(), error.ptr());
    }
  });

  py::class_<io::Case>(m, "Case", "A case: a process, its structure and what to compute")
      .def_static(
          "from_toml", [](const std::string& path) { return io::load_case_file(path); },
          py::arg("path"), "Reads a case file (TOML), checking every key as the CLI does.")
      .def(py::init([](const py::dict& d) {
             return io::parse_case_json(to_json(d, "dict", "a case"), "dict");
           }),
           py::arg("case"),
           "A case from a dict with the case file's keys (the `case` object of any --json "
           "output is accepted as is), checked as a TOML file is.")
      .def(
          "to_dict", [](const io::Case& c) { return to_python(io::to_json(c)); },
          "The effective case in the case file's keys and units.")
      .def_property_readonly("source", [](const io::Case& c) { return c.source; })
      .def_property_readonly("warnings", [](const io::Case& c) { return c.warnings; })
      .def("__repr__", [](const io::Case& c) { return "<cutdyn.Case " + c.source + ">"; });

  m.def(
      "example", [](const std::string& name) { return io::load_example(name); }, py::arg("name"),
      "A built-in example case (`cutdyn example --list`).");
  m.def(
      "examples",
      [] {
        std::vector<std::string> names;
        for (const auto& [name, text] : io::examples()) names.emplace_back(name);
        return names;
      },
      "The names of the built-in example cases.");
  m.def("lobes", &lobes, py::arg("case"), py::arg("method") = "",
        py::arg("target_depth_mm") = py::none(), py::arg("threads") = 0,
        py::arg("progress") = py::none());
  m.def("check", &check, py::arg("case"), py::arg("rpm"), py::arg("depth_mm"),
        py::arg("method") = "");
  m.def("sweep", &sweep, py::arg("case"), py::arg("key"), py::arg("values"), py::arg("metric") = "",
        py::arg("rpm") = py::none(), py::arg("depth_mm") = py::none(),
        py::arg("duration_s") = py::none(), py::arg("threads") = 0,
        py::arg("progress") = py::none());
  m.def("simulate", &simulate, py::arg("case"), py::arg("rpm") = py::none(),
        py::arg("depth_mm") = py::none(), py::arg("duration_s") = py::none());
  add_jobs(m);
  add_monitor(m);
}

}  // namespace cutdyn::python
