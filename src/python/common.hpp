// What the parts of the Python module share (docs/python.md): JSON ↔ Python, report tables as
// numpy arrays, and running a job with the GIL released so that Ctrl-C stops it.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <atomic>
#include <chrono>
#include <exception>
#include <functional>
#include <future>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "cutdyn/app/render.hpp"
#include "cutdyn/app/report_json.hpp"
#include "cutdyn/io/case_file.hpp"

namespace cutdyn::python {

namespace py = pybind11;

/// Thrown from a job's progress report when the caller pressed Ctrl-C (never reaches Python:
/// run_interruptible raises the interrupt instead).
struct Cancelled : std::exception {
  const char* what() const noexcept override { return "cancelled"; }
};

/// JSON → Python objects directly (a non-finite number, which JSON text cannot hold, as
/// None); Python → JSON through the json module. Exact for every value a report holds. A Python
/// object that is not JSON (or holds NaN) throws InvalidInput naming `where`: "not `what`: …".
py::object to_python(const nlohmann::json& j);
nlohmann::json to_json(const py::handle& object, const std::string& where, const std::string& what);

/// A report table as {column: numpy array}: float64 for numbers, int64 for counts, a list of
/// str for text.
py::dict columns_of(const app::ReportTable& table);
/// A numpy float64 array holding `values`.
py::array_t<double> array_of(const std::vector<double>& values);

/// A progress report that stops the job once `cancel` is set.
std::function<void(int, int)> stop_on(const std::atomic<bool>& cancel);
/// A simulation request: overrides of the case's [simulate] table, named as the Python
/// arguments (rpm, depth_mm, duration_s).
app::SimulateRequest simulate_request(std::optional<double> rpm, std::optional<double> depth_mm,
                                      std::optional<double> duration_s);
/// The request with its simulations stopped once `cancel` is set.
app::SimulateRequest stoppable(app::SimulateRequest request, const std::atomic<bool>& cancel);

namespace detail {
/// A thread that runs one task at a time, kept for the module's lifetime: a job on it finds
/// the OpenMP team of its previous job alive, as a C++ program's main thread does (a fresh
/// thread per call made each call 2–5 % slower; docs/benchmarks.md).
class Worker;
/// An idle worker (made when none is idle, so that concurrent calls from several Python
/// threads each have one), and its return.
Worker* acquire_worker();
void release_worker(Worker* worker);
void run_on(Worker* worker, std::function<void()> task);
}  // namespace detail

/// A Python callable progress(done, total) fed with a job's progress reports: the job records
/// the counts on its worker thread (reporter), and run_interruptible's polling loop calls the
/// callable on the calling thread, with the GIL, when they have moved (deliver) — at most every
/// 50 ms, and once at the end. An exception the callable raises stops the job and is raised.
class ProgressRelay {
 public:
  explicit ProgressRelay(py::object callback) : callback_(std::move(callback)) {}
  /// The job's progress report: records the counts, then stops the job once `cancel` is set.
  std::function<void(int, int)> reporter(const std::atomic<bool>& cancel) {
    return [this, &cancel](int done, int total) {
      total_ = total;
      done_ = done;
      if (cancel) throw Cancelled();
    };
  }
  /// Calls the callable if the count has moved since the last call (GIL held).
  void deliver() {
    const int done = done_;
    if (callback_.is_none() || done < 0 || done == shown_) return;
    shown_ = done;
    callback_(done, total_.load());
  }

 private:
  py::object callback_;
  std::atomic<int> done_{-1}, total_{0};
  int shown_ = -1;
};

/// Runs `job` with the GIL released on a kept worker thread. A signal on the calling thread
/// (Ctrl-C) sets `cancel`, which a job's progress reports turn into Cancelled; the exception
/// the signal's handler raised (KeyboardInterrupt) is raised once the job has stopped — also
/// for a job without progress reports, which finishes first. `relay`, if given, passes the
/// job's progress to a Python callable (ProgressRelay).
template <typename Result>
Result run_interruptible(const std::function<Result(const std::atomic<bool>& cancel)>& job,
                         ProgressRelay* relay = nullptr) {
  std::atomic<bool> cancel{false};
  auto task = std::make_shared<std::packaged_task<Result()>>([&] { return job(cancel); });
  std::future<Result> result = task->get_future();
  std::optional<py::error_already_set> interrupted;
  {
    py::gil_scoped_release release;
    detail::Worker* worker = detail::acquire_worker();
    detail::run_on(worker, [task] { (*task)(); });
    while (result.wait_for(std::chrono::milliseconds(50)) != std::future_status::ready) {
      py::gil_scoped_acquire acquire;
      if (!interrupted && PyErr_CheckSignals() != 0) {
        cancel = true;
        interrupted.emplace();  // fetches the handler's exception
      }
      if (relay && !interrupted) {
        try {
          relay->deliver();
        } catch (py::error_already_set& e) {  // the callable raised: stop, and raise it
          cancel = true;
          interrupted.emplace(std::move(e));
        }
      }
    }
    detail::release_worker(worker);
  }
  if (relay && !interrupted &&
      result.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
    try {
      relay->deliver();  // the last count
    } catch (py::error_already_set& e) {
      interrupted.emplace(std::move(e));
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

/// The report as the command line prints it.
template <typename... Args>
std::string text_of(const Args&... args) {
  std::ostringstream out;
  app::write_text(out, args...);
  return out.str();
}

/// {"report": the --json document, "text": what the command prints}: every job's result.
template <typename... Args>
py::dict result_of(const nlohmann::json& report, const Args&... args) {
  py::dict out;
  out["report"] = to_python(report);
  out["text"] = text_of(args...);
  return out;
}

// The module's further parts (module.cpp has the cases and the stability and simulation jobs).
void add_jobs(py::module_& m);     // drive, drive_sweep, plan, force, fit, identify
void add_monitor(py::module_& m);  // monitor_calibrate, monitor_estimate, monitor_teach

}  // namespace cutdyn::python
