// The teach job (docs/models/monitor.md §5): the band of the estimated force from reference
// runs.
#include "cutdyn/app/monitor.hpp"
#include "monitor_stream.hpp"

namespace cutdyn::app {

BandOptions TeachOptions::effective_band() const {
  BandOptions b = band;
  if (rpm && teeth) {
    const BandOptions cut = BandOptions::for_milling(*rpm, *teeth);
    b.smoothing_s = cut.smoothing_s;
    b.phase_tolerance_s = cut.phase_tolerance_s;
    b.average_s = cut.average_s;
  }
  if (smoothing_s) b.smoothing_s = *smoothing_s;
  if (phase_tolerance_s) b.phase_tolerance_s = *phase_tolerance_s;
  if (average_s) b.average_s = *average_s;
  return b;
}

std::vector<std::string> TeachOptions::validate() const {
  Validator v;
  if (references.empty()) v.add("references: give at least one reference run");
  if (calibration.empty()) v.add("calibration: missing (a calibration file or zheng2012)");
  v.merge(estimator.validate());
  if (rpm.has_value() != teeth.has_value())
    v.add("rpm and teeth: give both or neither (the tooth period is 60/(teeth·rpm))");
  else
    try {
      v.merge(effective_band().validate());
    } catch (const InvalidInput& e) {
      for (const std::string& p : e.problems()) v.add(p);
    }
  return v.problems();
}

TeachReport teach(const TeachOptions& options, const MonitorListener& listener) {
  if (const auto p = options.validate(); !p.empty()) throw InvalidInput(p, "options");
  TeachReport report;
  report.options = options;
  const Calibration calibration = options.calibration_given
                                      ? *options.calibration_given
                                      : read_calibration(options.calibration);
  std::map<std::string, std::vector<ForceRun>> runs;
  for (const std::string& input : options.references) {
    std::map<std::string, ForceRun> run;
    const auto in = LogInput::open(input, options.texts);
    detail::EstimateStream stream(calibration, options.calibration, options.estimator,
                                  in->name(), options.stop_at_bad_line, listener,
                                  report.warnings, {});
    auto each = [&](const CurrentRow& r, const detail::EstimateStream::Axis& a,
                    const ForceEstimate& e) {
      ForceRun& axis_run = run[a.name];
      axis_run.time_s.push_back(r.time_s);
      axis_run.force_n.push_back(e.force_n);
    };
    for (std::string_view chunk = in->read(); !chunk.empty(); chunk = in->read())
      stream.feed(chunk, each);
    stream.finish(each);
    for (auto& [axis, r] : run) runs[axis].push_back(std::move(r));
  }
  BandFile& band = report.band;
  band.options = options.effective_band();
  band.bandwidth_hz = options.estimator.bandwidth_hz;
  band.calibration = options.calibration;
  // The lambda captures the pair, not a structured binding (clang 14 cannot; the fuzz build).
  for (const auto& entry : runs)
    rethrow_as("teach-in", "axis " + entry.first,
               [&] { band.axes[entry.first] = teach_band(entry.second, band.options); });
  // Without the tooth period the level keeps the tooth pattern: a wide band, a slow alarm.
  if (!options.rpm && !options.average_s) {
    MonitorWarning w;
    w.kind = MonitorWarning::Kind::kNoToothPeriod;
    w.source = "monitor teach";
    detail::warn(listener, report.warnings, std::move(w));
  }
  return report;
}

}  // namespace cutdyn::app
