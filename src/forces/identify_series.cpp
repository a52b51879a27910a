// Mean forces of a test cut from its force record, over whole revolutions;
// docs/models/identification.md, "Mean forces from a force record".
#include <algorithm>
#include <cmath>

#include "cutdyn/core/error.hpp"
#include "cutdyn/forces/identify.hpp"

namespace cutdyn {
namespace {

std::vector<std::string> series_problems(const ForceSeries& s) {
  Validator v;
  v.require_positive("rpm", s.rpm, "rpm");
  v.require_positive("feed_per_tooth_m", s.feed_per_tooth_m, "m");
  v.require_positive("depth_m", s.depth_m, "m");
  const std::size_t n = s.time_s.size();
  const std::size_t before = v.problems().size();
  if (n < 2) v.add("time_s: " + std::to_string(n) + " sample(s): need at least 2");
  const auto same_length = [&](const std::vector<double>& f, const char* name) {
    if (f.size() != n)
      v.add(std::string(name) + ": " + std::to_string(f.size()) + " values for " +
            std::to_string(n) + " times");
  };
  same_length(s.fx_n, "fx_n");
  same_length(s.fy_n, "fy_n");
  if (!s.fz_n.empty()) same_length(s.fz_n, "fz_n");
  if (v.problems().size() > before) return v.problems();  // lengths: nothing more to check
  const auto finite = [&](const std::vector<double>& f, const char* name, const char* unit) {
    for (std::size_t i = 0; i < f.size(); ++i)
      if (!std::isfinite(f[i])) {
        v.require(false, std::string(name) + "[" + std::to_string(i) + "]", f[i], unit, "");
        return;  // the first one is enough
      }
  };
  finite(s.time_s, "time_s", "s");
  finite(s.fx_n, "fx_n", "N");
  finite(s.fy_n, "fy_n", "N");
  finite(s.fz_n, "fz_n", "N");
  const bool values_ok = v.problems().size() == before;
  for (std::size_t i = 1; values_ok && i < n; ++i)
    if (!(s.time_s[i] > s.time_s[i - 1])) {
      v.add("time_s[" + std::to_string(i) + "] = " + format_value(s.time_s[i]) +
            " s: must be greater than time_s[" + std::to_string(i - 1) +
            "] = " + format_value(s.time_s[i - 1]) + " s");
      break;
    }
  if (v.problems().size() == before && s.rpm > 0.0) {
    const double period = 60.0 / s.rpm, span = s.time_s.back() - s.time_s.front();
    if (span < period * (1.0 - 1e-9))
      v.add("time_s spans " + format_value(span) + " s, less than one revolution (" +
            format_value(period) + " s at " + format_value(s.rpm) + " rpm)");
    // The count of whole revolutions is an int (MeanForce::revolutions); no record of a cut
    // comes near 1e9 of them (a week at 100000 rpm): the speed or the time unit is wrong.
    if (!(span <= 1e9 * period))
      v.add("time_s spans " + format_value(span) + " s, more than 1e9 revolutions (" +
            format_value(period) + " s at " + format_value(s.rpm) +
            " rpm): is the speed or the time unit wrong?");
  }
  return v.problems();
}

// ∫ f dt over [from, t_end] by the trapezoidal rule, f linear between the samples (`from`
// inside the record).
double integral_from(const std::vector<double>& t, const std::vector<double>& f, double from) {
  std::size_t i = t.size() - 1;
  double sum = 0.0;
  while (i > 0 && t[i - 1] >= from) {
    sum += 0.5 * (t[i] - t[i - 1]) * (f[i] + f[i - 1]);
    --i;
  }
  if (i > 0 && t[i] > from) {  // the part of the step [t[i−1], t[i]] after `from`
    const double u = (from - t[i - 1]) / (t[i] - t[i - 1]);
    const double f_from = f[i - 1] + u * (f[i] - f[i - 1]);
    sum += 0.5 * (t[i] - from) * (f_from + f[i]);
  }
  return sum;
}

}  // namespace

MeanForce mean_over_revolutions(const ForceSeries& series) {
  Validator v;
  v.merge(series_problems(series));
  v.throw_if_any(series.label.empty() ? "force record" : series.label);
  const double period = 60.0 / series.rpm;
  const double span = series.time_s.back() - series.time_s.front();
  // Whole revolutions, a rounding short of one counted (a record of exactly N periods).
  const int revolutions = static_cast<int>(std::floor(span / period * (1.0 + 1e-9)));
  const double length = revolutions * period;
  const double from = std::max(series.time_s.front(), series.time_s.back() - length);
  MeanForce m;
  m.feed_per_tooth_m = series.feed_per_tooth_m;
  m.depth_m = series.depth_m;
  m.label = series.label;
  m.revolutions = revolutions;
  m.fx_n = integral_from(series.time_s, series.fx_n, from) / length;
  m.fy_n = integral_from(series.time_s, series.fy_n, from) / length;
  if (!series.fz_n.empty()) m.fz_n = integral_from(series.time_s, series.fz_n, from) / length;
  return m;
}

std::vector<MeanForce> mean_forces(const std::vector<ForceSeries>& series) {
  std::vector<std::string> problems;
  std::vector<MeanForce> out;
  for (std::size_t i = 0; i < series.size(); ++i) {
    const std::string name =
        series[i].label.empty() ? "series[" + std::to_string(i) + "]" : series[i].label;
    try {
      out.push_back(mean_over_revolutions(series[i]));
    } catch (const InvalidInput& e) {
      for (const std::string& p : e.problems()) problems.push_back(name + ": " + p);
    }
  }
  if (!problems.empty()) throw InvalidInput(problems, "force records");
  return out;
}

}  // namespace cutdyn
