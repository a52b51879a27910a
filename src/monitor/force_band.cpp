#include "cutdyn/monitor/force_band.hpp"

#include <algorithm>
#include <cmath>

#include "cutdyn/core/error.hpp"

namespace cutdyn {

std::vector<std::string> BandOptions::validate() const {
  Validator v("band");
  v.require_positive("bin_s", bin_s, "s");
  v.require_positive("smoothing_s", smoothing_s, "s");
  v.require(k_sigma >= 0.0, "k_sigma", k_sigma, "", "must be >= 0");
  v.require(relative_margin >= 0.0, "relative_margin", relative_margin, "", "must be >= 0");
  v.require(absolute_margin_n >= 0.0, "absolute_margin_n", absolute_margin_n, "N", "must be >= 0");
  v.require(peak_margin >= 0.0, "peak_margin", peak_margin, "", "must be >= 0");
  v.require_in_open("cutting_fraction", cutting_fraction, "", 0.0, 1.0);
  v.require(average_s >= 0.0 && std::isfinite(average_s), "average_s", average_s, "s",
            "must be a finite number >= 0");
  v.require(phase_tolerance_s >= 0.0 && std::isfinite(phase_tolerance_s), "phase_tolerance_s",
            phase_tolerance_s, "s", "must be a finite number >= 0");
  return v.problems();
}

BandOptions BandOptions::for_milling(double rpm, int teeth) {
  Validator v("band");
  v.require_positive("rpm", rpm, "rpm");
  v.require(teeth >= 1, "teeth", teeth, "", "must be at least 1");
  v.throw_if_any();
  BandOptions o;
  const double revolution_s = 60.0 / rpm;
  o.average_s = revolution_s / teeth;
  o.smoothing_s = 0.12 * o.average_s;
  o.phase_tolerance_s = revolution_s;
  return o;
}

std::size_t ForceBand::bin(double cycle_time_s) const {
  if (!(cycle_time_s > 0.0)) return 0;
  const double b = cycle_time_s / options.bin_s;
  const std::size_t last = mean_n.size() - 1;
  // Clamped before the conversion: a quotient beyond size_t (a cycle time far past the band)
  // would make it undefined.
  return b < static_cast<double>(last) ? static_cast<std::size_t>(b) : last;
}

std::vector<std::string> ForceBand::validate() const {
  Validator v;
  v.merge(options.validate());
  const std::size_t n = mean_n.size();
  if (n == 0) v.add("band: no bins");
  if (sigma_n.size() != n || upper_n.size() != n || lower_n.size() != n || cutting.size() != n)
    v.add("band: mean_n, sigma_n, upper_n, lower_n and cutting must have the same length");
  for (std::size_t i = 0; i < std::min({n, upper_n.size(), lower_n.size()}); ++i) {
    if (!std::isfinite(mean_n[i]) || !std::isfinite(upper_n[i]) || !std::isfinite(lower_n[i]) ||
        lower_n[i] > upper_n[i]) {
      v.add("band: bin " + std::to_string(i) + ": limits must be finite with lower <= upper");
      break;
    }
  }
  return v.problems();
}

double LoadSmoother::update(double t, double f) {
  double x = std::abs(f);
  if (average_s_ > 0.0) {
    window_.emplace_back(t, x);
    window_sum_ += x;
    while (window_.front().first <= t - average_s_) {
      window_sum_ -= window_.front().second;
      window_.pop_front();
    }
    x = window_sum_ / static_cast<double>(window_.size());
  }
  if (!started_) {
    started_ = true;
    level_ = x;
  } else {
    const double dt = t - last_time_;
    if (std::abs(dt - last_dt_) > 1e-6 * last_dt_) {
      last_dt_ = dt;
      gain_ = -std::expm1(-dt / tau_);
    }
    level_ += gain_ * (x - level_);
  }
  last_time_ = t;
  return level_;
}

ForceBand teach_band(const std::vector<ForceRun>& runs, const BandOptions& o) {
  Validator v;
  v.merge(o.validate());
  if (runs.empty()) v.add("teach-in: no reference run");
  double duration = 0.0;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const ForceRun& run = runs[r];
    if (run.time_s.size() < 2 || run.force_n.size() != run.time_s.size()) {
      v.add("teach-in: run " + std::to_string(r + 1) + " needs at least 2 samples");
      continue;
    }
    for (std::size_t i = 1; i < run.time_s.size(); ++i)
      if (!(run.time_s[i] > run.time_s[i - 1])) {
        v.add("teach-in: run " + std::to_string(r + 1) + ": time must increase (sample " +
              std::to_string(i + 1) + ")");
        break;
      }
    duration = std::max(duration, run.time_s.back() - run.time_s.front());
  }
  v.throw_if_any();

  ForceBand band;
  band.options = o;
  band.runs = static_cast<int>(runs.size());
  const auto bins = static_cast<std::size_t>(std::floor(duration / o.bin_s)) + 1;
  band.cycle_s = static_cast<double>(bins) * o.bin_s;
  // Each bin's mean and sum of squared deviations by Welford's update: a level of 2000 N that
  // scatters by 1 N has Σx² − n·m² cancel to 1e-6 of its size, which would leave σ with the
  // relative error ε·(m/σ)² ≈ 1e-9 and σ of bins within rounding of their mean at 0.
  std::vector<double> mean(bins, 0.0), squares(bins, 0.0), count(bins, 0.0);
  for (const ForceRun& run : runs) {
    LoadSmoother smoother(o.smoothing_s, o.average_s);
    for (std::size_t i = 0; i < run.time_s.size(); ++i) {
      const double level = smoother.update(run.time_s[i], run.force_n[i]);
      const std::size_t b = std::min(
          bins - 1, static_cast<std::size_t>((run.time_s[i] - run.time_s.front()) / o.bin_s));
      count[b] += 1.0;
      const double delta = level - mean[b];
      mean[b] += delta / count[b];
      squares[b] += delta * (level - mean[b]);
    }
  }
  band.mean_n.resize(bins);
  band.sigma_n.resize(bins);
  // A bin no sample fell into (samples sparser than bins) takes its left neighbour.
  for (std::size_t b = 0; b < bins; ++b) {
    if (count[b] == 0.0) {
      band.mean_n[b] = b > 0 ? band.mean_n[b - 1] : 0.0;
      band.sigma_n[b] = b > 0 ? band.sigma_n[b - 1] : 0.0;
      continue;
    }
    band.mean_n[b] = mean[b];
    band.sigma_n[b] = count[b] > 1.0 ? std::sqrt(squares[b] / (count[b] - 1.0)) : 0.0;
  }
  const double peak = *std::max_element(band.mean_n.begin(), band.mean_n.end());
  for (std::size_t b = 0; b < bins; ++b) {
    const double m = band.mean_n[b];
    const double half = o.k_sigma * band.sigma_n[b] + o.relative_margin * m + o.absolute_margin_n +
                        o.peak_margin * peak;
    band.upper_n.push_back(m + half);
    band.lower_n.push_back(std::max(0.0, m - half));
    band.cutting.push_back(peak > 0.0 && m >= o.cutting_fraction * peak ? 1 : 0);
  }
  // Independent of where the force pattern falls in time (the spindle phase at cycle start,
  // docs/models/monitor.md §5): each bin takes the widest limits of the bins within
  // ±phase_tolerance_s, and is cutting only if all of them are.
  const auto reach = static_cast<std::size_t>(std::ceil(o.phase_tolerance_s / o.bin_s - 1e-9));
  if (reach > 0) {
    const std::vector<double> up = band.upper_n, low = band.lower_n;
    const std::vector<std::uint8_t> cut = band.cutting;
    for (std::size_t b = 0; b < bins; ++b) {
      const std::size_t first = b >= reach ? b - reach : 0, last = std::min(bins - 1, b + reach);
      for (std::size_t j = first; j <= last; ++j) {
        band.upper_n[b] = std::max(band.upper_n[b], up[j]);
        band.lower_n[b] = std::min(band.lower_n[b], low[j]);
        band.cutting[b] = band.cutting[b] && cut[j];
      }
    }
  }
  return band;
}

const char* to_string(AlarmKind kind) {
  switch (kind) {
    case AlarmKind::kOverload:
      return "overload";
    case AlarmKind::kBreakage:
      return "breakage";
    case AlarmKind::kWear:
      return "wear";
  }
  return "?";
}

std::string alarm_text(unsigned flags) {
  std::string text;
  const auto add = [&](unsigned bit, const char* name) {
    if (!(flags & bit)) return;
    if (!text.empty()) text += '+';
    text += name;
  };
  add(kAlarmOverload, "overload");
  add(kAlarmBreakage, "breakage");
  add(kAlarmWear, "wear");
  return text;
}

std::vector<std::string> AlarmOptions::validate() const {
  Validator v("alarm");
  v.require(persist_s >= 0.0, "persist_s", persist_s, "s", "must be >= 0");
  v.require_positive("wear_fraction", wear_fraction, "");
  v.require_positive("wear_time_constant_s", wear_time_constant_s, "s");
  return v.problems();
}

AlarmMonitor::AlarmMonitor(ForceBand band, const AlarmOptions& o)
    : band_(std::move(band)),
      options_(o),
      smoother_(band_.options.smoothing_s, band_.options.average_s) {
  Validator v;
  v.merge(band_.validate());
  v.merge(o.validate());
  v.throw_if_any();
}

bool AlarmMonitor::track(Pending& p, bool violating, double t) {
  if (!violating) {
    p.violating = p.active = false;
    return false;
  }
  if (!p.violating) {
    p.violating = true;
    p.since = t;
  }
  if (!p.active && t - p.since >= options_.persist_s - 1e-12) {
    p.active = true;
    return true;  // confirmed now
  }
  return false;
}

void AlarmMonitor::confirm(AlarmKind kind, double since, double t, double level, double limit) {
  last_event_ = {kind, since, t, level, limit};
  events_.push_back(last_event_);
}

AlarmSample AlarmMonitor::update(double t, double f) {
  if (!started_) {
    start_ = t;
    started_ = true;
  }
  const double dt = t - last_time_;
  last_time_ = t;
  AlarmSample s;
  s.level_n = smoother_.update(t, f);
  const double cycle = std::fmod(t - start_, band_.cycle_s);
  const std::size_t b = band_.bin(cycle);
  s.upper_n = band_.upper_n[b];
  s.lower_n = band_.lower_n[b];
  const bool cutting = band_.cutting[b] != 0;
  // Wear: the relative excess over the taught mean, low-passed, in cutting bins only.
  if (cutting && dt > 0.0) {
    const double excess = (s.level_n - band_.mean_n[b]) / band_.mean_n[b];
    wear_ += -std::expm1(-dt / options_.wear_time_constant_s) * (excess - wear_);
  }
  s.wear = wear_;
  if (track(overload_, s.level_n > s.upper_n, t)) {
    confirm(AlarmKind::kOverload, overload_.since, t, s.level_n, s.upper_n);
    s.event = true;
  }
  if (track(breakage_, cutting && s.level_n < s.lower_n, t)) {
    confirm(AlarmKind::kBreakage, breakage_.since, t, s.level_n, s.lower_n);
    s.event = true;
  }
  if (!wear_active_ && wear_ > options_.wear_fraction) {
    wear_active_ = true;
    confirm(AlarmKind::kWear, t, t, wear_, options_.wear_fraction);
    s.event = true;
  } else if (wear_active_ && wear_ < 0.5 * options_.wear_fraction) {
    wear_active_ = false;  // hysteresis: re-arms at half the threshold
  }
  if (overload_.active) s.active |= kAlarmOverload;
  if (breakage_.active) s.active |= kAlarmBreakage;
  if (wear_active_) s.active |= kAlarmWear;
  return s;
}

}  // namespace cutdyn
