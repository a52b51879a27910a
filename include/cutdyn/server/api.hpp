// The web explorer's JSON API (`cutdyn serve`; docs/explorer.md), apart from any socket: a
// request (method, path, query, body) in, a response (status, type, body) out. It runs the
// job layer, so its numbers are the command line's: the reports are `--json`'s documents.
//
//   GET  /api/examples             {"examples": [names]}
//   GET  /api/case[?example=NAME]  the starting case (or an example): {"case", "source", "toml"}
//   GET  /api/schema               every case key: type, unit, choices, rule (io::case_schema)
//   POST /api/case                 a case checked: {"case": the effective case, "toml", "warnings"}
//   POST /api/lobes?method=&target_depth_mm=          `cutdyn lobes --json` (format=csv: its
//        --out CSV, byte for byte)
//   POST /api/check?rpm=&depth_mm=&method=            `cutdyn check --json`
//   POST /api/simulate?rpm=&depth_mm=&duration_s=&points=
//        `cutdyn simulate --json`, plus "traces" (its --out columns, at most `points` rows,
//        default 2000) and "spectrum" (of the displacement, app::trace_spectrum)
//
// A POST's body is a case as JSON: the case file's keys, or the `case` object of any --json
// output as it is. Its relative [[frf]] files are read from the starting case file's folder. Bad
// JSON, a bad case or a bad parameter: status 400 and
// {"error": the command line's message, "where", "problems": [...]}.
#pragma once

#include <atomic>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>

#include "cutdyn/io/case_file.hpp"

namespace cutdyn::server {

struct Request {
  std::string method;  // "GET", "POST"
  std::string path;    // "/api/lobes"
  std::map<std::string, std::string> query;
  std::string body;
};

struct Response {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
};

/// Thrown by a job when its request was cancelled (a newer one from the same page).
struct Cancelled {};

class Api {
 public:
  /// `start`: the case GET /api/case returns.
  explicit Api(io::Case start);

  /// Answers one request. `cancel`, when given and set while a job runs, stops the job at its
  /// next progress report (status 409, "cancelled"). Never throws for any input.
  Response handle(const Request& request, const std::atomic<bool>* cancel = nullptr) const;

 private:
  io::Case start_;
  std::filesystem::path folder_;  // the starting case file's folder (none for an example)
};

}  // namespace cutdyn::server
