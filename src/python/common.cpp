#include "common.hpp"

#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn::python {

py::object to_python(const nlohmann::json& j) {
  using Type = nlohmann::json::value_t;
  switch (j.type()) {
    case Type::boolean:
      return py::bool_(j.get<bool>());
    case Type::number_integer:
      return py::int_(j.get<std::int64_t>());
    case Type::number_unsigned:
      return py::int_(j.get<std::uint64_t>());
    case Type::number_float: {
      const double x = j.get<double>();
      return std::isfinite(x) ? py::object(py::float_(x)) : py::object(py::none());
    }
    case Type::string:
      return py::str(j.get_ref<const std::string&>());
    case Type::array: {
      py::list list(j.size());
      std::size_t i = 0;
      for (const auto& item : j) list[i++] = to_python(item);
      return list;
    }
    case Type::object: {
      py::dict dict;
      for (const auto& [key, value] : j.items()) dict[py::str(key)] = to_python(value);
      return dict;
    }
    default:
      return py::none();
  }
}

namespace detail {

class Worker {
 public:
  Worker() : thread_([this] { loop(); }) { thread_.detach(); }  // lives as long as the process
  void run(std::function<void()> task) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      task_ = std::move(task);
    }
    ready_.notify_one();
  }

 private:
  void loop() {
    for (;;) {
      std::function<void()> task;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        ready_.wait(lock, [this] { return static_cast<bool>(task_); });
        task = std::move(task_);
        task_ = nullptr;
      }
      task();  // a packaged task: what it throws goes to its future
    }
  }
  std::mutex mutex_;
  std::condition_variable ready_;
  std::function<void()> task_;
  std::thread thread_;
};

namespace {
std::mutex g_pool_mutex;
std::vector<Worker*>& idle_workers() {
  static auto* idle = new std::vector<Worker*>();  // never destroyed: its threads live on
  return *idle;
}
}  // namespace

Worker* acquire_worker() {
  std::lock_guard<std::mutex> lock(g_pool_mutex);
  auto& idle = idle_workers();
  if (idle.empty()) return new Worker();  // kept for the process' lifetime
  Worker* w = idle.back();
  idle.pop_back();
  return w;
}

void release_worker(Worker* worker) {
  std::lock_guard<std::mutex> lock(g_pool_mutex);
  idle_workers().push_back(worker);
}

void run_on(Worker* worker, std::function<void()> task) { worker->run(std::move(task)); }

}  // namespace detail

nlohmann::json to_json(const py::handle& object, const std::string& where,
                       const std::string& what) {
  std::string text;
  try {
    text = py::module_::import("json")
               .attr("dumps")(object, py::arg("allow_nan") = false)
               .cast<std::string>();
  } catch (const py::error_already_set& e) {
    throw InvalidInput({"not " + what + ": " + py::str(e.value()).cast<std::string>()}, where);
  }
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // an int too large for a double: 10**400
    throw InvalidInput({"not " + what + ": " + e.what()}, where);
  }
}

py::array_t<double> array_of(const std::vector<double>& values) {
  py::array_t<double> a(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), a.mutable_data());
  return a;
}

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

std::function<void(int, int)> stop_on(const std::atomic<bool>& cancel) {
  return [&cancel](int, int) {
    if (cancel) throw Cancelled();
  };
}

app::SimulateRequest simulate_request(std::optional<double> rpm, std::optional<double> depth_mm,
                                      std::optional<double> duration_s) {
  app::SimulateRequest r;
  r.rpm = rpm;
  if (depth_mm) r.depth_m = units::mm_to_m(*depth_mm);
  r.duration_s = duration_s;
  return r;
}

app::SimulateRequest stoppable(app::SimulateRequest request, const std::atomic<bool>& cancel) {
  request.progress = stop_on(cancel);
  return request;
}

}  // namespace cutdyn::python
