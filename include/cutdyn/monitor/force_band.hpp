// Limits and alarms on the estimated force in the manner of commercial tool monitors:
// teach-in of a band from reference runs, then overload, breakage and wear alarms;
// docs/models/monitor.md §5.
//
// The monitored level is L = a first-order low-pass (time constant `smoothing_s`) of |Fc|.
// Teach-in: in each bin of `bin_s` of the cycle time (time since the run's first sample),
// the mean m and standard deviation s of L over every sample of every reference run; the
// band is m ± (k·s + rel·m + abs). A bin is "cutting" if m >= cutting_fraction·max(m).
// Monitoring (cycle time = time since the first sample, modulo the cycle length):
//  * overload: L > upper for at least `persist_s`;
//  * breakage: in a cutting bin, L < lower for at least `persist_s` (a sudden loss of load
//    where the reference cut: a broken or missing tool);
//  * wear: W > wear_fraction, W the relative excess (L − m)/m of cutting bins low-passed with
//    time constant `wear_time_constant_s` (a slow rise of the smoothed level).
// Each alarm is an event with the time it began (the first sample of the violation).
#pragma once

#include <cstdint>
#include <deque>
#include <string>
#include <utility>
#include <vector>

namespace cutdyn {

struct BandOptions {
  double bin_s = 0.01;             // width of a band bin, > 0
  double smoothing_s = 0.01;       // time constant of the level L, > 0
  double k_sigma = 3.0;            // half-width k·s, >= 0
  double relative_margin = 0.10;   // plus rel·m, >= 0
  double absolute_margin_n = 0.0;  // plus abs, >= 0
  double peak_margin = 0.05;       // plus this·max(m), the least width, >= 0
  double cutting_fraction = 0.2;   // bins with m >= this·max(m) are cutting, in (0, 1)
  // Each bin takes the widest limits within ±this of cycle time (and is cutting only if all
  // those bins are), so that the band holds wherever the tooth pattern falls: the spindle
  // phase at cycle start is free. At least one spindle revolution (60/rpm), >= 0.
  double phase_tolerance_s = 0.1;
  // Moving average of |F| over this window before the low-pass (0: none); set it to the tooth
  // period 60/(z·rpm) to remove the tooth pattern from the level, >= 0.
  double average_s = 0.0;

  std::vector<std::string> validate() const;

  /// The settings for a milling cut at `rpm` with `teeth` teeth (docs/models/monitor.md §5):
  /// the level averaged over the tooth period T = 60/(teeth·rpm) (the tooth pattern removed,
  /// whatever the spindle phase), smoothed with τ = 0.12·T (3 ms at 600 rpm and 4 teeth: a
  /// broken tooth or an overload is caught within one tooth period), the phase tolerance one
  /// spindle revolution 60/rpm (tooth-to-tooth runout repeats once a revolution); the rest
  /// as default. Throws InvalidInput unless rpm > 0 and teeth >= 1.
  static BandOptions for_milling(double rpm, int teeth);
};

/// A taught band of one axis.
struct ForceBand {
  BandOptions options;
  double cycle_s = 0.0;  // number of bins × bin_s
  std::vector<double> mean_n, sigma_n, upper_n, lower_n;
  std::vector<std::uint8_t> cutting;
  int runs = 0;

  std::size_t bin(double cycle_time_s) const;  // clamped to the last bin
  std::vector<std::string> validate() const;
};

/// First-order low-pass of |F|, exact for any step: L += (1 − exp(−Δt/τ))·(|F| − L); the first
/// sample sets L = |F|.
/// With `average_s` > 0, |F| is first averaged over the samples of the last `average_s`
/// (a moving average: over one tooth period it removes the tooth pattern, so the level no
/// longer depends on the spindle phase).
class LoadSmoother {
 public:
  explicit LoadSmoother(double time_constant_s, double average_s = 0.0)
      : tau_(time_constant_s), average_s_(average_s) {}
  double update(double time_s, double force_n);
  double level() const { return level_; }

 private:
  double tau_, average_s_, level_ = 0.0, last_time_ = 0.0, last_dt_ = -1.0, gain_ = 1.0;
  bool started_ = false;
  std::deque<std::pair<double, double>> window_;  // (t, |F|) of the moving average
  double window_sum_ = 0.0;
};

/// One reference run of one axis: times (increasing) and estimated forces.
struct ForceRun {
  std::vector<double> time_s, force_n;
};

/// Teach-in from one or more reference runs. Throws InvalidInput for invalid options, no run,
/// or a run with fewer than 2 samples or times that do not increase.
ForceBand teach_band(const std::vector<ForceRun>& runs, const BandOptions& options = {});

enum class AlarmKind { kOverload, kBreakage, kWear };
const char* to_string(AlarmKind kind);

struct AlarmOptions {
  double persist_s = 0.005;           // a violation must last this long, >= 0
  double wear_fraction = 0.15;        // relative rise of the level that means wear, > 0
  double wear_time_constant_s = 0.5;  // > 0

  std::vector<std::string> validate() const;
};

struct AlarmEvent {
  AlarmKind kind = AlarmKind::kOverload;
  double time_s = 0.0;      // when the violation began
  double detected_s = 0.0;  // when it was confirmed (time_s + persist, or the wear crossing)
  double level_n = 0.0;     // L (wear: the smoothed relative excess W) when confirmed
  double limit_n = 0.0;     // the limit crossed (wear: wear_fraction)
};

/// Bit flags of the alarms active at a sample.
enum AlarmFlags : unsigned {
  kAlarmNone = 0,
  kAlarmOverload = 1,
  kAlarmBreakage = 2,
  kAlarmWear = 4
};
/// "", "overload", "breakage", "wear", or several joined by '+'.
std::string alarm_text(unsigned flags);

struct AlarmSample {
  double level_n = 0.0;  // L
  double upper_n = 0.0, lower_n = 0.0;
  double wear = 0.0;  // W
  unsigned active = kAlarmNone;
  bool event = false;  // an event was confirmed at this sample: see last_event()
};

/// The alarm monitor of one axis.
class AlarmMonitor {
 public:
  /// Throws InvalidInput for an invalid band or options.
  AlarmMonitor(ForceBand band, const AlarmOptions& options = {});
  AlarmSample update(double time_s, double force_n);
  const AlarmEvent& last_event() const { return last_event_; }
  const std::vector<AlarmEvent>& events() const { return events_; }
  const ForceBand& band() const { return band_; }

 private:
  struct Pending {
    bool violating = false, active = false;
    double since = 0.0;
  };
  bool track(Pending& p, bool violating, double time_s);
  void confirm(AlarmKind kind, double since, double time_s, double level, double limit);

  ForceBand band_;
  AlarmOptions options_;
  LoadSmoother smoother_;
  double start_ = 0.0, wear_ = 0.0, last_time_ = 0.0;
  bool started_ = false, wear_active_ = false;
  Pending overload_, breakage_;
  AlarmEvent last_event_;
  std::vector<AlarmEvent> events_;
};

}  // namespace cutdyn
