// The chatter frequency of a Floquet solution: which harmonic (θ + 2πk)/T of its multiplier
// e^(iθ) carries most of it (the full discretization's eigenvectors, sampled over a period).
#pragma once

#include <complex>
#include <vector>

namespace cutdyn::detail {

/// |(θ + 2π(k − kmax))/T| in Hz for the k in 0 … 2·kmax (kmax = steps/2) whose sum
/// |Σi values_i·e^(−i(θ + 2π(k − kmax))·t_i/T)| is largest (the first of equal ones): the
/// direct sum over every harmonic, O(samples·steps), for any sample times.
double dominant_frequency_hz(double theta, double period, const std::vector<double>& times,
                             const std::vector<std::complex<double>>& values, int steps);

/// The same for samples at t_i = −i·T/n (i = 0, 1, …): equal to dominant_frequency_hz with
/// those times and steps = n, from sums over the samples folded modulo n, taken from the
/// lowest frequency up until Parseval's identity shows that no harmonic left can be larger.
/// For even n, k = 0 and k = n have the same sum (the Nyquist alias): k = 0 is taken, where
/// the direct sum picks either by rounding.
double dominant_frequency_hz_uniform(double theta, double period, int n,
                                     const std::vector<std::complex<double>>& values);

}  // namespace cutdyn::detail
