#include "cli/common.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <system_error>
#include <utility>
#include <variant>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/io/output.hpp"
#include "cutdyn/io/plot.hpp"
#include "cutdyn/stability/advice.hpp"

namespace cutdyn::cli {

io::Case load_case(const std::string& path, std::string_view default_example, std::ostream& err) {
  io::Case c = app::load_case(path, default_example);
  for (const std::string& w : c.warnings)
    err << "cutdyn: warning: " << c.source << ": " << w << "\n";
  return c;
}

void check_output_folder(Validator& v, const char* flag, const std::string& path) {
  if (path.empty()) return;
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  if (!parent.empty() && !std::filesystem::is_directory(parent))
    v.add(std::string(flag) + " = " + path + ": the folder " + parent.string() + " does not exist");
}

void write_csv(io::OutputTransaction& outputs, const std::string& path,
               const app::ReportTable& table) {
  app::write_csv(outputs.open(path), table);
}

app::RequestNames flag_names() {
  app::RequestNames n;
  n.where = "command line";
  n.rpm = "--rpm";
  n.depth = "--depth-mm";
  n.duration = "--duration-s";
  n.method = "--method";
  n.torque_constant = "--kt";
  n.inertia = "--inertia";
  n.base = "--base";
  n.idle = "--idle";
  n.loaded = "--loaded";
  n.measure = "--measure";
  n.bandwidth = "--bandwidth-hz";
  return n;
}

namespace {

// Both paths name the same file (a path that cannot be resolved names none).
bool same_file(const std::string& a, const std::string& b) {
  if (a.empty() || b.empty()) return false;
  std::error_code ec;
  const std::filesystem::path x = std::filesystem::weakly_canonical(a, ec);
  if (ec) return false;
  const std::filesystem::path y = std::filesystem::weakly_canonical(b, ec);
  return !ec && x == y;
}

}  // namespace

void check_outputs(const Outputs& o, const std::vector<std::string>& inputs) {
  if (!o.plot.empty()) io::check_figure_path(o.plot);
  Validator v;
  check_output_folder(v, "--out", o.csv);
  check_output_folder(v, "--json", o.json);
  check_output_folder(v, "--plot", o.plot);
  if (same_file(o.csv, o.json) || same_file(o.csv, o.plot) || same_file(o.json, o.plot))
    v.add("--out, --json and --plot must name different files");
  // An output that names an input would overwrite it. Only files count: a case argument may
  // name a built-in example instead.
  for (const auto& [flag, path] :
       {std::pair{"--out", &o.csv}, std::pair{"--json", &o.json}, std::pair{"--plot", &o.plot}}) {
    if (path->empty() || *path == "-") continue;
    for (const std::string& input : inputs) {
      std::error_code ec;
      if (std::filesystem::is_regular_file(input, ec) && same_file(*path, input))
        v.add(std::string(flag) + " = " + *path + ": it is an input of the command (" + input +
              ") and would be overwritten");
    }
  }
  v.throw_if_any("command line");
}

void commit_outputs(io::OutputTransaction& outputs, const Outputs& o, std::ostream& out) {
  outputs.commit();
  for (const std::string* f : {&o.csv, &o.json, &o.plot})
    if (!f->empty()) out << "  wrote " << (*f == "-" ? "standard output" : *f) << "\n";
}

std::function<void(int, int)> progress_reporter(std::ostream& err, std::string label) {
  if (!isatty(STDERR_FILENO)) return {};
  // Nothing for a run that ends within a second; then the count, rewritten in place, at most
  // ten times a second, and the last one with its line end.
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto last = start;
  bool shown = false;
  return [&err, label, start, last, shown](int done, int total) mutable {
    const auto now = Clock::now();
    const bool finished = done == total;
    if (!shown && now - start < std::chrono::seconds(1)) return;
    if (!finished && now - last < std::chrono::milliseconds(100)) return;
    last = now;
    shown = true;
    err << "\r" << label << ": " << done << "/" << total << (finished ? "\n" : "") << std::flush;
  };
}

}  // namespace cutdyn::cli
