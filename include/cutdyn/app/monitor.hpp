// The monitor's jobs (docs/models/monitor.md): calibrate the axes from logs, estimate the
// cutting force from a current log as it arrives (with alarms against a taught band), and
// teach the band from reference runs. Each takes files and options and returns a Report; a
// front end parses its input, renders the Report and writes the files it asks for
// (monitor_files.hpp). Errors in the input throw cutdyn::InvalidInput naming the file and
// line; what happens along the way (warnings, alarms) goes to a MonitorListener as it
// happens and into the Report.
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "cutdyn/app/monitor_files.hpp"
#include "cutdyn/app/request.hpp"
#include "cutdyn/monitor/calibration.hpp"
#include "cutdyn/monitor/current_csv.hpp"
#include "cutdyn/monitor/force_band.hpp"
#include "cutdyn/monitor/force_estimator.hpp"

namespace cutdyn::app {

/// Something a job met that the user should know; `kind` says which, the other fields what
/// it is about (the message of each kind is in its comment).
struct MonitorWarning {
  enum class Kind {
    kBadLine,             // `message` ("line N: what"): a bad line of `source`, skipped
    kBadLinesSkipped,     // `count` bad lines of `source` skipped in all
    kFit,                 // a calibration fit's warning `message` for `axis`
    kTorqueSign,          // the torque sign of `axis` in doubt from `line` (`time_s`): kSignDoubt
    kTorqueSignCount,     // ... at `count` samples in all
    kUncertaintyUnknown,  // the calibration `source` of `axis` has no known uncertainty
    kNoBand,              // the band file `source` has no band for `axis`: no alarms on it
    kBandwidthMismatch,   // the band was taught with f_b = `value`, estimated with `other`
    kNoToothPeriod,       // teach without the cut's rpm and teeth (or average_s): wide band
  };
  Kind kind = Kind::kBadLine;
  std::string source;  // the file (or "calibration", "teach-in")
  std::string axis;
  std::size_t line = 0, count = 0;
  double time_s = 0.0, value = 0.0, other = 0.0;
  std::string message;
};

/// Why the torque sign is in doubt (docs/models/monitor.md §4.5), and what force_sigma_n
/// covers (§4.3): the texts the estimate states.
inline constexpr const char* kSignDoubt =
    "the motor torque may be against the motion here (a load that aids the motion, or "
    "braking), and the log has no rotor_angle_rad column: the estimate assumes the torque has "
    "the sign of the motion and may have the wrong sign; log the electrical rotor angle for the "
    "signed torque current (docs/models/monitor.md §4.5)";
inline constexpr const char* kSigmaCovers =
    "force_sigma_n is the standard uncertainty of force_n as an estimate of the filtered force "
    "(current and speed noise, the calibration's parameter uncertainties); the filter itself is "
    "stated, not an error: force_n is the true force through it";

/// What a running job reports as it happens (all of it is in its Report too), so that a long
/// or live run is not silent and one stopped by an error has shown what came before.
struct MonitorListener {
  std::function<void(const MonitorWarning&)> warning;
  std::function<void(const std::string& axis, const AlarmEvent&)> alarm;
};

// ---- calibrate -------------------------------------------------------------------------

/// A value given for one axis ("x") or for every axis ("").
struct AxisValue {
  std::string axis;
  double value = 0.0;
};

struct CalibrateOptions {
  std::vector<std::string> idle;    // no-cut logs at constant speeds (step 1)
  std::vector<std::string> loaded;  // logs with a reference force column (step 2)
  LogTexts texts;    // logs in memory, by the name idle or loaded gives them (others are files)
  std::string base;  // a calibration file or "zheng2012": KT, J, measure, the values not fitted
  std::vector<AxisValue> torque_constant_nm_per_a;  // KT, winning over the base
  std::vector<AxisValue> inertia_kg_m2;             // J, winning over the base
  std::optional<CurrentMeasure> measure;            // default: the base's, else space-vector
  std::string force_column = "force_n";             // of the loaded logs
  CalibrationOptions fit;
  bool stop_at_bad_line = true;  // false: skip bad lines (warned) and go on
  RequestNames names;            // how the front end calls these options, for its messages

  std::vector<std::string> validate() const;
};

struct CalibrateReport {
  CalibrateOptions options;
  std::map<std::string, CalibratedAxis> axes;  // what the calibration file holds
  std::vector<MonitorWarning> warnings;

  Calibration calibration() const;
};

/// Steps 1 (idle logs: Tnzm, X, the noise) and 2 (loaded logs: KBlf) per axis on top of the
/// given constants. Throws InvalidInput for invalid options, a bad log, a log whose recorded
/// measure is not the calibration's, a constant that is unknown, or a fit that fails.
CalibrateReport calibrate(const CalibrateOptions& options, const MonitorListener& listener = {});

// ---- estimate --------------------------------------------------------------------------

struct EstimateOptions {
  EstimatorOptions estimator;
  AlarmOptions alarms;              // with a band
  double tooth_frequency_hz = 0.0;  // also state the filter there (0: not)
  bool stop_at_bad_line = true;
  RequestNames names;  // how the front end calls these options, for its messages

  std::vector<std::string> validate() const;
};

/// The filter between the true force and the estimate of one axis (EstimateFilter), for the
/// axis' first step.
struct FilterReport {
  double bandwidth_hz = 0.0;
  double step_s = 0.0;  // 0: one sample only, no step
  double minus_3db_hz = 0.0, delay_s = 0.0;
  double gain_at_bandwidth = 0.0, lag_deg_at_bandwidth = 0.0;
  double tooth_frequency_hz = 0.0;  // 0: not asked for
  double gain_at_tooth_frequency = 0.0, lag_deg_at_tooth_frequency = 0.0;
};

/// One axis of an estimate, in the order the axes appeared.
struct EstimatedAxis {
  std::string axis;
  FilterReport filter;
  bool sigma_known = true;  // false: force_sigma_n left empty (the calibration's is unknown)
  bool banded = false;      // a band watched it
  std::size_t sign_doubt_samples = 0, sign_doubt_first_line = 0;
  double sign_doubt_first_time_s = 0.0;
};

struct EstimateReport {
  EstimateOptions options;
  std::string source, calibration, band;  // the log, the calibration and the band file
  std::size_t samples = 0, bad_lines = 0;
  bool signed_current = false;  // the log gave rotor_angle_rad: the Park transform's torque current
  std::vector<EstimatedAxis> axes;
  std::vector<std::pair<std::string, AlarmEvent>> alarms;  // (axis, event), as they came
  std::vector<MonitorWarning> warnings;
};

/// One estimated sample, as it is estimated.
struct EstimatedRow {
  const CurrentRow& row;
  const std::string& axis;
  const ForceEstimate& estimate;
  const AlarmSample* alarm;  // with a band for the axis
};

/// The estimate of one current log, fed as it arrives:
///     EstimateJob job(read_calibration("calib.json"), "calib.json", options);
///     for (auto chunk = in.read(); !chunk.empty(); chunk = in.read()) job.feed(chunk);
///     const EstimateReport report = job.finish();
/// The rows go to `csv` (the estimate's CSV: header, then kEstimateHeader's columns and with a
/// band level_n,upper_n,lower_n,alarm) once per chunk, and to `row` one by one.
class EstimateJob {
 public:
  struct Sinks {
    std::function<void(std::string_view)> csv;
    std::function<void(const EstimatedRow&)> row;
  };
  /// `calibration_name` and `source` name the calibration and the log in messages. Throws
  /// InvalidInput for invalid options (naming "options").
  EstimateJob(Calibration calibration, std::string calibration_name, const EstimateOptions& options,
              std::optional<BandFile> band = std::nullopt, std::string band_name = {},
              std::string source = "standard input", Sinks sinks = {},
              MonitorListener listener = {});
  ~EstimateJob();
  EstimateJob(const EstimateJob&) = delete;
  EstimateJob& operator=(const EstimateJob&) = delete;

  /// Parses and estimates the complete lines of `chunk` (joined to the unfinished line of the
  /// previous one), hands their rows to the sinks, then deals with its bad lines (a bad line
  /// throws InvalidInput when stopping at bad lines, after the rows before it are out).
  void feed(std::string_view chunk);
  /// The end of the input: the last line, the summary. Throws if no line was good.
  EstimateReport finish();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// The estimate of the log at `path` ("-": standard input) in one call.
EstimateReport estimate(const std::string& path, const std::string& calibration_path,
                        const EstimateOptions& options, const std::string& band_path = {},
                        EstimateJob::Sinks sinks = {}, const MonitorListener& listener = {});

// ---- teach -----------------------------------------------------------------------------

struct TeachOptions {
  std::vector<std::string> references;  // reference runs (current logs), one cycle each
  LogTexts texts;           // logs in memory, by the name references gives them (others are files)
  std::string calibration;  // a calibration file or "zheng2012"
  // The calibration itself (e.g. from a calibrate job in memory): used instead of reading
  // `calibration`, which then only names it.
  std::optional<Calibration> calibration_given;
  EstimatorOptions estimator;
  // bin_s, k_sigma, the margins and cutting_fraction; smoothing_s, phase_tolerance_s and
  // average_s unless the cut below or the overrides set them.
  BandOptions band;
  // A milling cut's spindle speed and teeth (both or neither): the level is then averaged
  // over the tooth period (BandOptions::for_milling).
  std::optional<double> rpm;
  std::optional<int> teeth;
  std::optional<double> smoothing_s, phase_tolerance_s, average_s;  // given: win over the cut's
  bool stop_at_bad_line = true;

  /// The band options taught with: `band`, the cut's, then the overrides.
  BandOptions effective_band() const;
  std::vector<std::string> validate() const;
};

struct TeachReport {
  TeachOptions options;
  BandFile band;  // what the band file holds
  std::vector<MonitorWarning> warnings;
};

/// Estimates each reference run with the calibration and teaches the band of every axis.
TeachReport teach(const TeachOptions& options, const MonitorListener& listener = {});

}  // namespace cutdyn::app
