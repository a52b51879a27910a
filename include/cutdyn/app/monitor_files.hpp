// The monitor's files (docs/models/monitor.md §6): the calibration file that `monitor
// calibrate` writes and `estimate` and `teach` read, the band file that `teach` writes and
// `estimate --band` reads, and the current logs they all read, as they arrive. Each reader
// throws cutdyn::InvalidInput naming the file and the key or line at fault.
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "cutdyn/monitor/calibration.hpp"
#include "cutdyn/monitor/current_csv.hpp"
#include "cutdyn/monitor/force_band.hpp"

namespace cutdyn::app {

/// The "format" of a calibration file and of a band file.
inline constexpr const char* kCalibrationFormat = "cutdyn monitor calibration";
inline constexpr const char* kBandFormat = "cutdyn monitor band";

/// A calibration: the calibration of each axis, by axis name.
using Calibration = std::map<std::string, AxisCalibration>;

/// The name of the preset calibration: the source's coefficients for axes x, y and z
/// (zheng2012_calibration), usable wherever a calibration file is.
inline constexpr const char* kZheng2012Preset = "zheng2012";
Calibration zheng2012_preset();

/// The calibration file at `path`, or the preset when `path` is "zheng2012". Every axis is
/// validated (AxisCalibration::validate).
Calibration read_calibration(const std::string& path);
/// The same from a parsed document; `source` names it in errors.
Calibration calibration_from_json(const nlohmann::json& doc, const std::string& source);

/// One axis of a calibration and, where this run fitted them, the fits that made it: what a
/// calibration file holds per axis (the fits' reports are for people and are not read back).
struct CalibratedAxis {
  AxisCalibration calibration;
  std::optional<IdleFit> idle;  // step 1
  std::optional<LoadFit> load;  // step 2
};

/// The calibration file's document: format, version and per axis the calibration (measure,
/// J, KT, X, Tnzm, KBlf, their sigma, the noise, uncertainty_known) and the fits' reports.
nlohmann::json calibration_json(const std::map<std::string, CalibratedAxis>& axes);
nlohmann::json calibration_json(const Calibration& calibration);

/// A band file: the taught band of each axis and how it was taught.
struct BandFile {
  BandOptions options;                 // as taught (each band carries them too)
  std::optional<double> bandwidth_hz;  // the estimator's f_b at teach-in (absent in old files)
  std::string calibration;             // the calibration the reference runs were estimated with
  std::map<std::string, ForceBand> axes;
};

/// The band file at `path`. Every band is validated (ForceBand::validate).
BandFile read_band(const std::string& path);
BandFile band_from_json(const nlohmann::json& doc, const std::string& source);
/// The band file's document.
nlohmann::json band_json(const BandFile& band);

/// Current logs held in memory (e.g. made from arrays), by the name a job's options give
/// them in place of a file's path.
using LogTexts = std::map<std::string, std::string>;

/// A current log (a file, or standard input for "-" or ""), read as it arrives: read()
/// returns whatever is available, blocking until something is, so that a live stream is
/// answered line by line.
class LogInput {
 public:
  explicit LogInput(const std::string& path);
  /// A log in memory, named `name` in messages: read() returns all of `text`, then the end.
  LogInput(std::string name, std::string text);
  /// The log that `name` is: `texts`' entry of that name, else the file (or standard input).
  static std::unique_ptr<LogInput> open(const std::string& name, const LogTexts& texts);
  LogInput(const LogInput&) = delete;
  LogInput& operator=(const LogInput&) = delete;
  ~LogInput();
  /// The next chunk; empty at the end of the input.
  std::string_view read();
  /// The file's path, or "standard input".
  const std::string& name() const { return name_; }

 private:
  int fd_ = -1;
  bool own_ = false;
  std::string name_;
  std::unique_ptr<char[]> buffer_;
  bool in_memory_ = false;  // a log in memory: text_, all of it handed out by the first read()
  bool text_read_ = false;
  std::string text_;
};

/// "[AXIS=]VALUE" (e.g. "x=1.25", or "1.25" for every axis) as (axis or "", value); nullopt
/// unless VALUE is a finite number.
std::optional<std::pair<std::string, double>> parse_axis_value(const std::string& text);

}  // namespace cutdyn::app
