#include "cutdyn/app/monitor_files.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <stdexcept>
#include <system_error>

#include "cutdyn/core/error.hpp"
#include "cutdyn/io/inputs.hpp"

namespace cutdyn::app {
namespace {

using nlohmann::json;

constexpr std::size_t kChunk = 1 << 16;

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

// The text of `key`: a string as it is, any other value as JSON ("" when absent), for a key
// whose value must be one of a few strings (a number there is refused by name, not thrown as
// json::type_error).
std::string text_at(const json& j, const char* key) {
  const auto it = j.find(key);
  if (it == j.end()) return "";
  return it->is_string() ? it->get<std::string>() : it->dump();
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
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InvalidInput({"is a folder, not a file"}, path);
  std::ifstream in(path);
  if (!in) throw InvalidInput({"cannot read the file"}, path);
  io::note_input(path);
  try {
    return json::parse(in);
  } catch (const json::exception& e) {  // parse_error, and out_of_range for a number like 1e999
    throw InvalidInput({std::string("not valid JSON: ") + e.what()}, path);
  }
}

void read_sigma(const json& s, const std::string& source, const std::string& at,
                AxisUncertainty& u) {
  if (!s.is_object()) throw InvalidInput({at + ": must be an object"}, source);
  reject_unknown(s,
                 {"inertia_kg_m2", "torque_constant_nm_per_a", "viscous_nm_s_per_rad",
                  "friction_nm", "friction_viscous_covariance", "force_gain_m"},
                 source, at);
  u.inertia_kg_m2 = number_at(s, "inertia_kg_m2", source, at, false);
  u.torque_constant_nm_per_a = number_at(s, "torque_constant_nm_per_a", source, at, false);
  u.viscous_nm_s_per_rad = number_at(s, "viscous_nm_s_per_rad", source, at, false);
  u.friction_nm = number_at(s, "friction_nm", source, at, false);
  u.friction_viscous_covariance = number_at(s, "friction_viscous_covariance", source, at, false);
  u.force_gain_m = number_at(s, "force_gain_m", source, at, false);
}

AxisCalibration axis_of_json(const json& a, const std::string& source, const std::string& at) {
  if (!a.is_object()) throw InvalidInput({at + ": must be an object"}, source);
  reject_unknown(a,
                 {"measure", "inertia_kg_m2", "torque_constant_nm_per_a", "viscous_nm_s_per_rad",
                  "friction_nm", "force_gain_m", "sigma", "current_noise_a", "speed_noise_rad_s",
                  "uncertainty_known", "idle_fit", "load_fit"},
                 source, at);
  AxisCalibration c;
  const std::string measure = text_at(a, "measure");
  const auto m = parse_current_measure(measure);
  if (!m)
    throw InvalidInput({at + "measure = \"" + measure + "\": must be rms or space-vector"}, source);
  c.model.measure = *m;
  c.model.inertia_kg_m2 = number_at(a, "inertia_kg_m2", source, at, true);
  c.model.torque_constant_nm_per_a = number_at(a, "torque_constant_nm_per_a", source, at, true);
  c.model.viscous_nm_s_per_rad = number_at(a, "viscous_nm_s_per_rad", source, at, true);
  c.model.friction_nm = number_at(a, "friction_nm", source, at, true);
  c.model.force_gain_m = number_at(a, "force_gain_m", source, at, true);
  c.current_noise_a = number_at(a, "current_noise_a", source, at, false);
  c.speed_noise_rad_s = number_at(a, "speed_noise_rad_s", source, at, false);
  if (const auto k = a.find("uncertainty_known"); k != a.end()) {
    if (!k->is_boolean())
      throw InvalidInput({at + "uncertainty_known = " + k->dump() + ": must be true or false"},
                         source);
    c.uncertainty_known = k->get<bool>();
  }
  if (a.contains("sigma")) read_sigma(a["sigma"], source, at + "sigma.", c.sigma);
  return c;
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

ForceBand band_of_json(const json& a, const json& doc, const std::string& path,
                       const std::string& at) {
  ForceBand b;
  b.options.bin_s = number_at(doc, "bin_s", path, "", true);
  b.options.smoothing_s = number_at(doc, "smoothing_s", path, "", true);
  b.options.average_s = number_at(doc, "average_s", path, "", false, 0.0);
  b.cycle_s = number_at(a, "cycle_s", path, at, true);
  const double runs = number_at(a, "runs", path, at, false, 0.0);
  if (!(runs >= 0.0 && runs <= 1e9 && runs == std::floor(runs)))  // else no int holds it
    throw InvalidInput({at + "runs = " + format_value(runs) + ": must be a whole number >= 0"},
                       path);
  b.runs = static_cast<int>(runs);
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

Calibration zheng2012_preset() {
  Calibration axes;
  for (char a : {'x', 'y', 'z'}) axes[std::string(1, a)] = zheng2012_calibration(a);
  return axes;
}

Calibration read_calibration(const std::string& path) {
  if (path == kZheng2012Preset) return zheng2012_preset();
  return calibration_from_json(read_json_file(path), path);
}

Calibration calibration_from_json(const json& doc, const std::string& source) {
  if (!doc.is_object() || text_at(doc, "format") != kCalibrationFormat)
    throw InvalidInput({std::string("format: must be \"") + kCalibrationFormat + "\""}, source);
  if (!doc.contains("axes") || !doc["axes"].is_object() || doc["axes"].empty())
    throw InvalidInput({"axes: missing or empty"}, source);
  Calibration axes;
  for (auto it = doc["axes"].begin(); it != doc["axes"].end(); ++it) {
    const AxisCalibration c = axis_of_json(it.value(), source, "axes." + it.key() + ".");
    rethrow_as(source, "axes." + it.key(), [&] {
      if (const auto p = c.validate(); !p.empty()) throw InvalidInput(p);
    });
    axes[it.key()] = c;
  }
  return axes;
}

json calibration_json(const std::map<std::string, CalibratedAxis>& axes) {
  json doc{{"format", kCalibrationFormat}, {"version", 1}};
  json all = json::object();
  for (const auto& [name, axis] : axes) {
    json a = axis_json(axis.calibration);
    if (axis.idle) {
      a["idle_fit"] = fit_json(axis.idle->report);
      if (!axis.idle->report.warnings.empty())
        a["idle_fit"]["warnings"] = axis.idle->report.warnings;
    }
    if (axis.load) {
      a["load_fit"] = fit_json(axis.load->report);
      a["load_fit"]["force_gain_sigma_from_idle_m"] = axis.load->force_gain_sigma_from_idle_m;
    }
    all[name] = a;
  }
  doc["axes"] = all;
  return doc;
}

json calibration_json(const Calibration& calibration) {
  std::map<std::string, CalibratedAxis> axes;
  for (const auto& [name, c] : calibration) axes[name].calibration = c;
  return calibration_json(axes);
}

BandFile read_band(const std::string& path) { return band_from_json(read_json_file(path), path); }

BandFile band_from_json(const json& doc, const std::string& source) {
  if (!doc.is_object() || text_at(doc, "format") != kBandFormat)
    throw InvalidInput({std::string("format: must be \"") + kBandFormat + "\""}, source);
  if (!doc.contains("axes") || !doc["axes"].is_object())
    throw InvalidInput({"axes: missing"}, source);
  BandFile file;
  BandOptions& o = file.options;
  o.bin_s = number_at(doc, "bin_s", source, "", true);
  o.smoothing_s = number_at(doc, "smoothing_s", source, "", true);
  o.k_sigma = number_at(doc, "k_sigma", source, "", false, o.k_sigma);
  o.relative_margin = number_at(doc, "relative_margin", source, "", false, o.relative_margin);
  o.absolute_margin_n = number_at(doc, "absolute_margin_n", source, "", false, o.absolute_margin_n);
  o.peak_margin = number_at(doc, "peak_margin", source, "", false, o.peak_margin);
  o.cutting_fraction = number_at(doc, "cutting_fraction", source, "", false, o.cutting_fraction);
  o.phase_tolerance_s = number_at(doc, "phase_tolerance_s", source, "", false, o.phase_tolerance_s);
  o.average_s = number_at(doc, "average_s", source, "", false, 0.0);
  if (doc.contains("bandwidth_hz") && !doc["bandwidth_hz"].is_null())
    file.bandwidth_hz = number_at(doc, "bandwidth_hz", source, "", true);
  if (const auto c = doc.find("calibration"); c != doc.end() && c->is_string())
    file.calibration = c->get<std::string>();
  for (auto it = doc["axes"].begin(); it != doc["axes"].end(); ++it)
    file.axes.emplace(it.key(), band_of_json(it.value(), doc, source, "axes." + it.key() + "."));
  return file;
}

json band_json(const BandFile& band) {
  const BandOptions& o = band.options;
  json doc{{"format", kBandFormat},
           {"version", 1},
           {"bin_s", o.bin_s},
           {"smoothing_s", o.smoothing_s},
           {"k_sigma", o.k_sigma},
           {"relative_margin", o.relative_margin},
           {"absolute_margin_n", o.absolute_margin_n},
           {"peak_margin", o.peak_margin},
           {"cutting_fraction", o.cutting_fraction},
           {"phase_tolerance_s", o.phase_tolerance_s},
           {"average_s", o.average_s},
           {"calibration", band.calibration}};
  if (band.bandwidth_hz) doc["bandwidth_hz"] = *band.bandwidth_hz;
  json axes = json::object();
  for (const auto& [axis, b] : band.axes) {
    json a{{"cycle_s", b.cycle_s}, {"runs", b.runs},       {"mean_n", b.mean_n},
           {"sigma_n", b.sigma_n}, {"upper_n", b.upper_n}, {"lower_n", b.lower_n}};
    a["cutting"] = json::array();
    for (auto c : b.cutting) a["cutting"].push_back(static_cast<int>(c));
    axes[axis] = a;
  }
  doc["axes"] = axes;
  return doc;
}

LogInput::LogInput(const std::string& path) : buffer_(new char[kChunk]) {
  if (path == "-" || path.empty()) {
    fd_ = STDIN_FILENO;
    name_ = "standard input";
    return;
  }
  name_ = path;
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) throw InvalidInput({"cannot read: " + std::generic_category().message(errno)}, path);
  own_ = true;
  struct stat s {};
  if (::fstat(fd_, &s) == 0 && S_ISDIR(s.st_mode)) {
    ::close(fd_);  // (a constructor that throws has no destructor run)
    throw InvalidInput({"is a folder, not a current log"}, path);
  }
  io::note_input(path);
}

LogInput::LogInput(std::string name, std::string text)
    : name_(std::move(name)), in_memory_(true), text_(std::move(text)) {}

std::unique_ptr<LogInput> LogInput::open(const std::string& name, const LogTexts& texts) {
  if (const auto it = texts.find(name); it != texts.end())
    return std::make_unique<LogInput>(name, it->second);
  return std::make_unique<LogInput>(name);
}

LogInput::~LogInput() {
  if (own_) ::close(fd_);
}

std::string_view LogInput::read() {
  if (in_memory_) {
    if (text_read_) return {};
    text_read_ = true;
    return text_;
  }
  for (;;) {
    const ssize_t n = ::read(fd_, buffer_.get(), kChunk);
    if (n >= 0) return {buffer_.get(), static_cast<std::size_t>(n)};
    if (errno == EAGAIN || errno == EWOULDBLOCK) {
      // A non-blocking input (a pipe its writer made so) that has nothing yet: a pause of the
      // stream, not its end; wait for more.
      pollfd ready{fd_, POLLIN, 0};
      ::poll(&ready, 1, -1);
      continue;
    }
    if (errno != EINTR)
      throw std::runtime_error(name_ + ": read error: " + std::generic_category().message(errno));
  }
}

std::optional<std::pair<std::string, double>> parse_axis_value(const std::string& text) {
  const auto eq = text.find('=');
  const std::string axis = eq == std::string::npos ? "" : text.substr(0, eq);
  const std::string number = eq == std::string::npos ? text : text.substr(eq + 1);
  try {
    std::size_t used = 0;
    const double v = std::stod(number, &used);
    if (used == number.size() && std::isfinite(v)) return std::pair{axis, v};
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

}  // namespace cutdyn::app
