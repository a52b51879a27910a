#include "common.hpp"

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn::python {

py::object to_python(const nlohmann::json& j) {
  return py::module_::import("json").attr("loads")(j.dump());
}

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
  return nlohmann::json::parse(text);
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
