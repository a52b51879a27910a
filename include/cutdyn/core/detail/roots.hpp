// Scalar root finding on a bracket, and scalar minimisation on an interval.
#pragma once

#include <functional>
#include <optional>

namespace cutdyn {

struct RootResult {
  double x = 0.0;
  double fx = 0.0;
  int evaluations = 0;
  bool converged = false;
};

/// Brent's method for f(x) = 0 on [a, b] with f(a)·f(b) <= 0. Returns std::nullopt when
/// the bracket does not change sign. Stops when the bracket is below
/// `x_tol + 4·eps·|x|` or after `max_evaluations`.
std::optional<RootResult> brent_root(const std::function<double(double)>& f, double a, double b,
                                     double x_tol, int max_evaluations = 200);

/// The same with f(a) and f(b) already known (not evaluated again, not counted).
std::optional<RootResult> brent_root(const std::function<double(double)>& f, double a, double fa,
                                     double b, double fb, double x_tol, int max_evaluations = 200);

struct MinimumResult {
  double x = 0.0;
  double fx = 0.0;
  int evaluations = 0;
  bool converged = false;
};

/// Brent's method (golden sections with parabolic steps) for a local minimum of f on
/// [a, b], a < b. Stops when x is known to within `x_tol + 2·sqrt(eps)·|x|` or after
/// `max_evaluations`. A unimodal f on [a, b] gives its minimum.
MinimumResult brent_minimum(const std::function<double(double)>& f, double a, double b,
                            double x_tol, int max_evaluations = 200);

}  // namespace cutdyn
