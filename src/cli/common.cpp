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
#include "cutdyn/io/inputs.hpp"
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

std::vector<OutputFlag> output_flags(const Outputs& o) {
  return {{"--out", o.csv}, {"--json", o.json}, {"--plot", o.plot}};
}

io::Case load_case(const std::string& path, std::string_view default_example, std::ostream& err,
                   const std::vector<OutputFlag>& outputs) {
  check_output_files(outputs, {path});
  io::Case c = load_case(path, default_example, err);
  check_output_files(outputs);
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

// The identity of an output target for telling two outputs apart: "-" and the other names of
// standard output alike, else the absolute, normalised path with links resolved.
std::string output_identity(const std::string& path) {
  if (const int stream = io::standard_stream(path); stream != 0)
    return stream == 1 ? "<standard output>" : "<standard error>";
  std::error_code ec;
  const std::filesystem::path canonical = std::filesystem::weakly_canonical(path, ec);
  return (ec ? std::filesystem::path(path) : canonical).lexically_normal().string();
}

}  // namespace

void check_output_files(const std::vector<OutputFlag>& outputs,
                        const std::vector<std::string>& inputs) {
  for (const std::string& input : inputs) io::note_input(input);
  Validator v;
  // Every file the outputs write, with the option that writes it.
  std::vector<std::pair<std::string, std::string>> files;
  for (const OutputFlag& o : outputs) {
    if (o.path.empty()) continue;
    check_output_folder(v, o.flag.c_str(), o.path);
    std::error_code ec;
    if (io::standard_stream(o.path) == 0 && std::filesystem::is_directory(o.path, ec))
      v.add(o.flag + " = " + o.path + ": is a folder (name a file in it)");
    if (o.flag == "--plot") {
      io::check_figure_path(o.path);
      const std::vector<std::filesystem::path> written = io::figure_files(o.path);
      files.emplace_back(o.flag, o.path);
      for (std::size_t i = 1; i < written.size(); ++i)
        files.emplace_back(o.flag + " (its " + written[i].extension().string().substr(1) +
                               " file " + written[i].string() + ")",
                           written[i].string());
    } else {
      files.emplace_back(o.flag, o.path);
    }
  }
  for (std::size_t i = 0; i < files.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j)
      if (output_identity(files[i].second) == output_identity(files[j].second)) {
        v.add(files[j].first + " and " + files[i].first + " name the same file (" +
              files[i].second + ")");
      }
    if (const std::string problem = io::input_overwrite_problem(files[i].second, files[i].first);
        !problem.empty())
      v.add(problem);
  }
  v.throw_if_any("command line");
}

void check_outputs(const Outputs& o, const std::vector<std::string>& inputs) {
  check_output_files(output_flags(o), inputs);
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
