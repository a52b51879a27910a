#include "cutdyn/simulate/growth_estimate.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

namespace cutdyn {

double index_slope(const std::vector<double>& y) {
  if (y.size() < 2) return 0.0;
  const auto n = static_cast<double>(y.size());
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    const auto x = static_cast<double>(i);
    sx += x;
    sy += y[i];
    sxx += x * x;
    sxy += x * y[i];
  }
  const double den = n * sxx - sx * sx;
  return den > 0.0 ? (n * sxy - sx * sy) / den : 0.0;
}

bool slope_settled(const std::vector<double>& log_amplitude) {
  if (log_amplitude.size() < 8) return false;
  const auto half = static_cast<std::ptrdiff_t>(log_amplitude.size() / 2);
  const double whole = index_slope(log_amplitude);
  const double early =
      index_slope(std::vector<double>(log_amplitude.begin(), log_amplitude.begin() + half));
  const double late =
      index_slope(std::vector<double>(log_amplitude.begin() + half, log_amplitude.end()));
  return (early > 0.0) == (whole > 0.0) && (late > 0.0) == (whole > 0.0);
}

namespace {

// Block Hankel matrix of samples[from + c + l] (column c, block row l).
Eigen::MatrixXd hankel(const std::vector<std::vector<double>>& samples, std::size_t from,
                       std::size_t blocks, std::size_t columns) {
  const std::size_t channels = samples[from].size();
  Eigen::MatrixXd h(static_cast<Eigen::Index>(blocks * channels),
                    static_cast<Eigen::Index>(columns));
  for (std::size_t c = 0; c < columns; ++c)
    for (std::size_t l = 0; l < blocks; ++l)
      for (std::size_t i = 0; i < channels; ++i)
        h(static_cast<Eigen::Index>(l * channels + i), static_cast<Eigen::Index>(c)) =
            samples[from + c + l][i];
  return h;
}

}  // namespace

std::optional<MultiplierEstimate> dominant_multiplier(
    const std::vector<std::vector<double>>& samples) {
  constexpr std::size_t kMaxSamples = 240;
  std::size_t first = samples.size() / 4;
  if (samples.size() - first > kMaxSamples) first = samples.size() - kMaxSamples;
  const std::size_t count = samples.size() - first;
  if (count < 12) return std::nullopt;
  const std::size_t channels = samples[first].size();
  if (channels == 0) return std::nullopt;
  for (std::size_t k = first; k < samples.size(); ++k)
    if (samples[k].size() != channels) return std::nullopt;

  // Fitted on the first three quarters of the samples; the last quarter is held out to test
  // the model's prediction (a model that fits noise or a response that is not a sum of
  // exponentials, e.g. one sampled out of step with a periodic excitation, fails it).
  const std::size_t fitted = count - count / 4;
  const std::size_t blocks = fitted / 2, columns = fitted - blocks;
  Eigen::MatrixXd h0 = hankel(samples, first, blocks, columns);
  Eigen::MatrixXd h1 = hankel(samples, first + 1, blocks, columns);
  const Eigen::MatrixXd held = hankel(samples, first + fitted - blocks + 1, blocks,
                                      count - fitted);  // the columns after h1's last
  const double scale = h0.cwiseAbs().maxCoeff();
  if (!(scale > 0.0) || !std::isfinite(scale)) return std::nullopt;
  h0 /= scale;
  h1 /= scale;

  const Eigen::BDCSVD<Eigen::MatrixXd> svd(h0, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& sigma = svd.singularValues();
  Eigen::Index rank = 0;
  while (rank < sigma.size() && sigma(rank) > 1e-8 * sigma(0)) ++rank;
  if (rank == 0 || 2 * static_cast<std::size_t>(rank) > columns) return std::nullopt;
  const Eigen::MatrixXd u = svd.matrixU().leftCols(rank);
  const Eigen::MatrixXd v = svd.matrixV().leftCols(rank);
  const Eigen::MatrixXd a = u.transpose() * h1 * v * sigma.head(rank).cwiseInverse().asDiagonal();
  // The model carries the last fitted column forward through the held-out samples.
  Eigen::VectorXd z = u.transpose() * h1.col(h1.cols() - 1);
  for (Eigen::Index c = 0; c < held.cols(); ++c) {
    z = a * z;
    const Eigen::VectorXd actual = held.col(c) / scale;
    if ((u * z - actual).norm() > 1e-4 * actual.norm()) return std::nullopt;
  }
  const Eigen::EigenSolver<Eigen::MatrixXd> eigen(a);
  if (eigen.info() != Eigen::Success) return std::nullopt;
  const Eigen::MatrixXcd& vectors = eigen.eigenvectors();
  // Each multiplier's share of the last sample (in the reduced coordinates): a multiplier of
  // rounding-level weight is not a component of the response.
  const Eigen::VectorXcd last = (u.transpose() * h1.col(h1.cols() - 1)).cast<std::complex<double>>();
  const Eigen::VectorXcd weight = vectors.colPivHouseholderQr().solve(last);
  std::vector<double> share(static_cast<std::size_t>(rank));
  double largest = 0.0;
  for (Eigen::Index i = 0; i < rank; ++i) {
    share[static_cast<std::size_t>(i)] = std::abs(weight(i)) * vectors.col(i).norm();
    largest = std::max(largest, share[static_cast<std::size_t>(i)]);
  }
  MultiplierEstimate out;
  out.components = static_cast<int>(rank);
  out.growth_per_period = -std::numeric_limits<double>::infinity();
  Eigen::Index top = -1;
  const auto significant = [&](Eigen::Index i) {
    return share[static_cast<std::size_t>(i)] > 1e-4 * largest &&
           std::abs(eigen.eigenvalues()(i)) > 0.0;
  };
  for (Eigen::Index i = 0; i < rank; ++i) {
    if (!significant(i)) continue;
    const double growth = std::log(std::abs(eigen.eigenvalues()(i)));
    if (growth > out.growth_per_period) {
      out.growth_per_period = growth;
      top = i;
    }
  }
  if (!std::isfinite(out.growth_per_period)) return std::nullopt;
  // Two components closer than the samples can resolve (about 1/count apart: a symmetric
  // structure's x and y modes give such pairs) are split by the pencil at random, and the
  // larger of the two is then biased up by up to that distance: no estimate (the slope, and
  // its own settledness, decide).
  const double resolution = 1.0 / static_cast<double>(count);
  const std::complex<double> largest_root = eigen.eigenvalues()(top);
  for (Eigen::Index i = 0; i < rank; ++i) {
    if (i == top || !significant(i)) continue;
    const std::complex<double> other = eigen.eigenvalues()(i);
    if (other == std::conj(largest_root)) continue;
    if (std::abs(other - largest_root) < resolution) return std::nullopt;
  }
  return out;
}

}  // namespace cutdyn
