#include "cutdyn/modal/measured_frf.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>

#include "cutdyn/core/error.hpp"

namespace cutdyn {

std::vector<std::string> MeasuredFrf::validate() const {
  Validator v;
  if (frequency_hz.size() != receptance_m_per_n.size()) {
    v.add("frequency_hz and receptance_m_per_n: must have the same length (" +
          std::to_string(frequency_hz.size()) + " and " +
          std::to_string(receptance_m_per_n.size()) + ")");
    return v.problems();
  }
  if (frequency_hz.size() < 3) {
    v.add("frequency_hz: at least 3 points are required (" + std::to_string(frequency_hz.size()) +
          " given)");
  }
  for (std::size_t i = 0; i < frequency_hz.size(); ++i) {
    const std::string at = "frequency_hz[" + std::to_string(i) + "]";
    const double f = frequency_hz[i];
    v.require(std::isfinite(f) && f >= 0.0, at, f, "Hz", "must be finite and at least 0");
    if (i > 0) {
      v.require(
          f > frequency_hz[i - 1], at, f, "Hz",
          "must be greater than the one before (" + format_value(frequency_hz[i - 1]) + " Hz)");
    }
    const std::complex<double> g = receptance_m_per_n[i];
    if (!std::isfinite(g.real()) || !std::isfinite(g.imag())) {
      v.add("receptance_m_per_n[" + std::to_string(i) + "] at " + format_value(f) +
            " Hz: must be finite");
    }
  }
  return v.problems();
}

std::complex<double> MeasuredFrf::at(double f_hz) const {
  assert(covers(f_hz) && frequency_hz.size() >= 2);
  const auto hi = std::upper_bound(frequency_hz.begin(), frequency_hz.end(), f_hz);
  std::size_t j = static_cast<std::size_t>(hi - frequency_hz.begin());
  j = std::clamp<std::size_t>(j, 1, frequency_hz.size() - 1);
  const double f0 = frequency_hz[j - 1], f1 = frequency_hz[j];
  const double t = (f_hz - f0) / (f1 - f0);
  return receptance_m_per_n[j - 1] + t * (receptance_m_per_n[j] - receptance_m_per_n[j - 1]);
}

MeasuredFrf sample_frf(const ModalModel& model, Direction direction,
                       const std::vector<double>& frequency_hz) {
  MeasuredFrf out;
  out.frequency_hz = frequency_hz;
  out.receptance_m_per_n.reserve(frequency_hz.size());
  for (double f : frequency_hz) {
    out.receptance_m_per_n.push_back(frf(model, direction, 2.0 * std::numbers::pi * f));
  }
  return out;
}

std::vector<double> linear_frequencies(double lo_hz, double hi_hz, int n) {
  assert(n >= 2);
  std::vector<double> f(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) f[i] = lo_hz + (hi_hz - lo_hz) * i / (n - 1);
  f.back() = hi_hz;
  return f;
}

}  // namespace cutdyn
