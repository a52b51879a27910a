// The reports of the jobs rendered for people: the text `cutdyn` prints on standard output
// and the figure it draws, for every front end (the command line, a Python module, a web
// server) to render a report exactly alike. Warnings are not part of the text: each front
// end shows a report's `warnings` its own way (the command line on standard error). The
// equations behind the numbers are cited where the jobs compute them (cutdyn/app/*.hpp).
#pragma once

#include <cstddef>
#include <ostream>
#include <string>

#include "cutdyn/app/drive.hpp"
#include "cutdyn/app/fit.hpp"
#include "cutdyn/app/force.hpp"
#include "cutdyn/app/identify.hpp"
#include "cutdyn/app/monitor.hpp"
#include "cutdyn/app/plan.hpp"
#include "cutdyn/app/simulate.hpp"
#include "cutdyn/app/stability.hpp"
#include "cutdyn/io/case_file.hpp"
#include "cutdyn/io/plot.hpp"

namespace cutdyn::app {

// ---- simulate (milling): [Ermolaev2020] ---------------------------------------------------

/// The cut, the summary over the last revolutions, the verdict and the predicted depth.
void write_text(std::ostream& out, const io::Case& c, const MillingSimulationJobReport& report);
/// Two panels: the displacement over the whole run and the forces over the last revolutions.
io::PlotFigure figure(const MillingSimulationJobReport& report);

/// The table of a sweep: the swept value, the metric `column` of milling_metric_names(), the
/// mean force, the teeth in cut and the verdict.
void write_text(std::ostream& out, const io::Case& c, const MillingSweepJobReport& report,
                std::size_t column);
/// The metric `column` against the swept key, the runs that chatter marked.
io::PlotSpec figure(const io::Case& c, const MillingSweepJobReport& report, std::size_t column);

// ---- simulate (turning) and force: docs/models/turning.md, docs/models/oxley.md -----------

/// The cut, each process' growth rate and amplitude, and its predicted critical depth.
void write_text(std::ostream& out, const io::Case& c, const TurningSimulationJobReport& report);
/// The tool's displacement over the whole run, one series per process.
io::PlotSpec figure(const TurningSimulationJobReport& report);

/// Oxley's prediction (if any), Kc and Kf, the vibration's duty cycle, the forces.
void write_text(std::ostream& out, const io::Case& c, const ForceJobReport& report);
/// Oxley's forces against the uncut chip thickness when Kc is predicted and the cut does not
/// vibrate; else three vibration periods of the pulsed forces.
io::PlotSpec figure(const io::Case& c, const ForceJobReport& report);

// ---- lobes and check: docs/models/turning.md, docs/models/milling-stability.md ------------

/// The method and grid, the table of critical depths (at most about 20 rows), the lowest
/// depth, the stable pockets and, at a target depth, the stable speeds and the advice.
void write_text(std::ostream& out, const io::Case& c, const LobesJobReport& report);
/// The critical depth against the spindle speed, the stable region below it.
io::PlotSpec figure(const LobesJobReport& report);

/// The verdict at the report's speed and depth: stable?, critical depth, bifurcation and
/// chatter frequency, margin, and the method's warnings.
void write_text(std::ostream& out, const io::Case& c, const CheckJobReport& report);

// ---- drive: [Ermolaev2020], docs/models/feed-drive.md ------------------------------------

/// The cut, and for each axis its steady state, load torque, motor speed, kδ and δ, and the
/// position errors.
void write_text(std::ostream& out, const io::Case& c, const DriveReport& report);
/// Two panels over the last revolutions: ε of each axis and its motor speed about the mean.
io::PlotFigure figure(const DriveReport& report);

/// The table of a sweep: the swept value and, for each axis, the metric `column` of
/// drive_metric_names().
void write_text(std::ostream& out, const io::Case& c, const DriveSweepReport& report,
                std::size_t column);
/// The metric `column` of each axis against the swept key.
io::PlotSpec figure(const io::Case& c, const DriveSweepReport& report, std::size_t column);

// ---- plan: [Zenkin2012], docs/models/bore-milling.md --------------------------------------

/// The bore and cutter, the largest axial feed, the allowance split, speeds, chip, errors,
/// main time, the warnings and what the optimisation within [limits] found.
void write_text(std::ostream& out, const io::Case& c, const PlanJobReport& report);
/// Two panels: t0 and Δ1 against the axial feed S0, and t0 against the offset h. Needs the
/// report's trade_off (a case with [limits]).
io::PlotFigure figure(const PlanJobReport& report);

// ---- identify: [Altintas2012, ch. 2], docs/models/identification.md ----------------------

/// The cut and its test cuts, the coefficients with their 95 % intervals, the measured and
/// fitted mean force of each test cut, and the notes.
void write_text(std::ostream& out, const io::Case& c, const IdentifyJobReport& report);
/// Mean force per unit depth against the feed per tooth: measured points, fitted lines.
io::PlotSpec figure(const IdentifyJobReport& report);

// ---- fit: docs/models/modal-fitting.md ----------------------------------------------------

/// The file read, the fit's band and error, and the table of the fitted modes.
void write_text(std::ostream& out, const FitJobReport& report);
/// Two panels: magnitude (log) and phase of the measured and the fitted FRF, modes marked.
io::PlotFigure figure(const FitJobReport& report);

// ---- monitor: docs/models/monitor.md --------------------------------------------------------

/// A warning of a monitor job in words, "SOURCE: what" (the command line prints it after
/// "cutdyn: warning: ").
std::string warning_text(const MonitorWarning& warning);
/// An alarm in words, "overload on axis x at T s (level …, confirmed at T s)" (the command
/// line prints it after "cutdyn: alarm: ").
std::string alarm_text(const std::string& axis, const AlarmEvent& alarm);

/// The logs calibrated with, and each axis' constants and fits (steps 1 and 2).
void write_text(std::ostream& out, const CalibrateReport& report);
/// "monitor estimate: N samples[, K alarms]" and the filter of each axis (§4.1, §4.3), and
/// what force_sigma_n covers. (The command line prints it on standard error, after "cutdyn: ",
/// when the estimates themselves go to standard output.)
void write_text(std::ostream& out, const EstimateReport& report);
/// The reference runs and each axis' band: runs, cycle, bins, peak mean level.
void write_text(std::ostream& out, const TeachReport& report);

}  // namespace cutdyn::app
