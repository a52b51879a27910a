#include "cli/common.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "cutdyn/core/error.hpp"

namespace cutdyn::cli {

io::Case load_case(const std::string& path, std::string_view default_example) {
  return path.empty() ? io::load_example(default_example) : io::load_case_file(path);
}

void require_turning(const io::Case& c, std::string_view command) {
  if (c.process != io::Process::kTurning) {
    throw InvalidInput(
        {"process = \"" + std::string(io::to_string(c.process)) + "\": `cutdyn " +
         std::string(command) +
         "` handles turning in this version (milling stability is not available yet)"},
        c.source);
  }
}

TurningModel turning_model(const io::Case& c, std::string_view command) {
  require_turning(c, command);
  Validator v;
  if (!c.cutting.kt_pa)
    v.add("cutting.kt_n_per_mm2: missing (required by `cutdyn " + std::string(command) + "`)");
  if (c.vibration && !c.vibration->duty_cycle && !c.vibration->workpiece_diameter_m)
    v.add(
        "vibration.workpiece_diameter_mm: missing (required to compute the duty cycle at each "
        "spindle speed; or give vibration.duty_cycle)");
  v.throw_if_any(c.source);
  TurningModel m;
  m.modal = c.modal;
  m.kt_pa = *c.cutting.kt_pa;
  if (c.vibration) {
    VibrationAssist va;
    va.frequency_hz = c.vibration->frequency_hz;
    va.amplitude_m = c.vibration->amplitude_m.value_or(0.0);
    va.workpiece_diameter_m = c.vibration->workpiece_diameter_m;
    va.duty_cycle = c.vibration->duty_cycle;
    m.vibration = va;
  }
  // The loader checked ranges in the user's units; this catches what only the model knows
  // (an undamped mode cannot be analysed for stability).
  if (const auto problems = m.validate(); !problems.empty()) throw InvalidInput(problems, c.source);
  return m;
}

std::function<void(int, int)> progress_reporter(std::ostream& err, std::string label) {
  if (!isatty(STDERR_FILENO)) return {};
  return [&err, label](int done, int total) {
    err << "\r" << label << ": " << done << "/" << total << (done == total ? "\n" : "")
        << std::flush;
  };
}

std::string human(double value, int digits) {
  // Never scientific notation for the magnitudes machinists read (20000 Hz, not 2e+04).
  const double magnitude = std::abs(value);
  if (magnitude >= 1.0 && magnitude < 1e9)
    digits = std::max(digits, static_cast<int>(std::floor(std::log10(magnitude))) + 1);
  std::ostringstream s;
  s << std::setprecision(digits) << value;
  return s.str();
}

}  // namespace cutdyn::cli
