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
  if (!coherence.empty() && coherence.size() != frequency_hz.size()) {
    v.add("coherence: " + std::to_string(coherence.size()) + " values for " +
          std::to_string(frequency_hz.size()) + " frequencies (one per frequency, or none)");
    return v.problems();
  }
  for (std::size_t i = 0; i < coherence.size(); ++i) {
    v.require(coherence[i] >= 0.0 && coherence[i] <= 1.0, "coherence[" + std::to_string(i) + "]",
              coherence[i], "", "must be 0 to 1 (the ordinary coherence γ²)");
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
  // The interval [f(j−1), f(j)] holding f: guessed from f's place in the band, which is exact on
  // the evenly spaced tables analysers write, then confirmed or corrected by a few steps, and
  // by bisection when the spacing is too uneven for that (a stability scan asks for G at
  // hundreds of frequencies per speed: the guess halves its time on a 3000-point table).
  const std::size_t n = frequency_hz.size();
  const double place = (f_hz - frequency_hz.front()) / (frequency_hz.back() - frequency_hz.front());
  std::size_t j = std::clamp<std::size_t>(
      static_cast<std::size_t>(place * static_cast<double>(n - 1)) + 1, 1, n - 1);
  constexpr int kSteps = 4;
  int steps = 0;
  for (; steps < kSteps && j > 1 && frequency_hz[j - 1] > f_hz; ++steps) --j;
  for (; steps < kSteps && j < n - 1 && frequency_hz[j] < f_hz; ++steps) ++j;
  if (frequency_hz[j - 1] > f_hz || (frequency_hz[j] < f_hz && j < n - 1)) {
    const auto hi = std::upper_bound(frequency_hz.begin(), frequency_hz.end(), f_hz);
    j = std::clamp<std::size_t>(static_cast<std::size_t>(hi - frequency_hz.begin()), 1, n - 1);
  }
  const double f0 = frequency_hz[j - 1], f1 = frequency_hz[j];
  const double t = (f_hz - f0) / (f1 - f0);
  return receptance_m_per_n[j - 1] + t * (receptance_m_per_n[j] - receptance_m_per_n[j - 1]);
}

MeasuredFrf add_frf(const MeasuredFrf& a, const MeasuredFrf& b) {
  MeasuredFrf sum;
  for (std::size_t i = 0; i < a.frequency_hz.size(); ++i) {
    const double f = a.frequency_hz[i];
    if (!b.covers(f)) continue;
    sum.frequency_hz.push_back(f);
    sum.receptance_m_per_n.push_back(a.receptance_m_per_n[i] + b.at(f));
  }
  if (sum.frequency_hz.size() < 3) {
    throw InvalidInput(
        {"the two FRFs' bands (" + format_value(a.min_hz()) + "–" + format_value(a.max_hz()) +
         " Hz and " + format_value(b.min_hz()) + "–" + format_value(b.max_hz()) +
         " Hz) share fewer than 3 points: they cannot "
         "be added"},
        "frf");
  }
  return sum;
}

Eigen::MatrixXcd MeasuredStructure::at(const std::vector<Direction>& directions,
                                       double omega_rad_s) const {
  Eigen::MatrixXcd g;
  at(directions, omega_rad_s, g);
  return g;
}

void MeasuredStructure::at(const std::vector<Direction>& directions, double omega_rad_s,
                           Eigen::MatrixXcd& g) const {
  const auto n = static_cast<Eigen::Index>(directions.size());
  g.resize(n, n);
  const double f = std::abs(omega_rad_s) / (2.0 * std::numbers::pi);
  const auto value = [&](const MeasuredFrf* table) {
    if (table == nullptr || !table->covers(f)) return std::complex<double>{};
    const std::complex<double> v = table->at(f);
    return omega_rad_s < 0.0 ? std::conj(v) : v;  // G(−ω) = conj G(ω): a real structure
  };
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < n; ++j) {
      const Direction di = directions[static_cast<std::size_t>(i)];
      const Direction dj = directions[static_cast<std::size_t>(j)];
      g(i, j) = di == dj ? value(direct(di)) : value(ptr(xy));
    }
  }
}

Eigen::MatrixXcd combined_receptance(const ModalModel& given, const MeasuredStructure& measured,
                                     const std::vector<Direction>& directions, double omega_rad_s) {
  Eigen::MatrixXcd g;
  combined_receptance(given, measured, directions, omega_rad_s, g);
  return g;
}

void combined_receptance(const ModalModel& given, const MeasuredStructure& measured,
                         const std::vector<Direction>& directions, double omega_rad_s,
                         Eigen::MatrixXcd& g) {
  measured.at(directions, omega_rad_s, g);
  if (given.modes.empty()) return;
  for (std::size_t i = 0; i < directions.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    g(k, k) += frf(given, directions[i], omega_rad_s);
  }
}

ModalModel with_fitted_modes(const ModalModel& given,
                             const std::optional<MeasuredStructure>& measured) {
  ModalModel all = given;
  if (measured)
    all.modes.insert(all.modes.end(), measured->fitted.modes.begin(), measured->fitted.modes.end());
  return all;
}

double MeasuredStructure::max_hz() const {
  double top = 0.0;
  for (const auto* t : {ptr(xx), ptr(yy), ptr(xy)})
    if (t != nullptr) top = std::max(top, t->max_hz());
  return top;
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
