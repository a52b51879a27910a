// The jobs' reports as JSON: one frame for every command (docs/json.md) — schema_version,
// command, source and the effective case — and each command's results. What `--json` writes,
// and what any other front end can send.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "cutdyn/app/drive.hpp"
#include "cutdyn/app/fit.hpp"
#include "cutdyn/app/force.hpp"
#include "cutdyn/app/identify.hpp"
#include "cutdyn/app/monitor.hpp"
#include "cutdyn/app/plan.hpp"
#include "cutdyn/app/simulate.hpp"
#include "cutdyn/app/stability.hpp"
#include "cutdyn/io/case_file.hpp"
#include "cutdyn/io/output.hpp"

namespace cutdyn::app {

/// Grows when a key is renamed, removed or changes its meaning (adding keys does not).
inline constexpr int kJsonSchemaVersion = 2;

/// {"schema_version", "command", "source", "case"}: the frame every document starts from.
nlohmann::json json_document(std::string_view command, const io::Case& c);

/// A table of named values, one row per point: what a CSV writes and a JSON array holds.
struct ReportTable {
  std::vector<std::string> columns;
  std::vector<std::vector<io::CsvCell>> rows;
};
/// The lobes, one row per speed: spindle_rpm, critical_depth_mm, chatter_hz, lobe,
/// bifurcation, beyond_limit (0/1), and duty_cycle, conventional_depth_mm,
/// conventional_chatter_hz for vibration-assisted turning.
ReportTable lobes_table(const LobesJobReport& report);
/// The traces of a milling simulation (thinned as recorded): time_s, fx_n, fy_n, force_n,
/// x_um, y_um, teeth_in_cut, cutting_force_n.
ReportTable trace_table(const MillingSimulationJobReport& report);
/// A milling sweep, one row per value: the key, the metrics of milling_metric_names() (NaN
/// where the cut has none, e.g. no surface location error), chatter (0/1).
ReportTable sweep_table(const MillingSweepJobReport& report);
/// The traces of a turning simulation, every run one after the other: process, time_s,
/// displacement_um, force_n, chip_thickness_um.
ReportTable trace_table(const TurningSimulationJobReport& report);
/// The traces of the drives over the last summary revolutions, every axis one after the
/// other: axis, time_s, axis_force_n, load_torque_nm, speed_rad_s, position_error_um,
/// epsilon_um.
ReportTable trace_table(const DriveReport& report);
/// A drive sweep, one row per value and axis: the key, axis, the metrics of
/// drive_metric_names() (NaN where the drive has none).
ReportTable sweep_table(const DriveSweepReport& report);

/// The table as CSV (io::CsvWriter: numbers in shortest round-trip form), NaN as an empty cell.
void write_csv(std::ostream& out, const ReportTable& table);

nlohmann::json to_json(const io::Case& c, const LobesJobReport& report);
/// A milling sweep: the metric plotted, and per value its metrics (null where NaN), chatter
/// and status.
nlohmann::json to_json(const io::Case& c, const MillingSweepJobReport& report,
                       const std::string& metric);
nlohmann::json to_json(const io::Case& c, const CheckJobReport& report);
nlohmann::json to_json(const io::Case& c, const TurningSimulationJobReport& report);
nlohmann::json to_json(const io::Case& c, const MillingSimulationJobReport& report);
nlohmann::json to_json(const io::Case& c, const ForceJobReport& report);
nlohmann::json to_json(const io::Case& c, const PlanJobReport& report);
nlohmann::json to_json(const io::Case& c, const DriveReport& report);
/// The summary of `monitor estimate`: per axis the estimate's filter, what the torque current
/// is, and the torque-sign warnings (it also keeps its `format` and `version`).
nlohmann::json to_json(const EstimateReport& report);
/// A sweep of the drives, with the metric it tabulates.
nlohmann::json to_json(const io::Case& c, const DriveSweepReport& report,
                       const std::string& metric);
/// `identify`: the cut, the coefficients in the case's units with their intervals, the samples
/// with their fitted forces and residuals, the fit's quality, notes and warnings.
nlohmann::json to_json(const io::Case& c, const IdentifyJobReport& report);
/// `cutdyn fit` has no case: the document names the FRF file instead.
nlohmann::json to_json(const FitJobReport& report);

}  // namespace cutdyn::app
