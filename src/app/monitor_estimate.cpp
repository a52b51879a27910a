// The estimate job (docs/models/monitor.md §4, §5): a current log through the estimators of
// its axes and, with a band, the alarm monitors, as it arrives.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <set>

#include "cutdyn/app/monitor.hpp"
#include "monitor_stream.hpp"

namespace cutdyn::app {
namespace {

FilterReport filter_report(const AxisForceEstimator& e, double tooth_hz) {
  FilterReport f;
  f.bandwidth_hz = e.options().bandwidth_hz;
  f.step_s = e.first_step_s();
  if (f.step_s <= 0.0) return f;
  const EstimateFilter h{f.bandwidth_hz, f.step_s};
  f.minus_3db_hz = h.minus_3db_hz();
  f.delay_s = h.delay_s();
  f.gain_at_bandwidth = h.gain(f.bandwidth_hz);
  f.lag_deg_at_bandwidth = h.lag_deg(f.bandwidth_hz);
  if (tooth_hz > 0.0) {
    f.tooth_frequency_hz = tooth_hz;
    f.gain_at_tooth_frequency = h.gain(tooth_hz);
    f.lag_deg_at_tooth_frequency = h.lag_deg(tooth_hz);
  }
  return f;
}

}  // namespace

std::vector<std::string> EstimateOptions::validate() const {
  Validator v;
  v.merge(estimator.validate());
  v.merge(alarms.validate());
  if (!(tooth_frequency_hz >= 0.0) || !std::isfinite(tooth_frequency_hz))
    v.add("tooth_frequency_hz = " + std::to_string(tooth_frequency_hz) +
          " Hz: must be a finite number >= 0 (0: not stated)");
  return v.problems();
}

struct EstimateJob::State {
  Calibration calibration;
  EstimateOptions options;
  std::string band_name;
  Sinks sinks;
  MonitorListener listener;
  EstimateReport report;
  std::map<std::string, AlarmMonitor> monitors;
  bool with_band = false;
  // The CSV text of the rows since the last flush, in [0, used) of `buffer`, which is only
  // storage: rows are written in place (write_estimate_row), not appended with a copy each.
  std::string buffer;
  std::size_t used = 0;
  std::map<std::string, std::size_t> seen_events;
  std::set<std::string> unbanded;
  std::unique_ptr<detail::EstimateStream> stream;

  // `n` bytes of room at the end of the text.
  char* room(std::size_t n) {
    if (buffer.size() < used + n) buffer.resize(std::max(2 * buffer.size(), used + n));
    return buffer.data() + used;
  }
  void put(std::string_view text) {
    std::memcpy(room(text.size()), text.data(), text.size());
    used += text.size();
  }
  void each(const CurrentRow& r, const detail::EstimateStream::Axis& a, const ForceEstimate& e);
  // The stream's `each`.
  void operator()(const CurrentRow& r, const detail::EstimateStream::Axis& a,
                  const ForceEstimate& e) {
    each(r, a, e);
  }
  void alarm_columns(double time_s, const std::string& axis, const ForceEstimate& e,
                     std::optional<AlarmSample>& alarm);
  void warn(MonitorWarning::Kind kind, const std::string& source, const std::string& axis) {
    MonitorWarning w;
    w.kind = kind;
    w.source = source;
    w.axis = axis;
    detail::warn(listener, report.warnings, std::move(w));
  }
};

void EstimateJob::State::alarm_columns(double time_s, const std::string& axis,
                                       const ForceEstimate& e, std::optional<AlarmSample>& alarm) {
  const auto it = monitors.find(axis);
  if (it == monitors.end()) {
    if (unbanded.insert(axis).second) warn(MonitorWarning::Kind::kNoBand, band_name, axis);
    put(",,,,");
    return;
  }
  const AlarmSample& s = alarm.emplace(it->second.update(time_s, e.force_n));
  for (const double x : {s.level_n, s.upper_n, s.lower_n}) {
    char* p = room(1 + kNumberRoom);
    *p = ',';
    used = static_cast<std::size_t>(write_number(p + 1, x, 7) - buffer.data());
  }
  put(",");
  put(alarm_text(s.active));
  const auto& all = it->second.events();
  for (std::size_t& k = seen_events[axis]; k < all.size(); ++k) {
    if (listener.alarm) listener.alarm(axis, all[k]);
    report.alarms.emplace_back(axis, all[k]);
  }
}

inline void EstimateJob::State::each(const CurrentRow& r, const detail::EstimateStream::Axis& a,
                                     const ForceEstimate& e) {
  const std::string& axis = a.name;
  // The calibration's uncertainty is unknown (the literature coefficients, §4.3 of
  // docs/models/monitor.md): said once per axis, at its first estimate.
  if (!e.sigma_known && a.estimates == 1)
    warn(MonitorWarning::Kind::kUncertaintyUnknown, report.calibration, axis);
  char* p = room(kEstimateRowRoom + axis.size() + 1);  // the row and its line end
  p = write_estimate_row(p, r.time_s, axis, e);
  if (!with_band && !sinks.row) {  // the plain estimate
    *p++ = '\n';
    used = static_cast<std::size_t>(p - buffer.data());
    return;
  }
  used = static_cast<std::size_t>(p - buffer.data());
  std::optional<AlarmSample> alarm;
  if (with_band) alarm_columns(r.time_s, axis, e, alarm);
  put("\n");
  if (sinks.row) sinks.row(EstimatedRow{r, axis, e, alarm ? &*alarm : nullptr});
}

EstimateJob::EstimateJob(Calibration calibration, std::string calibration_name,
                         const EstimateOptions& options, std::optional<BandFile> band,
                         std::string band_name, std::string source, Sinks sinks,
                         MonitorListener listener)
    : state_(std::make_unique<State>()) {
  if (const auto p = options.validate(); !p.empty()) throw InvalidInput(p, "options");
  State& s = *state_;
  s.calibration = std::move(calibration);
  s.options = options;
  s.band_name = std::move(band_name);
  s.sinks = std::move(sinks);
  s.listener = std::move(listener);
  s.report.options = options;
  s.report.source = source;
  s.report.calibration = std::move(calibration_name);
  s.report.band = s.band_name;
  s.with_band = band.has_value();
  if (band) {
    for (auto& [axis, b] : band->axes) s.monitors.emplace(axis, AlarmMonitor(b, options.alarms));
    if (band->bandwidth_hz && *band->bandwidth_hz != options.estimator.bandwidth_hz) {
      MonitorWarning w;
      w.kind = MonitorWarning::Kind::kBandwidthMismatch;
      w.source = s.band_name;
      w.value = *band->bandwidth_hz;
      w.other = options.estimator.bandwidth_hz;
      detail::warn(s.listener, s.report.warnings, std::move(w));
    }
  }
  s.put(kEstimateHeader);
  if (s.with_band) s.put(",level_n,upper_n,lower_n,alarm");
  s.put("\n");
  s.stream = std::make_unique<detail::EstimateStream>(
      s.calibration, s.report.calibration, options.estimator, std::move(source),
      options.stop_at_bad_line, s.listener, s.report.warnings,
      [&s] {
        if (s.sinks.csv) s.sinks.csv(std::string_view(s.buffer.data(), s.used));
        s.used = 0;
      });
  s.stream->set_names(options.names);
}

EstimateJob::~EstimateJob() = default;

void EstimateJob::feed(std::string_view chunk) { state_->stream->feed(chunk, *state_); }

EstimateReport EstimateJob::finish() {
  State& s = *state_;
  s.report.samples = s.stream->finish(s);
  s.report.bad_lines = s.stream->bad_lines();
  s.report.signed_current = s.stream->signed_current();
  for (const detail::EstimateStream::Axis* a : s.stream->axes()) {
    EstimatedAxis e;
    e.axis = a->name;
    e.filter = filter_report(*a->estimator, s.options.tooth_frequency_hz);
    // Unknown only where it was said (an axis with estimates; every one carries the
    // calibration's flag).
    e.sigma_known = a->estimates == 0 || a->estimator->calibration().uncertainty_known;
    e.banded = s.monitors.count(a->name) > 0;
    e.sign_doubt_samples = a->sign_doubts;
    e.sign_doubt_first_line = a->first_doubt_line;
    e.sign_doubt_first_time_s = a->first_doubt_time_s;
    s.report.axes.push_back(std::move(e));
  }
  return s.report;
}

EstimateReport estimate(const std::string& path, const std::string& calibration_path,
                        const EstimateOptions& options, const std::string& band_path,
                        EstimateJob::Sinks sinks, const MonitorListener& listener) {
  Calibration calibration = read_calibration(calibration_path);
  std::optional<BandFile> band;
  if (!band_path.empty()) band = read_band(band_path);
  LogInput in(path);
  EstimateJob job(std::move(calibration), calibration_path, options, std::move(band), band_path,
                  in.name(), std::move(sinks), listener);
  for (std::string_view chunk = in.read(); !chunk.empty(); chunk = in.read()) job.feed(chunk);
  return job.finish();
}

}  // namespace cutdyn::app
