// `cutdyn monitor calibrate | estimate | teach`: cutting force from servo-motor currents
// (docs/models/monitor.md).
#include <fcntl.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <system_error>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cutdyn/core/error.hpp"
#include "cutdyn/io/output.hpp"
#include "cutdyn/monitor/calibration.hpp"
#include "cutdyn/monitor/current_csv.hpp"
#include "cutdyn/monitor/force_band.hpp"
#include "cutdyn/monitor/force_estimator.hpp"

namespace cutdyn::cli {
namespace {

using nlohmann::json;

constexpr const char* kCalibrationFormat = "cutdyn monitor calibration";
constexpr const char* kBandFormat = "cutdyn monitor band";
constexpr std::size_t kChunk = 1 << 16;
constexpr std::size_t kShownBadLines = 5;

// ---- input: a file or standard input, read as it arrives ---------------------------------

class Input {
 public:
  explicit Input(const std::string& path) {
    if (path == "-" || path.empty()) {
      fd_ = STDIN_FILENO;
      name_ = "standard input";
      return;
    }
    name_ = path;
    fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0)
      throw InvalidInput({"cannot read: " + std::generic_category().message(errno)}, path);
    own_ = true;
  }
  Input(const Input&) = delete;
  Input& operator=(const Input&) = delete;
  ~Input() {
    if (own_) ::close(fd_);
  }
  // Whatever is available (blocks until something is); empty at the end.
  std::string_view read() {
    for (;;) {
      const ssize_t n = ::read(fd_, buffer_.get(), kChunk);
      if (n >= 0) return {buffer_.get(), static_cast<std::size_t>(n)};
      if (errno != EINTR)
        throw std::runtime_error(name_ + ": read error: " + std::generic_category().message(errno));
    }
  }
  const std::string& name() const { return name_; }

 private:
  int fd_ = -1;
  bool own_ = false;
  std::string name_;
  std::unique_ptr<char[]> buffer_{new char[kChunk]};
};

// What --on-bad-line says.
bool stop_at_bad_line(const std::string& policy) {
  if (policy == "stop") return true;
  if (policy == "skip") return false;
  throw InvalidInput({"--on-bad-line = \"" + policy + "\": must be stop or skip"}, "command line");
}

// Handles the bad lines of one input: stop (throw the first) or skip (warn about a few, count).
class BadLines {
 public:
  BadLines(std::string source, bool stop, std::ostream& err)
      : source_(std::move(source)), stop_(stop), err_(err) {}
  void take(std::vector<CsvLineError>& errors) {
    for (const CsvLineError& e : errors) {
      if (stop_) throw InvalidInput({e.text()}, source_);
      if (count_ < kShownBadLines)
        err_ << "cutdyn: warning: " << source_ << ": " << e.text() << " (skipped)\n";
      ++count_;
    }
    errors.clear();
  }
  // The summary, and an error if nothing was left.
  void finish(std::size_t good) const {
    if (count_ > 0)
      err_ << "cutdyn: warning: " << source_ << ": skipped " << count_ << " bad line"
           << (count_ == 1 ? "" : "s") << "\n";
    if (good == 0)
      throw InvalidInput({"no valid data line (" + std::to_string(count_) + " skipped)"}, source_);
  }
  std::size_t count() const { return count_; }

 private:
  std::string source_;
  bool stop_;
  std::ostream& err_;
  std::size_t count_ = 0;
};

// The refusal of a log whose recorded current measure is not the calibration's (docs/models/
// monitor.md §1, §6).
InvalidInput measure_mismatch(const std::string& file, std::size_t line, const std::string& axis,
                              CurrentMeasure logged, CurrentMeasure calibration) {
  return InvalidInput({"line " + std::to_string(line) + ": axis " + axis +
                       ": the currents were logged with measure = " +
                       std::string(to_string(logged)) + ", the calibration's measure is " +
                       std::string(to_string(calibration)) +
                       ": KT holds for one measure only (they differ by √2); calibrate with "
                       "--measure " + std::string(to_string(logged)) +
                       " or log the calibration's measure"},
                      file);
}

// A whole log, per axis: the runs of calibration and teach-in; `measures` gets the measure
// its comments record per axis (and the line).
std::map<std::string, AxisRun> read_log(
    const std::string& path, const std::string& force_column, bool stop, std::ostream& err,
    std::map<std::string, std::pair<CurrentMeasure, std::size_t>>* measures = nullptr) {
  Input in(path);
  CurrentCsvParser parser(in.name(), force_column);
  BadLines bad(in.name(), stop, err);
  std::vector<CurrentRow> rows;
  std::vector<CsvLineError> errors;
  for (std::string_view chunk = in.read(); !chunk.empty(); chunk = in.read()) {
    parser.feed(chunk, rows, errors, stop);
    bad.take(errors);
  }
  parser.finish(rows, errors, stop);
  bad.take(errors);
  bad.finish(parser.good_rows());
  std::map<std::string, AxisRun> runs;
  const bool angle = parser.has_rotor_angle();
  for (const CurrentRow& r : rows)
    runs[parser.axes()[static_cast<std::size_t>(r.axis)]].push_back(
        {r.time_s, r.iu_a, r.iv_a, r.iw_a, r.speed_rad_s, r.extra, angle, r.rotor_angle_rad});
  if (measures)
    for (const auto& [axis, run] : runs)
      if (const auto m = parser.recorded_measure(axis)) (*measures)[axis] = *m;
  return runs;
}

// ---- calibration files --------------------------------------------------------------------

double number_at(const json& j, const std::string& key, const std::string& where,
                 const std::string& path, bool required, double fallback = 0.0) {
  const auto it = j.find(key);
  if (it == j.end() || it->is_null()) {
    if (required) throw InvalidInput({path + key + ": missing"}, where);
    return fallback;
  }
  if (!it->is_number())
    throw InvalidInput({path + key + " = " + it->dump() + ": must be a number"}, where);
  return it->get<double>();
}

void reject_unknown(const json& j, std::initializer_list<const char*> known,
                    const std::string& where, const std::string& path) {
  for (auto it = j.begin(); it != j.end(); ++it) {
    bool ok = false;
    for (const char* k : known) ok = ok || it.key() == k;
    if (!ok) throw InvalidInput({path + it.key() + ": unknown key"}, where);
  }
}

json read_json_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InvalidInput({"cannot read the file"}, path);
  try {
    return json::parse(in);
  } catch (const json::parse_error& e) {
    throw InvalidInput({std::string("not valid JSON: ") + e.what()}, path);
  }
}

std::map<std::string, AxisCalibration> zheng2012_preset() {
  std::map<std::string, AxisCalibration> axes;
  for (char a : {'x', 'y', 'z'}) axes[std::string(1, a)] = zheng2012_calibration(a);
  return axes;
}

std::map<std::string, AxisCalibration> read_calibration(const std::string& path) {
  if (path == "zheng2012") return zheng2012_preset();
  const json doc = read_json_file(path);
  if (!doc.is_object() || doc.value("format", "") != kCalibrationFormat)
    throw InvalidInput({std::string("format: must be \"") + kCalibrationFormat + "\""}, path);
  if (!doc.contains("axes") || !doc["axes"].is_object() || doc["axes"].empty())
    throw InvalidInput({"axes: missing or empty"}, path);
  std::map<std::string, AxisCalibration> axes;
  for (auto it = doc["axes"].begin(); it != doc["axes"].end(); ++it) {
    const json& a = it.value();
    const std::string at = "axes." + it.key() + ".";
    if (!a.is_object()) throw InvalidInput({at + ": must be an object"}, path);
    reject_unknown(a,
                   {"measure", "inertia_kg_m2", "torque_constant_nm_per_a", "viscous_nm_s_per_rad",
                    "friction_nm", "force_gain_m", "sigma", "current_noise_a", "speed_noise_rad_s",
                    "uncertainty_known", "idle_fit", "load_fit"},
                   path, at);
    AxisCalibration c;
    const std::string measure = a.value("measure", "");
    const auto m = parse_current_measure(measure);
    if (!m)
      throw InvalidInput({at + "measure = \"" + measure + "\": must be rms or space-vector"}, path);
    c.model.measure = *m;
    c.model.inertia_kg_m2 = number_at(a, "inertia_kg_m2", path, at, true);
    c.model.torque_constant_nm_per_a = number_at(a, "torque_constant_nm_per_a", path, at, true);
    c.model.viscous_nm_s_per_rad = number_at(a, "viscous_nm_s_per_rad", path, at, true);
    c.model.friction_nm = number_at(a, "friction_nm", path, at, true);
    c.model.force_gain_m = number_at(a, "force_gain_m", path, at, true);
    c.current_noise_a = number_at(a, "current_noise_a", path, at, false);
    c.speed_noise_rad_s = number_at(a, "speed_noise_rad_s", path, at, false);
    if (const auto k = a.find("uncertainty_known"); k != a.end()) {
      if (!k->is_boolean())
        throw InvalidInput({at + "uncertainty_known = " + k->dump() + ": must be true or false"},
                           path);
      c.uncertainty_known = k->get<bool>();
    }
    if (a.contains("sigma")) {
      const json& s = a["sigma"];
      const std::string sat = at + "sigma.";
      if (!s.is_object()) throw InvalidInput({sat + ": must be an object"}, path);
      reject_unknown(s,
                     {"inertia_kg_m2", "torque_constant_nm_per_a", "viscous_nm_s_per_rad",
                      "friction_nm", "friction_viscous_covariance", "force_gain_m"},
                     path, sat);
      c.sigma.inertia_kg_m2 = number_at(s, "inertia_kg_m2", path, sat, false);
      c.sigma.torque_constant_nm_per_a = number_at(s, "torque_constant_nm_per_a", path, sat, false);
      c.sigma.viscous_nm_s_per_rad = number_at(s, "viscous_nm_s_per_rad", path, sat, false);
      c.sigma.friction_nm = number_at(s, "friction_nm", path, sat, false);
      c.sigma.friction_viscous_covariance =
          number_at(s, "friction_viscous_covariance", path, sat, false);
      c.sigma.force_gain_m = number_at(s, "force_gain_m", path, sat, false);
    }
    rethrow_as(path, "axes." + it.key(), [&] {
      if (const auto p = c.validate(); !p.empty()) throw InvalidInput(p);
    });
    axes[it.key()] = c;
  }
  return axes;
}

json fit_json(const FitReport& r) {
  return {{"status", to_string(r.status)},
          {"windows", r.windows},
          {"windows_rejected", r.windows_rejected},
          {"distinct_speeds", r.distinct_speeds},
          {"r_squared", r.r_squared},
          {"residual_rms_nm", r.residual_rms_nm},
          {"residual_sigma_nm", r.residual_sigma_nm}};
}

json axis_json(const AxisCalibration& c) {
  const AxisModel& m = c.model;
  const AxisUncertainty& s = c.sigma;
  return {{"measure", std::string(to_string(m.measure))},
          {"inertia_kg_m2", m.inertia_kg_m2},
          {"torque_constant_nm_per_a", m.torque_constant_nm_per_a},
          {"viscous_nm_s_per_rad", m.viscous_nm_s_per_rad},
          {"friction_nm", m.friction_nm},
          {"force_gain_m", m.force_gain_m},
          {"sigma",
           {{"inertia_kg_m2", s.inertia_kg_m2},
            {"torque_constant_nm_per_a", s.torque_constant_nm_per_a},
            {"viscous_nm_s_per_rad", s.viscous_nm_s_per_rad},
            {"friction_nm", s.friction_nm},
            {"friction_viscous_covariance", s.friction_viscous_covariance},
            {"force_gain_m", s.force_gain_m}}},
          {"current_noise_a", c.current_noise_a},
          {"speed_noise_rad_s", c.speed_noise_rad_s},
          {"uncertainty_known", c.uncertainty_known}};
}

// "[AXIS=]VALUE" → (axis or "", value).
std::pair<std::string, double> axis_value(const std::string& text, const char* flag) {
  const auto eq = text.find('=');
  const std::string axis = eq == std::string::npos ? "" : text.substr(0, eq);
  const std::string number = eq == std::string::npos ? text : text.substr(eq + 1);
  try {
    std::size_t used = 0;
    const double v = std::stod(number, &used);
    if (used == number.size() && std::isfinite(v)) return {axis, v};
  } catch (const std::exception&) {
  }
  throw InvalidInput(
      {std::string(flag) + " = \"" + text + "\": must be VALUE or AXIS=VALUE with a number"},
      "command line");
}

void check_out_flag(const std::string& out, const char* flag) {
  Validator v;
  if (out.empty()) v.add(std::string(flag) + ": missing (where to write)");
  check_output_folder(v, flag, out);
  v.throw_if_any("command line");
}

std::string pm(double value, double sigma) { return human(value, 6) + " ± " + human(sigma, 2); }

}  // namespace

int run_monitor_calibrate(const MonitorCalibrateArgs& args, std::ostream& out, std::ostream& err) {
  const bool stop = stop_at_bad_line(args.on_bad_line);
  check_out_flag(args.out, "--out");
  CalibrationOptions options;
  options.window_s = args.window_s;
  options.steady_tolerance = args.steady_tolerance;
  options.standstill_rad_s = args.standstill_rad_s;
  if (const auto p = options.validate(); !p.empty()) throw InvalidInput(p, "command line");
  std::optional<CurrentMeasure> measure;
  if (!args.measure.empty()) {
    measure = parse_current_measure(args.measure);
    if (!measure)
      throw InvalidInput({"--measure = \"" + args.measure + "\": must be rms or space-vector"},
                         "command line");
  }

  std::map<std::string, AxisCalibration> base;
  if (!args.base.empty()) base = read_calibration(args.base);
  std::map<std::string, std::vector<AxisRun>> idle, loaded;
  std::set<std::string> axes;
  // Per file, the measures its comments record per axis.
  std::vector<std::pair<std::string, std::map<std::string, std::pair<CurrentMeasure, std::size_t>>>>
      recorded;
  for (const std::string& f : args.idle) {
    recorded.emplace_back(f, std::map<std::string, std::pair<CurrentMeasure, std::size_t>>{});
    for (auto& [axis, run] : read_log(f, "", stop, err, &recorded.back().second)) {
      idle[axis].push_back(std::move(run));
      axes.insert(axis);
    }
  }
  for (const std::string& f : args.loaded) {
    recorded.emplace_back(f, std::map<std::string, std::pair<CurrentMeasure, std::size_t>>{});
    for (auto& [axis, run] : read_log(f, args.force_column, stop, err, &recorded.back().second)) {
      loaded[axis].push_back(std::move(run));
      axes.insert(axis);
    }
  }
  if (axes.empty())
    for (const auto& [axis, c] : base) axes.insert(axis);
  if (axes.empty())
    throw InvalidInput({"nothing to calibrate: give --idle and/or --loaded logs, or --base"},
                       "command line");

  // Given constants: the base, then the flags.
  std::map<std::string, AxisCalibration> result;
  std::map<std::string, bool> kt_given, j_given;
  for (const std::string& axis : axes) {
    AxisCalibration c;
    if (const auto it = base.find(axis); it != base.end()) {
      c = it->second;
      kt_given[axis] = j_given[axis] = true;
    }
    if (measure) c.model.measure = *measure;
    result[axis] = c;
  }
  // A log whose recorded measure is not the calibration's is refused (its KT would be off √2).
  for (const auto& [file, m] : recorded)
    for (const auto& [axis, logged] : m)
      if (logged.first != result[axis].model.measure)
        throw measure_mismatch(file, logged.second, axis, logged.first, result[axis].model.measure);
  const auto apply = [&](const std::vector<std::string>& values, const char* flag, bool kt) {
    for (const std::string& text : values) {
      const auto [axis, v] = axis_value(text, flag);
      if (!axis.empty() && !axes.count(axis))
        throw InvalidInput({std::string(flag) + " = \"" + text + "\": no log has the axis " + axis},
                           "command line");
      for (auto& [name, c] : result) {
        if (!axis.empty() && name != axis) continue;
        (kt ? c.model.torque_constant_nm_per_a : c.model.inertia_kg_m2) = v;
        (kt ? c.sigma.torque_constant_nm_per_a : c.sigma.inertia_kg_m2) = 0.0;
        (kt ? kt_given : j_given)[name] = true;
      }
    }
  };
  apply(args.kt, "--kt", true);
  apply(args.inertia, "--inertia", false);
  Validator v;
  for (const std::string& axis : axes) {
    if (!kt_given[axis])
      v.add("axis " + axis + ": the torque constant is unknown: give --kt " + axis +
            "=VALUE (N·m/A) or --base");
    if (!j_given[axis])
      v.add("axis " + axis + ": the inertia is unknown: give --inertia " + axis +
            "=VALUE (kg·m²) or --base");
  }
  v.throw_if_any("command line");

  json doc{{"format", kCalibrationFormat}, {"version", 1}};
  json axes_json = json::object();
  out << "cutdyn monitor calibrate: " << axes.size() << " ax" << (axes.size() == 1 ? "is" : "es")
      << ", " << args.idle.size() << " idle and " << args.loaded.size() << " loaded log"
      << (args.loaded.size() == 1 ? "" : "s") << "\n";
  for (const std::string& axis : axes) {
    AxisCalibration& c = result[axis];
    json extra = json::object();
    out << "  axis " << axis << " (KT = " << human(c.model.torque_constant_nm_per_a) << " N·m/A "
        << to_string(c.model.measure) << ", J = " << human(c.model.inertia_kg_m2) << " kg·m²)\n";
    if (idle.count(axis)) {
      const IdleFit f = fit_idle(c.model, idle[axis], options);
      if (f.report.status != CalibrationStatus::kSuccess)
        throw InvalidInput({"axis " + axis + ": " + f.report.message}, "calibration");
      for (const std::string& w : f.report.warnings)
        err << "cutdyn: warning: calibration: axis " << axis << ": " << w << "\n";
      c.model.friction_nm = f.friction_nm;
      c.model.viscous_nm_s_per_rad = f.viscous_nm_s_per_rad;
      c.sigma.friction_nm = f.friction_sigma_nm;
      c.sigma.viscous_nm_s_per_rad = f.viscous_sigma;
      c.sigma.friction_viscous_covariance = f.covariance;
      c.current_noise_a = f.current_noise_a;
      c.speed_noise_rad_s = f.speed_noise_rad_s;
      extra["idle_fit"] = fit_json(f.report);
      if (!f.report.warnings.empty()) extra["idle_fit"]["warnings"] = f.report.warnings;
      out << "    step 1: Tnzm = " << pm(f.friction_nm, f.friction_sigma_nm)
          << " N·m, X = " << pm(f.viscous_nm_s_per_rad, f.viscous_sigma) << " N·m·s/rad\n"
          << "            " << f.report.windows << " steady windows at " << f.report.distinct_speeds
          << " speeds (" << f.report.windows_rejected
          << " rejected), R² = " << human(f.report.r_squared, 6)
          << ", residual RMS = " << human(f.report.residual_rms_nm, 3) << " N·m\n"
          << "            noise: current " << human(f.current_noise_a, 3) << " A, speed "
          << human(f.speed_noise_rad_s, 3) << " rad/s\n";
    } else if (!base.count(axis)) {
      v.add("axis " + axis + ": no idle log and no --base: Tnzm and X are unknown");
    }
    if (loaded.count(axis)) {
      const LoadFit f = fit_load(c, loaded[axis], options);
      if (f.report.status != CalibrationStatus::kSuccess)
        throw InvalidInput({"axis " + axis + ": " + f.report.message}, "calibration");
      c.model.force_gain_m = f.force_gain_m;
      c.sigma.force_gain_m = f.force_gain_sigma_m;
      extra["load_fit"] = fit_json(f.report);
      extra["load_fit"]["force_gain_sigma_from_idle_m"] = f.force_gain_sigma_from_idle_m;
      out << "    step 2: KBlf = " << pm(f.force_gain_m, f.force_gain_sigma_m) << " m, "
          << f.report.windows << " windows, R² = " << human(f.report.r_squared, 6)
          << ", residual RMS = " << human(f.report.residual_rms_nm, 3) << " N·m\n";
    } else if (!base.count(axis)) {
      v.add("axis " + axis + ": no loaded log and no --base: KBlf is unknown");
    }
    // Tnzm, X and KBlf fitted here carry their uncertainties; one kept from a base whose
    // uncertainty is unknown (the literature coefficients) keeps it unknown.
    if (idle.count(axis) && loaded.count(axis)) c.uncertainty_known = true;
    if (!c.uncertainty_known)
      out << "    uncertainty unknown: Tnzm, X or KBlf are the base's, which has no known "
             "uncertainty; force_sigma_n will be left empty (calibrate with --idle and "
             "--loaded)\n";
    if (v.ok())
      rethrow_as("calibration", "axis " + axis, [&] {
        if (const auto p = c.validate(); !p.empty()) throw InvalidInput(p);
      });
    json a = axis_json(c);
    a.update(extra);
    axes_json[axis] = a;
  }
  v.throw_if_any("calibration");
  doc["axes"] = axes_json;
  io::OutputTransaction outputs;
  io::write_json(outputs.open(args.out), doc);
  outputs.commit();
  out << "  wrote " << args.out << "\n";
  return 0;
}

namespace {

EstimatorOptions estimator_options(const MonitorEstimatorArgs& a) {
  EstimatorOptions o;
  o.bandwidth_hz = a.bandwidth_hz;
  o.standstill_rad_s = a.standstill_rad_s;
  if (const auto p = o.validate(); !p.empty()) throw InvalidInput(p, "command line");
  return o;
}

// The estimators of the axes a stream names, made as the axes appear.
class Estimators {
 public:
  Estimators(std::map<std::string, AxisCalibration> cal, const EstimatorOptions& o,
             std::string calib_name)
      : cal_(std::move(cal)), options_(o), calib_name_(std::move(calib_name)) {}
  // The estimator of the parser's axis `index` named `name`, or null if not calibrated.
  AxisForceEstimator* get(int index, const std::string& name) {
    const auto i = static_cast<std::size_t>(index);
    while (by_index_.size() <= i) by_index_.push_back(nullptr);
    if (!by_index_[i]) {
      const auto it = cal_.find(name);
      if (it == cal_.end()) return nullptr;
      owned_.push_back(std::make_unique<AxisForceEstimator>(it->second, options_));
      by_index_[i] = owned_.back().get();
      names_.push_back(name);
    }
    return by_index_[i];
  }
  std::string missing(const std::string& name) const {
    std::string have;
    for (const auto& [axis, c] : cal_) have += (have.empty() ? "" : ", ") + axis;
    return "axis \"" + name + "\" is not in the calibration " + calib_name_ + " (it has " + have +
           ")";
  }
  // True the first time it is asked for the parser's axis `index` (its first good row).
  bool first_row(int index) {
    const auto i = static_cast<std::size_t>(index);
    if (seen_.size() <= i) seen_.resize(i + 1, false);
    if (seen_[i]) return false;
    seen_[i] = true;
    return true;
  }
  // Samples of an axis whose torque sign is in doubt (no rotor angle, §4.5 of
  // docs/models/monitor.md): how many, and the first.
  struct SignDoubt {
    std::size_t samples = 0, first_line = 0;
    double first_time_s = 0.0;
  };
  std::map<std::string, SignDoubt>& sign_doubts() { return doubts_; }
  const std::map<std::string, SignDoubt>& sign_doubts() const { return doubts_; }
  // Whether the logs gave the rotor angle (the signed torque current): set by the stream.
  bool signed_current = false;

  // The estimators made so far, with their axis names, in order of appearance.
  std::vector<std::pair<std::string, const AxisForceEstimator*>> made() const {
    std::vector<std::pair<std::string, const AxisForceEstimator*>> all;
    for (std::size_t i = 0; i < owned_.size(); ++i) all.emplace_back(names_[i], owned_[i].get());
    return all;
  }

 private:
  std::map<std::string, AxisCalibration> cal_;
  EstimatorOptions options_;
  std::string calib_name_;
  std::vector<AxisForceEstimator*> by_index_;
  std::vector<std::unique_ptr<AxisForceEstimator>> owned_;
  std::vector<std::string> names_;
  std::map<std::string, SignDoubt> doubts_;
  std::vector<bool> seen_;
};

// What the estimate is (docs/models/monitor.md §4.1, §4.3): the filter of each axis, for its
// first step, as text lines and as JSON.
constexpr const char* kSignDoubt =
    "the motor torque may be against the motion here (a load that aids the motion, or "
    "braking), and the log has no rotor_angle_rad column: the estimate assumes the torque has "
    "the sign of the motion and may have the wrong sign; log the electrical rotor angle for the "
    "signed torque current (docs/models/monitor.md §4.5)";
constexpr const char* kSigmaCovers =
    "force_sigma_n is the standard uncertainty of force_n as an estimate of the filtered force "
    "(current and speed noise, the calibration's parameter uncertainties); the filter itself is "
    "stated, not an error: force_n is the true force through it";

json filter_json(const AxisForceEstimator& e, double tooth_hz) {
  const double dt = e.first_step_s();
  json j{{"transfer_function", EstimateFilter::formula()},
         {"bandwidth_hz", e.options().bandwidth_hz},
         {"step_s", dt}};
  if (dt > 0.0) {
    const EstimateFilter h{e.options().bandwidth_hz, dt};
    j["minus_3db_hz"] = h.minus_3db_hz();
    j["delay_s"] = h.delay_s();
    if (tooth_hz > 0.0) {
      j["tooth_frequency_hz"] = tooth_hz;
      j["gain_at_tooth_frequency"] = h.gain(tooth_hz);
      j["lag_deg_at_tooth_frequency"] = h.lag_deg(tooth_hz);
    }
  }
  return j;
}

void describe_filter(std::ostream& out, const std::string& axis, const AxisForceEstimator& e,
                     double tooth_hz) {
  const double dt = e.first_step_s();
  const double fb = e.options().bandwidth_hz;
  out << "  axis " << axis << ": force_n = the force through H(f) = sinc(f·Δt)·e^(−jπfΔt)·((1 − r)/"
         "(1 − r·e^(−j2πfΔt)))², r = exp(−2π·f_b·Δt), f_b = "
      << human(fb) << " Hz";
  if (dt <= 0.0) {
    out << " (one sample: no step)\n";
    return;
  }
  const EstimateFilter h{fb, dt};
  out << ", Δt = " << human(dt) << " s: −3 dB at " << human(h.minus_3db_hz()) << " Hz, gain "
      << human(h.gain(fb), 3) << " and lag " << human(h.lag_deg(fb), 3) << "° at f_b, delay "
      << human(h.delay_s(), 3) << " s at low frequency";
  if (tooth_hz > 0.0)
    out << "; at the tooth frequency " << human(tooth_hz) << " Hz: gain " << human(h.gain(tooth_hz), 3)
        << ", lag " << human(h.lag_deg(tooth_hz), 3) << "°";
  out << "\n";
}

// Streams `input` through the estimators: `each(row, axis name, estimate)` per good row,
// `flush()` after each chunk read (so a live stream is answered line by line).
template <typename Each, typename Flush>
std::size_t estimate_stream(const std::string& input, Estimators& estimators, bool stop,
                            std::ostream& err, Each each, Flush flush) {
  Input in(input);
  CurrentCsvParser parser(in.name());
  BadLines bad(in.name(), stop, err);
  std::vector<CurrentRow> rows;
  std::vector<CsvLineError> errors;
  std::size_t good = 0;
  const auto process = [&] {
    for (const CurrentRow& r : rows) {
      const std::string& name = parser.axes()[static_cast<std::size_t>(r.axis)];
      AxisForceEstimator* e = estimators.get(r.axis, name);
      if (!e) {
        errors.push_back({r.line, estimators.missing(name)});
        bad.take(errors);
        continue;
      }
      if (estimators.first_row(r.axis))
        if (const auto m = parser.recorded_measure(name);
            m && m->first != e->calibration().model.measure)
          throw measure_mismatch(in.name(), m->second, name, m->first,
                                 e->calibration().model.measure);
      ForceEstimate estimate;
      try {
        estimate = e->update(r.time_s, r.iu_a, r.iv_a, r.iw_a, r.speed_rad_s,
                             parser.has_rotor_angle() ? std::optional<double>(r.rotor_angle_rad)
                                                      : std::nullopt);
      } catch (const InvalidInput& x) {
        // The bandwidth against the log's sampling (the only check of update): the flag.
        std::vector<std::string> problems;
        for (const std::string& p : x.problems())
          problems.push_back("--bandwidth-hz: " + p + ", axis " + name + " at line " +
                             std::to_string(r.line));
        throw InvalidInput(problems, in.name());
      }
      if (estimate.torque_sign_doubtful) {
        auto& d = estimators.sign_doubts()[name];
        if (d.samples++ == 0) {
          d.first_line = r.line;
          d.first_time_s = r.time_s;
          err << "cutdyn: warning: " << in.name() << ": line " << r.line << ", axis " << name
              << " at " << human(r.time_s, 7) << " s: " << kSignDoubt << "\n";
        }
      }
      each(r, name, estimate);
      ++good;
    }
    rows.clear();
    flush();
    bad.take(errors);  // after the good lines before it are out
  };
  for (std::string_view chunk = in.read(); !chunk.empty(); chunk = in.read()) {
    parser.feed(chunk, rows, errors, stop);
    process();
  }
  parser.finish(rows, errors, stop);
  process();
  bad.finish(good);
  estimators.signed_current = parser.has_rotor_angle();
  for (const auto& [axis, d] : estimators.sign_doubts())
    if (d.samples > 1)
      err << "cutdyn: warning: " << in.name() << ": axis " << axis << ": the torque sign is in "
          << "doubt at " << d.samples << " samples\n";
  return good;
}

ForceBand band_of_json(const json& a, const json& doc, const std::string& path,
                       const std::string& at) {
  ForceBand b;
  b.options.bin_s = number_at(doc, "bin_s", path, "", true);
  b.options.smoothing_s = number_at(doc, "smoothing_s", path, "", true);
  b.options.average_s = number_at(doc, "average_s", path, "", false, 0.0);
  b.cycle_s = number_at(a, "cycle_s", path, at, true);
  const auto vec = [&](const char* key, std::vector<double>& v) {
    if (!a.contains(key) || !a[key].is_array())
      throw InvalidInput({at + key + ": missing (an array of numbers)"}, path);
    for (const json& x : a[key]) {
      if (!x.is_number()) throw InvalidInput({at + key + ": must hold numbers only"}, path);
      v.push_back(x.get<double>());
    }
  };
  vec("mean_n", b.mean_n);
  vec("sigma_n", b.sigma_n);
  vec("upper_n", b.upper_n);
  vec("lower_n", b.lower_n);
  std::vector<double> cutting;
  vec("cutting", cutting);
  for (double x : cutting) b.cutting.push_back(x != 0.0 ? 1 : 0);
  rethrow_as(path, at.substr(0, at.size() - 1), [&] {
    if (const auto p = b.validate(); !p.empty()) throw InvalidInput(p);
  });
  return b;
}

}  // namespace

int run_monitor_estimate(const MonitorEstimateArgs& args, std::ostream& out, std::ostream& err) {
  const bool stop = stop_at_bad_line(args.estimator.on_bad_line);
  const EstimatorOptions options = estimator_options(args.estimator);
  AlarmOptions alarm_options;
  alarm_options.persist_s = args.persist_s;
  alarm_options.wear_fraction = args.wear_fraction;
  alarm_options.wear_time_constant_s = args.wear_time_constant_s;
  if (const auto p = alarm_options.validate(); !p.empty()) throw InvalidInput(p, "command line");
  {
    Validator v;
    check_output_folder(v, "--out", args.out);
    check_output_folder(v, "--alarms", args.alarms);
    check_output_folder(v, "--json", args.json);
    if (!args.alarms.empty() && args.band.empty()) v.add("--alarms needs --band");
    if (!(args.tooth_frequency_hz >= 0.0) || !std::isfinite(args.tooth_frequency_hz))
      v.add("--tooth-frequency-hz = " + human(args.tooth_frequency_hz) +
            ": must be a finite number >= 0 (0: not reported)");
    v.throw_if_any("command line");
  }
  Estimators estimators(read_calibration(args.estimator.calib), options, args.estimator.calib);

  std::map<std::string, AlarmMonitor> monitors;
  if (!args.band.empty()) {
    const json doc = read_json_file(args.band);
    if (!doc.is_object() || doc.value("format", "") != kBandFormat)
      throw InvalidInput({std::string("format: must be \"") + kBandFormat + "\""}, args.band);
    if (!doc.contains("axes") || !doc["axes"].is_object())
      throw InvalidInput({"axes: missing"}, args.band);
    for (auto it = doc["axes"].begin(); it != doc["axes"].end(); ++it)
      monitors.emplace(
          it.key(), AlarmMonitor(band_of_json(it.value(), doc, args.band, "axes." + it.key() + "."),
                                 alarm_options));
    const double taught =
        number_at(doc, "bandwidth_hz", args.band, "", false, options.bandwidth_hz);
    if (taught != options.bandwidth_hz)
      err << "cutdyn: warning: " << args.band << ": taught with --bandwidth-hz " << human(taught)
          << ", estimating with " << human(options.bandwidth_hz) << "\n";
  }
  const bool with_band = !args.band.empty();

  io::OutputTransaction outputs;
  std::ostream& sink = args.out.empty() ? out : outputs.open(args.out);
  std::string buffer = kEstimateHeader;
  if (with_band) buffer += ",level_n,upper_n,lower_n,alarm";
  buffer += '\n';
  std::vector<std::pair<std::string, AlarmEvent>> events;
  std::map<std::string, std::size_t> seen_events;
  std::set<std::string> unbanded, unknown_sigma;
  const auto each = [&](const CurrentRow& r, const std::string& axis, const ForceEstimate& e) {
    // The calibration's uncertainty is unknown (the literature coefficients, §4.3 of
    // docs/models/monitor.md): said once per axis, at its first estimate.
    if (!e.sigma_known && unknown_sigma.insert(axis).second)
      err << "cutdyn: warning: " << args.estimator.calib
          << ": uncertainty unknown for the literature coefficients (axis " << axis
          << "): force_sigma_n is left empty; calibrate the machine (cutdyn monitor calibrate "
             "--idle ... --loaded ...) for an uncertainty\n";
    append_estimate_row(buffer, r.time_s, axis, e);
    if (with_band) {
      const auto it = monitors.find(axis);
      if (it == monitors.end()) {
        if (unbanded.insert(axis).second)
          err << "cutdyn: warning: " << args.band << ": no band for axis " << axis
              << ": no alarms on it\n";
        buffer += ",,,,";
      } else {
        const AlarmSample s = it->second.update(r.time_s, e.force_n);
        buffer += ',';
        append_number(buffer, s.level_n, 7);
        buffer += ',';
        append_number(buffer, s.upper_n, 7);
        buffer += ',';
        append_number(buffer, s.lower_n, 7);
        buffer += ',';
        buffer += alarm_text(s.active);
        const auto& all = it->second.events();
        for (std::size_t& k = seen_events[axis]; k < all.size(); ++k) {
          const AlarmEvent& a = all[k];
          err << "cutdyn: alarm: " << to_string(a.kind) << " on axis " << axis << " at "
              << human(a.time_s, 7) << " s ("
              << (a.kind == AlarmKind::kWear
                      ? "smoothed rise " + human(100.0 * a.level_n, 3) + " % > " +
                            human(100.0 * a.limit_n, 3) + " %"
                      : "level " + human(a.level_n, 5) +
                            (a.kind == AlarmKind::kOverload ? " N > upper limit "
                                                            : " N < lower limit ") +
                            human(a.limit_n, 5) + " N")
              << ", confirmed at " << human(a.detected_s, 7) << " s)\n";
          events.emplace_back(axis, a);
        }
      }
    }
    buffer += '\n';
  };
  const auto flush = [&] {
    sink.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    if (args.out.empty()) sink.flush();
    buffer.clear();
  };
  const std::size_t samples = estimate_stream(args.input, estimators, stop, err, each, flush);
  json summary{{"format", "cutdyn monitor estimate"}, {"version", 1}, {"samples", samples},
               {"force_sigma_n_covers", kSigmaCovers}};
  summary["axes"] = json::object();
  for (const auto& [axis, e] : estimators.made()) {
    json a{{"filter", filter_json(*e, args.tooth_frequency_hz)},
           {"torque_current", estimators.signed_current
                                  ? "signed: Park transform with rotor_angle_rad"
                                  : "magnitude with the sign of the motion (no rotor_angle_rad)"},
           {"warnings", json::array()}};
    if (const auto d = estimators.sign_doubts().find(axis); d != estimators.sign_doubts().end())
      a["warnings"].push_back({{"kind", "torque-sign"},
                               {"message", kSignDoubt},
                               {"samples", d->second.samples},
                               {"first_line", d->second.first_line},
                               {"first_time_s", d->second.first_time_s}});
    summary["axes"][axis] = a;
  }
  if (!args.json.empty()) io::write_json(outputs.open(args.json), summary);
  if (!args.alarms.empty()) {
    io::CsvWriter csv(outputs.open(args.alarms),
                      {"time_s", "axis", "alarm", "detected_s", "level", "limit"});
    for (const auto& [axis, a] : events)
      csv.row({a.time_s, axis, std::string(to_string(a.kind)), a.detected_s, a.level_n, a.limit_n});
  }
  outputs.commit();
  std::ostream& report = args.out.empty() ? err : out;
  report << (args.out.empty() ? "cutdyn: " : "") << "monitor estimate: " << samples << " samples";
  if (with_band) report << ", " << events.size() << " alarm" << (events.size() == 1 ? "" : "s");
  report << "\n";
  for (const auto& [axis, e] : estimators.made())
    describe_filter(report, axis, *e, args.tooth_frequency_hz);
  report << "  " << kSigmaCovers << "\n";
  for (const std::string* f : {&args.out, &args.alarms, &args.json})
    if (!f->empty()) out << "  wrote " << *f << "\n";
  return 0;
}

int run_monitor_teach(const MonitorTeachArgs& args, std::ostream& out, std::ostream& err) {
  const bool stop = stop_at_bad_line(args.estimator.on_bad_line);
  check_out_flag(args.out, "--out");
  const EstimatorOptions options = estimator_options(args.estimator);
  if (args.rpm.has_value() != args.teeth.has_value())
    throw InvalidInput({args.rpm ? "--rpm needs --teeth (the tooth period is 60/(teeth·rpm))"
                                 : "--teeth needs --rpm (the tooth period is 60/(teeth·rpm))"},
                       "command line");
  BandOptions band_options =
      args.rpm ? BandOptions::for_milling(*args.rpm, *args.teeth) : BandOptions{};
  band_options.bin_s = args.bin_s;
  if (args.smoothing_s) band_options.smoothing_s = *args.smoothing_s;
  band_options.k_sigma = args.k_sigma;
  band_options.relative_margin = args.relative_margin;
  band_options.absolute_margin_n = args.absolute_margin_n;
  band_options.peak_margin = args.peak_margin;
  band_options.cutting_fraction = args.cutting_fraction;
  if (args.phase_tolerance_s) band_options.phase_tolerance_s = *args.phase_tolerance_s;
  if (args.average_s) band_options.average_s = *args.average_s;
  if (const auto p = band_options.validate(); !p.empty()) throw InvalidInput(p, "command line");
  if (args.inputs.empty())
    throw InvalidInput({"REFERENCE: give at least one reference run"}, "command line");
  const auto calibration = read_calibration(args.estimator.calib);

  std::map<std::string, std::vector<ForceRun>> runs;
  for (const std::string& input : args.inputs) {
    Estimators estimators(calibration, options, args.estimator.calib);
    std::map<std::string, ForceRun> run;
    estimate_stream(
        input, estimators, stop, err,
        [&](const CurrentRow& r, const std::string& axis, const ForceEstimate& e) {
          run[axis].time_s.push_back(r.time_s);
          run[axis].force_n.push_back(e.force_n);
        },
        [] {});
    for (auto& [axis, r] : run) runs[axis].push_back(std::move(r));
  }
  json doc{{"format", kBandFormat},
           {"version", 1},
           {"bin_s", band_options.bin_s},
           {"smoothing_s", band_options.smoothing_s},
           {"k_sigma", band_options.k_sigma},
           {"relative_margin", band_options.relative_margin},
           {"absolute_margin_n", band_options.absolute_margin_n},
           {"peak_margin", band_options.peak_margin},
           {"cutting_fraction", band_options.cutting_fraction},
           {"phase_tolerance_s", band_options.phase_tolerance_s},
           {"average_s", band_options.average_s},
           {"bandwidth_hz", options.bandwidth_hz},
           {"calibration", args.estimator.calib}};
  json axes = json::object();
  out << "cutdyn monitor teach: " << args.inputs.size() << " reference run"
      << (args.inputs.size() == 1 ? "" : "s") << "\n";
  for (const auto& [axis, r] : runs) {
    ForceBand band;
    rethrow_as("teach-in", "axis " + axis, [&] { band = teach_band(r, band_options); });
    const auto peak = std::max_element(band.mean_n.begin(), band.mean_n.end());
    std::size_t cutting = 0;
    for (auto c : band.cutting) cutting += c;
    out << "  axis " << axis << ": " << r.size() << " run" << (r.size() == 1 ? "" : "s")
        << ", cycle " << human(band.cycle_s) << " s in " << band.mean_n.size()
        << " bins, peak mean level " << human(*peak, 5) << " N, " << cutting << " cutting bins\n";
    json a{{"cycle_s", band.cycle_s}, {"runs", band.runs},       {"mean_n", band.mean_n},
           {"sigma_n", band.sigma_n}, {"upper_n", band.upper_n}, {"lower_n", band.lower_n}};
    a["cutting"] = json::array();
    for (auto c : band.cutting) a["cutting"].push_back(static_cast<int>(c));
    axes[axis] = a;
  }
  doc["axes"] = axes;
  io::OutputTransaction outputs;
  io::write_json(outputs.open(args.out), doc);
  outputs.commit();
  out << "  wrote " << args.out << "\n";
  if (!args.rpm && !args.average_s)
    err << "cutdyn: warning: monitor teach: no --rpm and --teeth: the monitored level keeps the "
           "tooth pattern (no averaging over the tooth period), so the band is wide and a broken "
           "tooth may take several tooth periods to be caught; give the cut's --rpm and --teeth\n";
  return 0;
}

std::function<int(std::ostream&, std::ostream&)> add_monitor_command(CLI::App& app) {
  auto* monitor = app.add_subcommand(
      "monitor", "cutting force from servo-motor currents: calibrate, estimate, teach-in limits");
  monitor->require_subcommand(1);
  auto cal = std::make_shared<MonitorCalibrateArgs>();
  auto est = std::make_shared<MonitorEstimateArgs>();
  auto teach = std::make_shared<MonitorTeachArgs>();

  const auto bad_line = [](CLI::App* c, std::string& policy) {
    c->add_option("--on-bad-line", policy,
                  "stop (default): a malformed line is an error (exit 2); skip: leave it out "
                  "and report how many were skipped");
  };
  const auto estimator = [&](CLI::App* c, MonitorEstimatorArgs& a) {
    c->add_option("--calib", a.calib,
                  "calibration file (JSON, from `monitor calibrate`) or "
                  "zheng2012 (the source's preset)")
        ->required();
    c->add_option("--bandwidth-hz", a.bandwidth_hz,
                  "f_b of the estimate's filter, where its gain is 0.5 and its lag 90° (−3 dB at "
                  "0.644·f_b; default 50)");
    c->add_option("--standstill-rad-s", a.standstill_rad_s,
                  "below this speed the axis is at standstill (default 0.5)");
    bad_line(c, a.on_bad_line);
  };

  auto* c1 = monitor->add_subcommand("calibrate",
                                     "fit Tnzm and X (idle logs) and KBlf (loaded logs) per axis");
  c1->add_option("--idle", cal->idle, "no-cut logs at constant speeds (CSV)")->expected(1, -1);
  c1->add_option("--loaded", cal->loaded, "logs with a reference force column (CSV)")
      ->expected(1, -1);
  c1->add_option("--base", cal->base,
                 "calibration file or zheng2012: KT, J, measure and the values not fitted");
  c1->add_option("--kt", cal->kt, "torque constant [AXIS=]VALUE (N·m/A)");
  c1->add_option("--inertia", cal->inertia, "inertia at the motor [AXIS=]VALUE (kg·m²)");
  c1->add_option("--measure", cal->measure,
                 "equivalent current: space-vector (default; --base keeps its own) | rms");
  c1->add_option("--force-column", cal->force_column,
                 "reference force column of the loaded logs (default force_n)");
  c1->add_option("--window-s", cal->window_s, "averaging window (default 0.05 s)");
  c1->add_option("--steady-tolerance", cal->steady_tolerance,
                 "a window is steady if its speed changes by at most this fraction (default "
                 "0.01)");
  c1->add_option("--standstill-rad-s", cal->standstill_rad_s,
                 "windows with a slower sample are not used (default 0.5)");
  c1->add_option("--out", cal->out, "write the calibration (JSON)")->required();
  bad_line(c1, cal->on_bad_line);

  auto* c2 = monitor->add_subcommand(
      "estimate", "estimate the cutting force from a current log, as it arrives");
  c2->add_option("INPUT", est->input, "current log (CSV), - for standard input (default)");
  estimator(c2, est->estimator);
  c2->add_option("--out", est->out, "write the estimate to a file (else standard output)");
  c2->add_option("--band", est->band, "band file from `monitor teach`: add alarms");
  c2->add_option("--alarms", est->alarms, "with --band: write the alarm events (CSV)");
  c2->add_option("--tooth-frequency-hz", est->tooth_frequency_hz,
                 "also report the estimate's filter gain and lag at this frequency (e.g. teeth × "
                 "rpm/60)");
  c2->add_option("--json", est->json,
                 "write a summary as JSON: the filter of each axis, what force_sigma_n covers, "
                 "warnings");
  c2->add_option("--persist-s", est->persist_s,
                 "overload and breakage must last this long (default 0.005 s)");
  c2->add_option("--wear-fraction", est->wear_fraction,
                 "relative rise of the smoothed level that means wear (default 0.15)");
  c2->add_option("--wear-time-constant-s", est->wear_time_constant_s,
                 "smoothing of the wear indicator (default 0.5 s)");

  auto* c3 = monitor->add_subcommand(
      "teach", "teach-in: learn the band of the estimated force from reference runs");
  c3->add_option("REFERENCE", teach->inputs, "reference runs (CSV current logs), one cycle each")
      ->required();
  estimator(c3, teach->estimator);
  c3->add_option("--out", teach->out, "write the band (JSON)")->required();
  c3->add_option("--bin-s", teach->bin_s, "band bin width (default 0.01 s)");
  c3->add_option("--rpm", teach->rpm,
                 "spindle speed of the cut (with --teeth): the level is averaged over the tooth "
                 "period T = 60/(teeth·rpm) and smoothed with 0.12·T, the phase tolerance is one "
                 "revolution; a broken tooth is then caught within about one tooth period");
  c3->add_option("--teeth", teach->teeth, "number of teeth of the cutter (with --rpm)");
  c3->add_option("--smoothing-s", teach->smoothing_s,
                 "time constant of the monitored level (default 0.01 s; with --rpm and --teeth "
                 "0.12 tooth periods)");
  c3->add_option("--k-sigma", teach->k_sigma, "half-width: k·sigma (default 3) ...");
  c3->add_option("--relative-margin", teach->relative_margin, "... + this·mean (default 0.1) ...");
  c3->add_option("--absolute-margin-n", teach->absolute_margin_n, "... + this (default 0 N) ...");
  c3->add_option("--peak-margin", teach->peak_margin,
                 "... + this·the peak mean level (default 0.05)");
  c3->add_option("--phase-tolerance-s", teach->phase_tolerance_s,
                 "each bin takes the widest limits within ± this much cycle time, so that the "
                 "band does not depend on the spindle phase at cycle start: at least one spindle "
                 "revolution, 60/rpm (default 0.1 s; with --rpm: 60/rpm)");
  c3->add_option("--average-s", teach->average_s,
                 "moving average of |F| over this window before the smoothing: the tooth period "
                 "60/(teeth·rpm) removes the tooth pattern (default 0: none; with --rpm and "
                 "--teeth: the tooth period)");
  c3->add_option("--cutting-fraction", teach->cutting_fraction,
                 "bins whose mean is at least this fraction of the peak are cutting (default "
                 "0.2); breakage is watched there");

  return [=](std::ostream& out, std::ostream& err) -> int {
    if (!monitor->parsed()) return -1;
    if (c1->parsed()) return run_monitor_calibrate(*cal, out, err);
    if (c2->parsed()) return run_monitor_estimate(*est, out, err);
    if (c3->parsed()) return run_monitor_teach(*teach, out, err);
    return -1;
  };
}

}  // namespace cutdyn::cli
