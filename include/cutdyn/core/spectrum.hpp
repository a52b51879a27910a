// The amplitude spectrum of a sampled signal: what a trace's chatter frequency is read from.
#pragma once

#include <vector>

namespace cutdyn {

/// Single-sided amplitude spectrum: `amplitude[k]` at `frequency_hz[k]` = k/(N·dt), k = 0 …
/// N/2, in the signal's unit, Hann-windowed and corrected for the window's coherent gain, so
/// that a sine of amplitude A on a bin's frequency reads A there (the mean reads as itself at
/// 0 Hz).
struct Spectrum {
  std::vector<double> frequency_hz, amplitude;
};

/// The spectrum of `signal`, sampled every `dt` seconds. Throws InvalidInput for fewer than 4
/// samples, a step that is not positive and finite, or a sample that is not finite.
Spectrum amplitude_spectrum(const std::vector<double>& signal, double dt);

}  // namespace cutdyn
