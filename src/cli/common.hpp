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
#include "cutdyn/app/detail/text.hpp"
#include "cutdyn/app/report_json.hpp"
#include "cutdyn/app/stability.hpp"
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

/// An output option and the file it names ("" when not given).
struct OutputFlag {
  std::string flag;
  std::string path;
};
std::vector<OutputFlag> output_flags(const Outputs& o);  // --out, --json, --plot

/// load_case for a command that writes `outputs`: they are checked (check_output_files)
/// before the case is read, against the case file, and after, against the files it names.
io::Case load_case(const std::string& path, std::string_view default_example, std::ostream& err,
                   const std::vector<OutputFlag>& outputs);
using app::lobes_grid;
using app::milling_process;
using app::OxleyPrediction;
using app::predict_with_oxley;
using app::require_turning;
using app::turning_process;

/// How the jobs name the command line's inputs: "command line", --rpm, --depth-mm,
/// --duration-s, --method.
app::RequestNames flag_names();

using app::json_document;  // the frame of every JSON document (cutdyn/app/report_json.hpp)
using app::kJsonSchemaVersion;

/// Checks the output files of a command before any work: existing folders, a known figure
/// format for --plot, no file named by two outputs (a figure's .dat and .gp companions and
/// "-" = /dev/stdout included), and none that is an input of the command: `inputs` (files the
/// command will read; a name that is not a file, such as a built-in example's, is ignored) and
/// every file read so far in the command's InputScope (the case and the files it names).
/// Throws InvalidInput listing every problem.
void check_output_files(const std::vector<OutputFlag>& outputs,
                        const std::vector<std::string>& inputs = {});
/// The same for --out/--json/--plot.
void check_outputs(const Outputs& o, const std::vector<std::string>& inputs = {});

/// Commits the outputs (they appear together) and lists the files written.
void commit_outputs(io::OutputTransaction& outputs, const Outputs& o, std::ostream& out);
/// Adds a problem to `v` if `path`'s folder does not exist.
void check_output_folder(Validator& v, const char* flag, const std::string& path);

/// Writes a report table as CSV to `path` within `outputs`; a NaN (a quantity a row has not)
/// is an empty cell.
void write_csv(io::OutputTransaction& outputs, const std::string& path,
               const app::ReportTable& table);

/// Progress on stderr while it is a terminal ("lobes: 120/200"), once the run has taken a
/// second (at most ten updates a second); silent otherwise.
std::function<void(int, int)> progress_reporter(std::ostream& err, std::string label);

using app::human;  // cutdyn/app/detail/text.hpp

}  // namespace cutdyn::cli
