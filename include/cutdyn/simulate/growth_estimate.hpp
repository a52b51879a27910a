// How fast the free (regenerative) response of a simulated cut grows or decays, from samples of
// it once per period: the dominant Floquet multiplier by a matrix pencil, not only the slope of
// its log-amplitude.
//
// Near a stability boundary the root that decides (growth of order 1e-3 per period) is often
// masked for hundreds of periods by a better-excited neighbour that decays 10× faster: the
// slope of ln(amplitude) over a 30-revolution run then has the wrong sign (measured: 16 of 326
// runs at 0.99× and 1.01× the critical depth). The samples of a linear periodic system are
// sums of c_i·μ_i^k; a block Hankel matrix of them has the rank of the components present, and
// its shift (the matrix pencil [Hua1990]) has the μ_i as eigenvalues, so a growing component is
// found while it is still ten times smaller than a decaying one.
#pragma once

#include <optional>
#include <vector>

namespace cutdyn {

struct MultiplierEstimate {
  double growth_per_period = 0.0;  // ln|μ| of the largest multiplier present in the samples
  int components = 0;              // multipliers found (rank of the Hankel matrix)
};

/// `samples[k]`: linear observations of the free response at period k (every sample the same
/// length; several channels and phases of the period help). Uses the samples from the first
/// quarter on (at most the last 240). Empty when the samples are not explained by a few
/// multipliers (the Hankel matrix is of more than half its possible rank, or the model predicts
/// the samples worse than 1e-6), or when another component lies within 1/N of the largest
/// (N samples used: closer than they resolve): then the caller falls back on the amplitude's
/// slope.
std::optional<MultiplierEstimate> dominant_multiplier(
    const std::vector<std::vector<double>>& samples);

/// Least-squares slope of y against its index (0 for fewer than two values).
double index_slope(const std::vector<double>& y);

/// A growth estimate from the log-amplitude is settled when the slopes over the two halves of
/// its window have the sign of the whole.
bool slope_settled(const std::vector<double>& log_amplitude);

}  // namespace cutdyn
