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
// output as it is. Bad JSON, a bad case or a bad parameter: status 400 and
// {"error": the command line's message, "where", "problems": [...]}.
//
// The server reads no path a request names. A case's [[frf]] `file` may only be one of the
// starting case's own [[frf]] files (by the name that case gives it, as GET /api/case shows
// it), or a file of the data folder the server was started with (`--data DIR`), named by its
// path within the folder: no absolute path, no "..", no link that leads out of it. Anything
// else gets one answer, the same whether the path exists or not.
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
  /// `start`: the case GET /api/case returns. `data_folder`: the folder whose files a
  /// request's case may name (none when empty). Throws InvalidInput if it is not a folder.
  explicit Api(io::Case start, const std::filesystem::path& data_folder = {});

  /// Answers one request. `cancel`, when given and set while a job runs, stops the job at its
  /// next progress report (status 409, "cancelled"). Never throws for any input.
  Response handle(const Request& request, const std::atomic<bool>* cancel = nullptr) const;

 private:
  FrfReadResult read_frf(const std::string& file, const FrfFileOptions& options) const;
  static FrfReadResult reread(const std::string& file, const std::filesystem::path& path,
                              const FrfFileOptions& options);

  io::Case start_;
  std::map<std::string, std::filesystem::path> start_files_;  // [[frf]] file as named → path
  std::filesystem::path data_folder_;                         // canonical; empty: none
};

}  // namespace cutdyn::server
