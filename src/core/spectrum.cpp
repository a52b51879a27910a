#include "cutdyn/core/spectrum.hpp"

#include <cmath>
#include <complex>
#include <string>
#include <unsupported/Eigen/FFT>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn {

Spectrum amplitude_spectrum(const std::vector<double>& signal, double dt) {
  Validator v;
  v.require(signal.size() >= 4, "samples", static_cast<double>(signal.size()), "",
            "must be at least 4");
  v.require(std::isfinite(dt) && dt > 0.0, "dt", dt, "s", "must be positive and finite");
  for (std::size_t i = 0; i < signal.size(); ++i)
    if (!std::isfinite(signal[i])) {
      v.add("signal[" + std::to_string(i) + "]: must be finite");
      break;
    }
  v.throw_if_any("spectrum");
  const std::size_t n = signal.size();
  // Hann window; its coherent gain (the mean of the window, 1/2) is divided out.
  std::vector<double> windowed(n);
  double gain = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double w =
        0.5 - 0.5 * std::cos(units::kTwoPi * static_cast<double>(i) / static_cast<double>(n));
    windowed[i] = w * signal[i];
    gain += w;
  }
  std::vector<std::complex<double>> bins;
  Eigen::FFT<double> fft;
  fft.fwd(bins, windowed);
  Spectrum s;
  const std::size_t half = n / 2;
  s.frequency_hz.resize(half + 1);
  s.amplitude.resize(half + 1);
  for (std::size_t k = 0; k <= half; ++k) {
    s.frequency_hz[k] = static_cast<double>(k) / (static_cast<double>(n) * dt);
    // Both sides of a real signal add up, but for 0 and (even n) the Nyquist bin.
    const double sides = (k == 0 || 2 * k == n) ? 1.0 : 2.0;
    s.amplitude[k] = sides * std::abs(bins[k]) / gain;
  }
  return s;
}

}  // namespace cutdyn
