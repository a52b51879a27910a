// The Python module's native part, `cutdyn._cutdyn` (docs/python.md): cases in, the job
// layer's reports out — the same jobs and the same JSON as the command line, so that no rule
// is written twice. Tables come back as numpy arrays (float64 for numbers, int64 for counts).
// `cutdyn/__init__.py` wraps these functions in result classes.
//
// Long jobs run with the GIL released on a worker thread; the calling thread checks for
// signals every 50 ms and, on Ctrl-C, asks the job to stop at its next progress report
// (KeyboardInterrupt once it has).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <exception>
#include <functional>
#include <future>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "cutdyn/app/render.hpp"
#include "cutdyn/app/report_json.hpp"
#include "cutdyn/app/simulate.hpp"
#include "cutdyn/app/stability.hpp"
#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/io/case_file.hpp"

namespace py = pybind11;

namespace cutdyn::python {
namespace {

// Thrown from a job's progress report when the caller pressed Ctrl-C (never reaches Python:
// run_interruptible raises the interrupt instead).
struct Cancelled : std::exception {
  const char* what() const noexcept override { return "cancelled"; }
};

// JSON ↔ Python through the json module: exact for every value a report holds.
py::object to_python(const nlohmann::json& j) {
  return py::module_::import("json").attr("loads")(j.dump());
}

nlohmann::json to_json(const py::handle& object, const std::string& where) {
  std::string text;
  try {
    text = py::module_::import("json")
               .attr("dumps")(object, py::arg("allow_nan") = false)
               .cast<std::string>();
  } catch (const py::error_already_set& e) {
    throw InvalidInput({std::string("not a case: ") + e.what()}, where);
  }
  return nlohmann::json::parse(text);
}

// Runs `job` with the GIL released on a worker thread. A signal on the calling thread (Ctrl-C)
// sets `cancel`, which a job's progress reports turn into Cancelled; the exception the signal's
// handler raised (KeyboardInterrupt) is raised once the job has stopped — also for a job without
// progress reports, which finishes first.
template <typename Result>
Result run_interruptible(const std::function<Result(const std::atomic<bool>& cancel)>& job) {
  std::atomic<bool> cancel{false};
  std::future<Result> result;
  std::optional<py::error_already_set> interrupted;
  {
    py::gil_scoped_release release;
    result = std::async(std::launch::async, [&] { return job(cancel); });
    while (result.wait_for(std::chrono::milliseconds(50)) != std::future_status::ready) {
      py::gil_scoped_acquire acquire;
      if (!interrupted && PyErr_CheckSignals() != 0) {
        cancel = true;
        interrupted.emplace();  // fetches the handler's exception
      }
    }
  }
  if (interrupted) {
    try {
      result.get();
    } catch (...) {  // Cancelled, or whatever the stopped job threw: the interrupt wins
    }
    throw std::move(*interrupted);
  }
  return result.get();
}

// A progress report that stops the job once `cancel` is set.
std::function<void(int, int)> stop_on(const std::atomic<bool>& cancel) {
  return [&cancel](int, int) {
    if (cancel) throw Cancelled();
  };
}

// The report as the command line prints it.
template <typename Report>
std::string text_of(const io::Case& c, const Report& r) {
  std::ostringstream out;
  app::write_text(out, c, r);
  return out.str();
}

// A report table as {column: numpy array}: float64 for numbers, int64 for counts, a list of
// str for text.
py::dict columns_of(const app::ReportTable& table) {
  py::dict out;
  for (std::size_t k = 0; k < table.columns.size(); ++k) {
    const auto kind = table.rows.empty() ? std::size_t{0} : table.rows.front()[k].index();
    if (kind == 2) {
      py::list text;
      for (const auto& row : table.rows) text.append(std::get<std::string>(row[k]));
      out[py::str(table.columns[k])] = text;
    } else if (kind == 1) {
      py::array_t<long long> a(static_cast<py::ssize_t>(table.rows.size()));
      auto v = a.mutable_unchecked<1>();
      for (std::size_t i = 0; i < table.rows.size(); ++i)
        v(static_cast<py::ssize_t>(i)) = std::get<long long>(table.rows[i][k]);
      out[py::str(table.columns[k])] = a;
    } else {
      py::array_t<double> a(static_cast<py::ssize_t>(table.rows.size()));
      auto v = a.mutable_unchecked<1>();
      for (std::size_t i = 0; i < table.rows.size(); ++i)
        v(static_cast<py::ssize_t>(i)) = std::get<double>(table.rows[i][k]);
      out[py::str(table.columns[k])] = a;
    }
  }
  return out;
}

py::dict lobes(const io::Case& c, const std::string& method, std::optional<double> target_depth_mm,
               int threads) {
  app::LobesRequest request;
  request.method = method;
  request.threads = threads;
  if (target_depth_mm) request.target_depth_m = units::mm_to_m(*target_depth_mm);
  request.names.depth = "target_depth_mm";
  const app::LobesJobReport r =
      run_interruptible<app::LobesJobReport>([&](const std::atomic<bool>& cancel) {
        app::LobesRequest stoppable = request;
        stoppable.progress = stop_on(cancel);
        return app::run_lobes(c, stoppable);
      });
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

// Overrides of the case's [simulate] table, named as the Python arguments.
app::SimulateRequest simulate_request(std::optional<double> rpm, std::optional<double> depth_mm,
                                      std::optional<double> duration_s) {
  app::SimulateRequest r;
  r.rpm = rpm;
  if (depth_mm) r.depth_m = units::mm_to_m(*depth_mm);
  r.duration_s = duration_s;
  return r;
}

// One simulation (`cutdyn simulate`): the traces as arrays (the columns of its --out), its
// report and text; milling or turning, as the case says.
py::dict simulate(const io::Case& c, std::optional<double> rpm, std::optional<double> depth_mm,
                  std::optional<double> duration_s) {
  const app::SimulateRequest request = simulate_request(rpm, depth_mm, duration_s);
  py::dict out;
  if (c.process == io::Process::kMilling) {
    const auto job = run_interruptible<app::MillingSimulationJobReport>(
        [&](const std::atomic<bool>&) { return app::simulate_milling_case(c, request); });
    out["columns"] = columns_of(app::trace_table(job));
    out["report"] = to_python(app::to_json(c, job));
    out["text"] = text_of(c, job);
  } else {
    const auto job = run_interruptible<app::TurningSimulationJobReport>(
        [&](const std::atomic<bool>&) { return app::simulate_turning_case(c, request); });
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
               std::optional<double> duration_s, int threads) {
  const auto& names = app::milling_metric_names();
  const std::size_t column = app::metric_index(names, metric, names.front(), "metric", "request");
  const app::SimulateRequest request = simulate_request(rpm, depth_mm, duration_s);
  // (The job refuses a case that is not milling, naming it.)
  const auto job = run_interruptible<app::MillingSweepJobReport>([&](const std::atomic<bool>&
                                                                         cancel) {
    return app::sweep_milling_case(c, app::Sweep{key, values}, request, threads, stop_on(cancel));
  });
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
      .def(py::init(
               [](const py::dict& d) { return io::parse_case_json(to_json(d, "dict"), "dict"); }),
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
        py::arg("target_depth_mm") = py::none(), py::arg("threads") = 0);
  m.def("check", &check, py::arg("case"), py::arg("rpm"), py::arg("depth_mm"),
        py::arg("method") = "");
  m.def("sweep", &sweep, py::arg("case"), py::arg("key"), py::arg("values"), py::arg("metric") = "",
        py::arg("rpm") = py::none(), py::arg("depth_mm") = py::none(),
        py::arg("duration_s") = py::none(), py::arg("threads") = 0);
  m.def("simulate", &simulate, py::arg("case"), py::arg("rpm") = py::none(),
        py::arg("depth_mm") = py::none(), py::arg("duration_s") = py::none());
}

}  // namespace cutdyn::python
