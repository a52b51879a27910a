#include "monitor_stream.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

namespace cutdyn::app::detail {
namespace {

constexpr std::size_t kShownBadLines = 5;

}  // namespace

void warn(const MonitorListener& listener, std::vector<MonitorWarning>& warnings,
          MonitorWarning w) {
  if (listener.warning) listener.warning(w);
  warnings.push_back(std::move(w));
}

void BadLines::take(std::vector<CsvLineError>& errors) {
  for (const CsvLineError& e : errors) {
    if (stop_) throw InvalidInput({e.text()}, source_);
    if (count_ < kShownBadLines) {
      MonitorWarning w;
      w.kind = MonitorWarning::Kind::kBadLine;
      w.source = source_;
      w.line = e.line;
      w.message = e.text();
      warn(listener_, warnings_, std::move(w));
    }
    ++count_;
  }
  errors.clear();
}

void BadLines::finish(std::size_t good) {
  if (count_ > 0) {
    MonitorWarning w;
    w.kind = MonitorWarning::Kind::kBadLinesSkipped;
    w.source = source_;
    w.count = count_;
    warn(listener_, warnings_, std::move(w));
  }
  if (good == 0)
    throw InvalidInput({"no valid data line (" + std::to_string(count_) + " skipped)"}, source_);
}

InvalidInput measure_mismatch(const std::string& measure_name, const std::string& file,
                              std::size_t line, const std::string& axis, CurrentMeasure logged,
                              CurrentMeasure calibration) {
  return InvalidInput(
      {"line " + std::to_string(line) + ": axis " + axis +
       ": the currents were logged with measure = " + std::string(to_string(logged)) +
       ", the calibration's measure is " + std::string(to_string(calibration)) +
       ": KT holds for one measure only (they differ by √2); calibrate with " + measure_name + " " +
       std::string(to_string(logged)) + " or log the calibration's measure"},
      file);
}

std::map<std::string, AxisRun> read_log(LogInput& in, const std::string& force_column, bool stop,
                                        const MonitorListener& listener,
                                        std::vector<MonitorWarning>& warnings,
                                        RecordedMeasures* measures) {
  CurrentCsvParser parser(in.name(), force_column);
  BadLines bad(in.name(), stop, listener, warnings);
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

EstimateStream::EstimateStream(const Calibration& calibration, std::string calibration_name,
                               const EstimatorOptions& options, std::string source, bool stop,
                               const MonitorListener& listener,
                               std::vector<MonitorWarning>& warnings,
                               std::function<void()> flush)
    : calibration_(calibration),
      calibration_name_(std::move(calibration_name)),
      options_(options),
      source_(std::move(source)),
      stop_(stop),
      listener_(listener),
      warnings_(warnings),
      flush_(std::move(flush)),
      parser_(source_),
      bad_(source_, stop, listener, warnings) {}

EstimateStream::Axis* EstimateStream::make_axis(std::size_t i) {
  while (by_index_.size() <= i) by_index_.push_back(nullptr);
  const std::string& name = parser_.axes()[i];
  const auto it = calibration_.find(name);
  if (it == calibration_.end()) return nullptr;
  by_index_[i] = std::make_unique<Axis>();
  by_index_[i]->name = name;
  by_index_[i]->estimator = std::make_unique<AxisForceEstimator>(it->second, options_);
  made_.push_back(by_index_[i].get());
  return by_index_[i].get();
}

void EstimateStream::bandwidth_error(const InvalidInput& x, const CurrentRow& r, const Axis& a) {
  // The bandwidth against the log's sampling (the only check of update).
  std::vector<std::string> problems;
  for (const std::string& p : x.problems())
    problems.push_back(names_.bandwidth + ": " + p + ", axis " + a.name + " at line " +
                       std::to_string(r.line));
  throw InvalidInput(problems, source_);
}

void EstimateStream::first_row(Axis& a) {
  a.seen = true;
  const CurrentMeasure measure = a.estimator->calibration().model.measure;
  if (const auto m = parser_.recorded_measure(a.name); m && m->first != measure)
    throw measure_mismatch(names_.measure, source_, m->second, a.name, m->first, measure);
}

void EstimateStream::refuse(const CurrentRow& r, const Axis* a, std::vector<CsvLineError>& own) {
  const std::string& name = parser_.axes()[static_cast<std::size_t>(r.axis)];
  std::string problem;
  if (!a) {
    std::string have;
    for (const auto& [axis, c] : calibration_) have += (have.empty() ? "" : ", ") + axis;
    problem = "axis \"" + name + "\" is not in the calibration " + calibration_name_ +
              " (it has " + have + ")";
  } else {
    problem = "the estimate of axis " + name +
              " is not finite: a value of the line is beyond what the estimator can take (a "
              "current or speed near the range of a double, or a time step near 0); the axis "
              "starts afresh at its next line";
  }
  own.push_back({r.line, std::move(problem)});
  if (stop_) {
    // The first bad line (the parser stopped after these rows): the estimates before it are
    // out first.
    if (flush_) flush_();
    bad_.take(own);
  }
}

void EstimateStream::first_doubt(const CurrentRow& r, Axis& a) {
  a.first_doubt_line = r.line;
  a.first_doubt_time_s = r.time_s;
  MonitorWarning w;
  w.kind = MonitorWarning::Kind::kTorqueSign;
  w.source = source_;
  w.axis = a.name;
  w.line = r.line;
  w.time_s = r.time_s;
  w.message = kSignDoubt;
  warn(listener_, warnings_, std::move(w));
}

void EstimateStream::end_piece(std::vector<CsvLineError>& own) {
  rows_.clear();
  if (flush_) flush_();
  if (!own.empty()) {  // in line order with the parser's
    errors_.insert(errors_.end(), own.begin(), own.end());
    std::stable_sort(errors_.begin(), errors_.end(),
                     [](const CsvLineError& x, const CsvLineError& y) { return x.line < y.line; });
  }
  bad_.take(errors_);  // after the good lines before it are out
}

std::size_t EstimateStream::close() {
  bad_.finish(good_);
  std::map<std::string, std::size_t> doubts;  // by axis name
  for (const Axis* a : made_)
    if (a->sign_doubts > 1) doubts[a->name] = a->sign_doubts;
  for (const auto& [axis, samples] : doubts) {
    MonitorWarning w;
    w.kind = MonitorWarning::Kind::kTorqueSignCount;
    w.source = source_;
    w.axis = axis;
    w.count = samples;
    warn(listener_, warnings_, std::move(w));
  }
  return good_;
}

}  // namespace cutdyn::app::detail
