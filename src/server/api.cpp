#include "cutdyn/server/api.hpp"

#include <charconv>
#include <cmath>
#include <exception>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <utility>

#include "cutdyn/app/report_json.hpp"
#include "cutdyn/app/simulate.hpp"
#include "cutdyn/app/stability.hpp"
#include "cutdyn/core/error.hpp"
#include "cutdyn/core/spectrum.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn::server {
namespace {

using nlohmann::json;

// (Text that is not UTF-8 — a message quoting a bad body — is written with U+FFFD.)
Response json_response(int status, const json& body) {
  return {status, "application/json", body.dump(-1, ' ', false, json::error_handler_t::replace)};
}

Response error_response(int status, const std::string& where,
                        const std::vector<std::string>& problems) {
  std::string message;
  for (const std::string& p : problems) message += (message.empty() ? "" : "\n") + where + ": " + p;
  return json_response(status, {{"error", message}, {"where", where}, {"problems", problems}});
}

// The query's parameters: each known (a number, or text), none unknown; every problem named.
class Query {
 public:
  Query(const std::map<std::string, std::string>& query, std::set<std::string> known)
      : query_(query) {
    for (const auto& [key, value] : query)
      if (!known.count(key)) v_.add(key + ": not a parameter of this request");
  }
  std::optional<double> number(const std::string& key) {
    const auto it = query_.find(key);
    if (it == query_.end() || it->second.empty()) return std::nullopt;
    double x = 0.0;
    const std::string& text = it->second;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), x);
    if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(x)) {
      v_.add(key + " = \"" + text + "\": not a finite number");
      return std::nullopt;
    }
    return x;
  }
  std::string text(const std::string& key) {
    const auto it = query_.find(key);
    return it == query_.end() ? std::string() : it->second;
  }
  void throw_if_any() { v_.throw_if_any("request"); }

 private:
  const std::map<std::string, std::string>& query_;
  Validator v_;
};

// The body's case: JSON, then the case file's rules; its [[frf]] files are read by `read_frf`.
io::Case case_of(const std::string& body, const io::FrfFileReader& read_frf) {
  json j;
  try {
    j = json::parse(body);
  } catch (const json::exception& e) {  // parse_error, and out_of_range for a number like 1e999
    throw InvalidInput({std::string("not JSON: ") + e.what()}, "body");
  }
  return io::parse_case_json(j, "body", read_frf);
}

// Whether `path` lies within `folder` (both absolute and normalised, links resolved).
bool within(const std::filesystem::path& path, const std::filesystem::path& folder) {
  auto p = path.begin();
  for (auto f = folder.begin(); f != folder.end(); ++f, ++p) {
    if (f->empty()) continue;  // a trailing separator
    if (p == path.end() || *p != *f) return false;
  }
  return true;
}

std::function<void(int, int)> stop_on(const std::atomic<bool>* cancel) {
  if (!cancel) return {};
  return [cancel](int, int) {
    if (*cancel) throw Cancelled{};
  };
}

// `cutdyn lobes --json`, or with format=csv its --out CSV.
Response lobes(const io::Case& c, Query& q, const std::atomic<bool>* cancel) {
  app::LobesRequest r;
  r.method = q.text("method");
  if (const auto depth = q.number("target_depth_mm")) r.target_depth_m = units::mm_to_m(*depth);
  const std::string format = q.text("format");
  q.throw_if_any();
  if (format != "" && format != "json" && format != "csv")
    throw InvalidInput({"format = \"" + format + "\": must be json or csv"}, "request");
  r.progress = stop_on(cancel);
  r.names.depth = "target_depth_mm";
  const app::LobesJobReport report = app::run_lobes(c, r);
  if (format != "csv") return json_response(200, app::to_json(c, report));
  std::ostringstream csv;
  app::write_csv(csv, app::lobes_table(report));
  return {200, "text/csv; charset=utf-8", csv.str()};
}

json check(const io::Case& c, Query& q) {
  app::CheckRequest r;
  const auto rpm = q.number("rpm");
  const auto depth = q.number("depth_mm");
  r.method = q.text("method");
  q.throw_if_any();
  Validator v;
  if (!rpm) v.add("rpm: missing");
  if (!depth) v.add("depth_mm: missing");
  v.throw_if_any("request");
  r.rpm = *rpm;
  r.depth_m = units::mm_to_m(*depth);
  return app::to_json(c, app::run_check(c, r));
}

// At most `points` rows of a table, evenly spread (every k-th), as {column: [values]}.
json thinned(const app::ReportTable& table, std::size_t points) {
  const std::size_t n = table.rows.size();
  const std::size_t every = n > points ? (n + points - 1) / points : 1;
  json out = json::object();
  for (std::size_t k = 0; k < table.columns.size(); ++k) {
    json column = json::array();
    for (std::size_t i = 0; i < n; i += every)
      std::visit([&](const auto& v) { column.push_back(v); }, table.rows[i][k]);
    out[table.columns[k]] = std::move(column);
  }
  return out;
}

// The amplitude spectrum (µm) of displacements over the second half of their record (the
// steady part), or null when the record is too short or not evenly sampled.
json spectrum(const std::vector<double>& time_s,
              const std::vector<std::pair<std::string, const std::vector<double>*>>& series) {
  const std::size_t n = time_s.size(), from = n / 2;
  if (n - from < 16) return nullptr;
  const double dt = time_s[from + 1] - time_s[from];
  for (std::size_t i = from + 1; i < n; ++i)
    if (std::abs(time_s[i] - time_s[i - 1] - dt) > 1e-6 * dt) return nullptr;
  json out{{"from_s", time_s[from]}};
  for (const auto& [name, values] : series) {
    std::vector<double> um(values->begin() + static_cast<std::ptrdiff_t>(from), values->end());
    for (double& x : um) x = units::m_to_um(x);
    const Spectrum s = amplitude_spectrum(um, dt);
    out["frequency_hz"] = s.frequency_hz;
    out[name] = s.amplitude;
  }
  return out;
}

json simulate(const io::Case& c, Query& q, const std::atomic<bool>* cancel) {
  app::SimulateRequest r;
  r.rpm = q.number("rpm");
  if (const auto depth = q.number("depth_mm")) r.depth_m = units::mm_to_m(*depth);
  r.duration_s = q.number("duration_s");
  const auto points = q.number("points");
  q.throw_if_any();
  if (points && !(*points >= 10 && *points <= 1e6))
    throw InvalidInput({"points = " + std::to_string(*points) + ": must be 10 to 1e6"}, "request");
  const auto max_points = static_cast<std::size_t>(points.value_or(2000));
  r.progress = stop_on(cancel);
  if (c.process == io::Process::kMilling) {
    const auto job = app::simulate_milling_case(c, r);
    json doc = app::to_json(c, job);
    doc["traces"] = thinned(app::trace_table(job), max_points);
    doc["spectrum"] =
        spectrum(job.result.time_s, {{"x_um", &job.result.x_m}, {"y_um", &job.result.y_m}});
    return doc;
  }
  const auto job = app::simulate_turning_case(c, r);
  json doc = app::to_json(c, job);
  doc["traces"] = thinned(app::trace_table(job), max_points);
  if (!job.runs.empty())
    doc["spectrum"] = spectrum(job.runs.front().result.time_s,
                               {{"displacement_um", &job.runs.front().result.displacement_m}});
  return doc;
}

json case_document(const io::Case& c) {
  return {
      {"case", io::to_json(c)}, {"source", c.source}, {"toml", c.text}, {"warnings", c.warnings}};
}

}  // namespace

Api::Api(io::Case start, const std::filesystem::path& data_folder) : start_(std::move(start)) {
  // By the name the case file gives and by the name its echo gives (GET /api/case).
  for (const io::FrfTable& t : start_.frfs) {
    start_files_[t.file] = t.path;
    start_files_[t.path.string()] = t.path;
  }
  if (data_folder.empty()) return;
  std::error_code ec;
  data_folder_ = std::filesystem::canonical(data_folder, ec);
  if (ec || !std::filesystem::is_directory(data_folder_, ec))
    throw InvalidInput({"--data = " + data_folder.string() + ": not a folder"}, "command line");
}

FrfReadResult Api::read_frf(const std::string& file, const FrfFileOptions& options) const {
  namespace fs = std::filesystem;
  // The starting case's own files, by the names it gives them (the page sends them back).
  if (const auto it = start_files_.find(file); it != start_files_.end())
    return reread(file, it->second, options);
  // One answer for every path outside the data folder, whether it exists or not.
  const auto refuse = [&]() -> FrfReadResult {
    throw InvalidInput({"not a file the server reads: name a file of its data folder (cutdyn "
                        "serve --data DIR) by its path within the folder, or one of the "
                        "starting case's [[frf]] files"},
                       "request");
  };
  const fs::path name(file);
  if (data_folder_.empty() || name.empty() || name.has_root_path()) return refuse();
  for (const fs::path& part : name)
    if (part == "..") return refuse();
  std::error_code ec;
  const fs::path resolved = fs::weakly_canonical(data_folder_ / name, ec);
  if (ec || !within(resolved, data_folder_)) return refuse();  // a link out of the folder
  if (!fs::is_regular_file(resolved, ec))
    throw InvalidInput({"no such file in the data folder"}, file);
  return reread(file, resolved, options);
}

// Reads `path`, the problems naming the file as the request does (not the server's path).
FrfReadResult Api::reread(const std::string& file, const std::filesystem::path& path,
                          const FrfFileOptions& options) {
  try {
    return read_frf_file(path, options);
  } catch (const InvalidInput& e) {
    throw InvalidInput(e.problems(), file);
  }
}

Response Api::handle(const Request& request, const std::atomic<bool>* cancel) const {
  const io::FrfFileReader reader = [this](const std::string& file, const FrfFileOptions& options) {
    return read_frf(file, options);
  };
  try {
    const std::string& path = request.path;
    if (request.method == "GET") {
      if (path == "/api/examples") {
        json names = json::array();
        for (const auto& [name, text] : io::examples()) names.push_back(name);
        return json_response(200, {{"examples", names}});
      }
      if (path == "/api/schema") return json_response(200, io::case_schema());
      if (path == "/api/case") {
        if (const auto it = request.query.find("example"); it != request.query.end())
          return json_response(200, case_document(io::load_example(it->second)));
        return json_response(200, case_document(start_));
      }
    } else if (request.method == "POST") {
      if (path == "/api/case") {
        Query q(request.query, {});
        q.throw_if_any();
        return json_response(200, case_document(case_of(request.body, reader)));
      }
      if (path == "/api/lobes" || path == "/api/check" || path == "/api/simulate") {
        const io::Case c = case_of(request.body, reader);
        if (path == "/api/lobes") {
          Query q(request.query, {"method", "target_depth_mm", "format"});
          return lobes(c, q, cancel);
        }
        if (path == "/api/check") {
          Query q(request.query, {"rpm", "depth_mm", "method"});
          return json_response(200, check(c, q));
        }
        Query q(request.query, {"rpm", "depth_mm", "duration_s", "points"});
        return json_response(200, simulate(c, q, cancel));
      }
    }
    return error_response(404, "request", {request.method + " " + path + ": no such request"});
  } catch (const InvalidInput& e) {
    return error_response(400, e.where().empty() ? "input" : e.where(), e.problems());
  } catch (const Cancelled&) {
    return error_response(409, "request", {"cancelled: a newer request from the same page"});
  } catch (const std::exception& e) {
    return error_response(500, "server", {e.what()});
  }
}

}  // namespace cutdyn::server
