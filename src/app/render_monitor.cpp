// The monitor's reports rendered: the text of `cutdyn monitor calibrate | estimate | teach`
// and of the warnings and alarms its jobs report as they happen (docs/models/monitor.md).
#include <algorithm>
#include <sstream>

#include "cutdyn/app/detail/text.hpp"
#include "cutdyn/app/render.hpp"

namespace cutdyn::app {
namespace {

std::string pm(double value, double sigma) { return human(value, 6) + " ± " + human(sigma, 2); }

std::string plural(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

void print_axis(std::ostream& out, const std::string& axis, const CalibratedAxis& a) {
  const AxisCalibration& c = a.calibration;
  out << "  axis " << axis << " (KT = " << human(c.model.torque_constant_nm_per_a) << " N·m/A "
      << to_string(c.model.measure) << ", J = " << human(c.model.inertia_kg_m2) << " kg·m²)\n";
  if (a.idle) {
    const IdleFit& f = *a.idle;
    out << "    step 1: Tnzm = " << pm(f.friction_nm, f.friction_sigma_nm)
        << " N·m, X = " << pm(f.viscous_nm_s_per_rad, f.viscous_sigma) << " N·m·s/rad\n"
        << "            " << f.report.windows << " steady windows at " << f.report.distinct_speeds
        << " speeds (" << f.report.windows_rejected
        << " rejected), R² = " << human(f.report.r_squared, 6)
        << ", residual RMS = " << human(f.report.residual_rms_nm, 3) << " N·m\n"
        << "            noise: current " << human(f.current_noise_a, 3) << " A, speed "
        << human(f.speed_noise_rad_s, 3) << " rad/s\n";
  }
  if (a.load) {
    const LoadFit& f = *a.load;
    out << "    step 2: KBlf = " << pm(f.force_gain_m, f.force_gain_sigma_m) << " m, "
        << f.report.windows << " windows, R² = " << human(f.report.r_squared, 6)
        << ", residual RMS = " << human(f.report.residual_rms_nm, 3) << " N·m\n";
  }
  if (!c.uncertainty_known)
    out << "    uncertainty unknown: Tnzm, X or KBlf are the base's, which has no known "
           "uncertainty; force_sigma_n will be left empty (calibrate with --idle and "
           "--loaded)\n";
}

// What the estimate is (docs/models/monitor.md §4.1, §4.3): the filter of each axis, for its
// first step, as text.
void describe_filter(std::ostream& out, const std::string& axis, const FilterReport& f) {
  out << "  axis " << axis
      << ": force_n = the force through H(f) = sinc(f·Δt)·e^(−jπfΔt)·((1 − r)/"
         "(1 − r·e^(−j2πfΔt)))², r = exp(−2π·f_b·Δt), f_b = "
      << human(f.bandwidth_hz) << " Hz";
  if (f.step_s <= 0.0) {
    out << " (one sample: no step)\n";
    return;
  }
  out << ", Δt = " << human(f.step_s) << " s: −3 dB at " << human(f.minus_3db_hz) << " Hz, gain "
      << human(f.gain_at_bandwidth, 3) << " and lag " << human(f.lag_deg_at_bandwidth, 3)
      << "° at f_b, delay " << human(f.delay_s, 3) << " s at low frequency";
  if (f.tooth_frequency_hz > 0.0)
    out << "; at the tooth frequency " << human(f.tooth_frequency_hz) << " Hz: gain "
        << human(f.gain_at_tooth_frequency, 3) << ", lag " << human(f.lag_deg_at_tooth_frequency, 3)
        << "°";
  out << "\n";
}

}  // namespace

std::string warning_text(const MonitorWarning& w) {
  std::ostringstream text;
  using Kind = MonitorWarning::Kind;
  text << w.source << ": ";
  switch (w.kind) {
    case Kind::kBadLine:
      text << w.message << " (skipped)";
      break;
    case Kind::kBadLinesSkipped:
      text << "skipped " << plural(w.count, "bad line", "bad lines");
      break;
    case Kind::kFit:
      text << "axis " << w.axis << ": " << w.message;
      break;
    case Kind::kTorqueSign:
      text << "line " << w.line << ", axis " << w.axis << " at " << human(w.time_s, 7)
           << " s: " << w.message;
      break;
    case Kind::kTorqueSignCount:
      text << "axis " << w.axis << ": the torque sign is in doubt at " << w.count << " samples";
      break;
    case Kind::kUncertaintyUnknown:
      text << "uncertainty unknown for the literature coefficients (axis " << w.axis
           << "): force_sigma_n is left empty; calibrate the machine (cutdyn monitor calibrate "
              "--idle ... --loaded ...) for an uncertainty";
      break;
    case Kind::kNoBand:
      text << "no band for axis " << w.axis << ": no alarms on it";
      break;
    case Kind::kBandwidthMismatch:
      text << "taught with --bandwidth-hz " << human(w.value) << ", estimating with "
           << human(w.other);
      break;
    case Kind::kNoToothPeriod:
      text << "no --rpm and --teeth: the monitored level keeps the tooth pattern (no averaging "
              "over the tooth period), so the band is wide and a broken tooth may take several "
              "tooth periods to be caught; give the cut's --rpm and --teeth";
      break;
  }
  return text.str();
}

std::string alarm_text(const std::string& axis, const AlarmEvent& a) {
  std::ostringstream text;
  text << to_string(a.kind) << " on axis " << axis << " at " << human(a.time_s, 7) << " s ("
       << (a.kind == AlarmKind::kWear
               ? "smoothed rise " + human(100.0 * a.level_n, 3) + " % > " +
                     human(100.0 * a.limit_n, 3) + " %"
               : "level " + human(a.level_n, 5) +
                     (a.kind == AlarmKind::kOverload ? " N > upper limit " : " N < lower limit ") +
                     human(a.limit_n, 5) + " N")
       << ", confirmed at " << human(a.detected_s, 7) << " s)";
  return text.str();
}

void write_text(std::ostream& out, const CalibrateReport& report) {
  const CalibrateOptions& options = report.options;
  const std::size_t axes = report.axes.size();
  out << "cutdyn monitor calibrate: " << axes << " ax" << (axes == 1 ? "is" : "es") << ", "
      << options.idle.size() << " idle and "
      << plural(options.loaded.size(), "loaded log", "loaded logs") << "\n";
  for (const auto& [axis, a] : report.axes) print_axis(out, axis, a);
}

void write_text(std::ostream& report, const EstimateReport& r) {
  report << "cutdyn monitor estimate: " << r.samples << " samples";
  if (!r.band.empty()) report << ", " << plural(r.alarms.size(), "alarm", "alarms");
  report << "\n";
  for (const EstimatedAxis& e : r.axes) describe_filter(report, e.axis, e.filter);
  report << "  " << kSigmaCovers << "\n";
}

void write_text(std::ostream& out, const TeachReport& report) {
  const TeachOptions& options = report.options;
  out << "cutdyn monitor teach: "
      << plural(options.references.size(), "reference run", "reference runs") << "\n";
  for (const auto& [axis, band] : report.band.axes) {
    const auto peak = std::max_element(band.mean_n.begin(), band.mean_n.end());
    std::size_t cutting = 0;
    for (auto c : band.cutting) cutting += c;
    out << "  axis " << axis << ": " << plural(static_cast<std::size_t>(band.runs), "run", "runs")
        << ", cycle " << human(band.cycle_s) << " s in " << band.mean_n.size()
        << " bins, peak mean level " << human(*peak, 5) << " N, " << cutting << " cutting bins\n";
  }
}

}  // namespace cutdyn::app
