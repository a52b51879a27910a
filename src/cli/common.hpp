// Pieces every command shares: loading the case, requiring keys, progress, formatting.
#pragma once

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "cli/commands.hpp"
#include "cutdyn/app/case_models.hpp"
#include "cutdyn/core/error.hpp"
#include "cutdyn/forces/oxley.hpp"
#include "cutdyn/io/case_file.hpp"
#include "cutdyn/io/output.hpp"
#include "cutdyn/stability/lobes.hpp"
#include "cutdyn/stability/milling.hpp"
#include "cutdyn/stability/turning.hpp"

namespace cutdyn::cli {

// The models of a case are the library's (cutdyn/app/case_models.hpp).
/// app::load_case, with the case's load warnings (an old key name) printed on `err` as
/// "cutdyn: warning: SOURCE: ...".
io::Case load_case(const std::string& path, std::string_view default_example, std::ostream& err);
using app::lobes_grid;
using app::milling_model;
using app::OxleyPrediction;
using app::predict_with_oxley;
using app::require_turning;
using app::turning_model;

/// One line: "Kc and Kt predicted by Oxley's theory for AISI1045 at 200 m/min, ...".
std::string oxley_summary(const io::Case& c, const OxleyPrediction& p);

/// Checks --out/--json/--plot before any work: figure format, existing folders, distinct files.
void check_outputs(const Outputs& o);

/// The stability method asked for: --method (`flag`), else the case's [lobes].method. Throws
/// InvalidInput naming --method and the names for an unknown one.
StabilityMethod asked_method(const io::Case& c, const std::string& flag);
/// Commits the outputs (they appear together) and lists the files written.
void commit_outputs(io::OutputTransaction& outputs, const Outputs& o, std::ostream& out);
/// Adds a problem to `v` if `path`'s folder does not exist.
void check_output_folder(Validator& v, const char* flag, const std::string& path);

/// Runs `check`; an InvalidInput it throws is rethrown naming `where` and prefixing `key`.
template <typename F>
void rethrow_as(const std::string& where, const std::string& key, F&& check) {
  try {
    check();
  } catch (const InvalidInput& e) {
    std::vector<std::string> problems;
    for (const std::string& p : e.problems()) problems.push_back(key + ": " + p);
    throw InvalidInput(problems, where);
  }
}

/// "6.736 mm", or "> 30 mm" when no boundary was found below the limit.
std::string depth_text(const CriticalDepth& b);

/// How `report_lobes` presents a lobe diagram.
struct LobesView {
  std::string description;  // one line about the model
  std::string method;
  double depth_max_m = 0.0;
  std::string title;                                      // figure title
  std::string label;                                      // the main curve's legend
  const std::vector<CriticalDepth>* reference = nullptr;  // e.g. the conventional lobes
  std::string reference_label;
  bool duty_cycle = false;               // add the duty_cycle column
  std::optional<double> target_depth_m;  // list the speed ranges stable at this depth
  std::vector<std::string> warnings;     // where the method is weak (printed and in --json)
};

/// Prints the summary table, lowest depth and stable pockets, and writes the CSV
/// (spindle_rpm,critical_depth_mm,chatter_hz,lobe,bifurcation,beyond_limit,...), JSON and
/// figure that `outputs` asks for, all or none.
void report_lobes(const io::Case& c, const LobesReport& report, const LobesView& view,
                  const Outputs& outputs, std::ostream& out, std::ostream& err);

/// What `report_check` adds for one process: the model line, the method, the lobe number,
/// lines after the margin, and extra JSON fields.
struct CheckView {
  std::string description;
  std::string method;
  int lobe = 0;
  std::vector<std::string> notes;
  nlohmann::json extra = nlohmann::json::object();
};

/// Prints the verdict of `cutdyn check` (stable?, critical depth, bifurcation and chatter
/// frequency, margin) and writes --json if asked.
void report_check(const io::Case& c, const CheckArgs& args, const CriticalDepth& b,
                  const CheckView& view, std::ostream& out);

/// Progress on stderr while it is a terminal ("lobes: 120/200 speeds"); silent otherwise.
std::function<void(int, int)> progress_reporter(std::ostream& err, std::string label);

/// A fixed-precision number for people: `digits` significant digits.
std::string human(double value, int digits = 4);

}  // namespace cutdyn::cli
