// The monitor jobs' shared parts (not public): the bad lines of a log, a whole log read into
// runs per axis, and the estimators of a stream's axes fed row by row.
#pragma once

#include <cmath>
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "cutdyn/app/monitor.hpp"
#include "cutdyn/core/error.hpp"

namespace cutdyn::app::detail {

/// Records a warning: in `warnings` and to the listener.
void warn(const MonitorListener& listener, std::vector<MonitorWarning>& warnings, MonitorWarning w);

/// The bad lines of one input: stop (throw the first) or skip (warn about the first few,
/// count them).
class BadLines {
 public:
  BadLines(std::string source, bool stop, const MonitorListener& listener,
           std::vector<MonitorWarning>& warnings)
      : source_(std::move(source)), stop_(stop), listener_(listener), warnings_(warnings) {}
  void take(std::vector<CsvLineError>& errors);
  /// The summary, and an error if no line was good.
  void finish(std::size_t good);
  std::size_t count() const { return count_; }

 private:
  std::string source_;
  bool stop_;
  const MonitorListener& listener_;
  std::vector<MonitorWarning>& warnings_;
  std::size_t count_ = 0;
};

/// The refusal of a log whose recorded current measure is not the calibration's (docs/models/
/// monitor.md §1, §6).
InvalidInput measure_mismatch(const std::string& measure_name, const std::string& file,
                              std::size_t line, const std::string& axis, CurrentMeasure logged,
                              CurrentMeasure calibration);

/// A whole log, per axis: the runs of calibration; `measures` gets the measure its comments
/// record per axis (and the line).
using RecordedMeasures = std::map<std::string, std::pair<CurrentMeasure, std::size_t>>;
std::map<std::string, AxisRun> read_log(LogInput& in, const std::string& force_column, bool stop,
                                        const MonitorListener& listener,
                                        std::vector<MonitorWarning>& warnings,
                                        RecordedMeasures* measures = nullptr);

/// A log fed chunk by chunk through the estimators of its axes (made as the axes appear):
/// `each(row, axis, estimate)` per good row (a callable given to feed and finish: the caller's
/// own type, so that its work per row is compiled into the loop over the rows), `flush()` after
/// the rows of each chunk, before its bad lines are dealt with.
class EstimateStream {
 public:
  EstimateStream(const Calibration& calibration, std::string calibration_name,
                 const EstimatorOptions& options, std::string source, bool stop,
                 const MonitorListener& listener, std::vector<MonitorWarning>& warnings,
                 std::function<void()> flush);
  /// How the front end calls the measure and the bandwidth, for the messages.
  void set_names(const RequestNames& names) { names_ = names; }
  template <class Each>
  void feed(std::string_view chunk, Each& each) {
    parser_.feed(chunk, rows_, errors_, stop_);
    process(each);
  }
  /// The end: the last line, the counts. Returns the good rows.
  template <class Each>
  std::size_t finish(Each& each) {
    parser_.finish(rows_, errors_, stop_);
    process(each);
    return close();
  }

  struct Axis {
    std::string name;
    std::unique_ptr<AxisForceEstimator> estimator;
    bool seen = false;
    std::size_t estimates = 0;  // the good rows so far, this one included in `each`
    std::size_t sign_doubts = 0, first_doubt_line = 0;
    double first_doubt_time_s = 0.0;
  };
  /// The axes estimated, in order of appearance.
  const std::vector<Axis*>& axes() const { return made_; }
  bool signed_current() const { return parser_.has_rotor_angle(); }
  std::size_t bad_lines() const { return bad_.count(); }
  const std::string& source() const { return source_; }

 private:
  // The axis of parser index i, which has none yet: made now, or nullptr if the calibration
  // has no such axis (then asked again at each of its rows).
  Axis* make_axis(std::size_t i);
  // The rows of a piece through their axes' estimators, then the piece's end.
  template <class Each>
  void process(Each& each);
  // The row through the axis' estimator (a bandwidth above the row's Nyquist frequency thrown
  // as the front end names it, by bandwidth_error). Returned as update makes it: a copy of a
  // just written estimate would wait on its stores.
  ForceEstimate update(const CurrentRow& r, Axis& a) {
    AxisForceEstimator& e = *a.estimator;
    try {
      return parser_.has_rotor_angle()
                 ? e.update(r.time_s, r.iu_a, r.iv_a, r.iw_a, r.speed_rad_s, r.rotor_angle_rad)
                 : e.update(r.time_s, r.iu_a, r.iv_a, r.iw_a, r.speed_rad_s);
    } catch (const InvalidInput& x) {
      bandwidth_error(x, r, a);
    }
  }
  [[noreturn, gnu::noinline]] void bandwidth_error(const InvalidInput& x, const CurrentRow& r,
                                                   const Axis& a);
  // Row r's estimate taken (counted, its sign doubt said), or refused if it is not finite.
  bool accept(const CurrentRow& r, Axis& a, const ForceEstimate& estimate) {
    // Finite values so large (a current of 1e200 A) or steps so short (1e-300 s) that the
    // estimate overflows: a bad line, never a NaN or an infinity in the output; the axis
    // starts afresh at its next line (its filter state holds the overflow).
    if (!std::isfinite(estimate.force_n) || !std::isfinite(estimate.force_sigma_n) ||
        !std::isfinite(estimate.speed_rad_s) || !std::isfinite(estimate.accel_rad_s2)) {
      a.estimator->reset();
      return false;
    }
    if (estimate.torque_sign_doubtful && a.sign_doubts++ == 0) first_doubt(r, a);
    ++a.estimates;
    ++good_;
    return true;
  }
  // The first row of an axis: its log's recorded measure checked against the calibration's.
  [[gnu::noinline]] void first_row(Axis& a);
  // The first row of an axis whose torque sign is in doubt: kept and said.
  [[gnu::noinline]] void first_doubt(const CurrentRow& r, Axis& a);
  // Row r refused (its axis `a` not in the calibration, or null; or its estimate not finite):
  // in `own`, and thrown at once where the stream stops at a bad line.
  [[gnu::noinline]] void refuse(const CurrentRow& r, const Axis* a, std::vector<CsvLineError>& own);
  // A piece's end: its rows handed on (flush), then its bad lines (`own`: the estimate's).
  void end_piece(std::vector<CsvLineError>& own);
  // finish's counts and warnings.
  std::size_t close();

  RequestNames names_;
  const Calibration& calibration_;
  std::string calibration_name_;
  EstimatorOptions options_;
  std::string source_;
  bool stop_;
  const MonitorListener& listener_;
  std::vector<MonitorWarning>& warnings_;
  std::function<void()> flush_;
  CurrentCsvParser parser_;
  BadLines bad_;
  std::vector<CurrentRow> rows_;
  std::vector<CsvLineError> errors_;
  std::vector<std::unique_ptr<Axis>> by_index_;
  std::vector<Axis*> made_;
  std::size_t good_ = 0;
};

template <class Each>
void EstimateStream::process(Each& each) {
  std::vector<CsvLineError> own;  // the lines the parser passed and the estimate refuses
  for (const CurrentRow& r : rows_) {
    const auto i = static_cast<std::size_t>(r.axis);
    Axis* const a = i < by_index_.size() && by_index_[i] ? by_index_[i].get() : make_axis(i);
    if (a) {
      if (!a->seen) [[unlikely]]
        first_row(*a);
      const ForceEstimate estimate = update(r, *a);
      if (accept(r, *a, estimate)) {
        each(r, static_cast<const Axis&>(*a), estimate);
        continue;
      }
    }
    refuse(r, a, own);
  }
  end_piece(own);
}

}  // namespace cutdyn::app::detail
