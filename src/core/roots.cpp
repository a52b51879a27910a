#include "cutdyn/core/detail/roots.hpp"

#include <cmath>
#include <limits>
#include <utility>

namespace cutdyn {

// [Brent1973], "Algorithms for Minimization without Derivatives", ch. 4 (zero).
std::optional<RootResult> brent_root(const std::function<double(double)>& f, double a, double b,
                                     double x_tol, int max_evaluations) {
  const double fa = f(a);
  const double fb = f(b);
  auto result = brent_root(f, a, fa, b, fb, x_tol, max_evaluations - 2);
  if (result) result->evaluations += 2;
  return result;
}

std::optional<RootResult> brent_root(const std::function<double(double)>& f, double a, double fa,
                                     double b, double fb, double x_tol, int max_evaluations) {
  int evaluations = 0;
  if (fa == 0.0) return RootResult{a, fa, evaluations, true};
  if (fb == 0.0) return RootResult{b, fb, evaluations, true};
  if ((fa > 0.0) == (fb > 0.0)) return std::nullopt;
  const double eps = std::numeric_limits<double>::epsilon();
  double c = a, fc = fa, d = b - a, e = d;
  while (evaluations < max_evaluations) {
    if ((fb > 0.0) == (fc > 0.0)) {
      c = a;
      fc = fa;
      d = e = b - a;
    }
    if (std::abs(fc) < std::abs(fb)) {
      a = b;
      b = c;
      c = a;
      fa = fb;
      fb = fc;
      fc = fa;
    }
    const double tol = 2.0 * eps * std::abs(b) + 0.5 * x_tol;
    const double m = 0.5 * (c - b);
    if (std::abs(m) <= tol || fb == 0.0) return RootResult{b, fb, evaluations, true};
    if (std::abs(e) >= tol && std::abs(fa) > std::abs(fb)) {
      double p, q, r;
      const double s = fb / fa;
      if (a == c) {
        p = 2.0 * m * s;
        q = 1.0 - s;
      } else {
        q = fa / fc;
        r = fb / fc;
        p = s * (2.0 * m * q * (q - r) - (b - a) * (r - 1.0));
        q = (q - 1.0) * (r - 1.0) * (s - 1.0);
      }
      if (p > 0.0) q = -q;
      p = std::abs(p);
      if (2.0 * p < std::min(3.0 * m * q - std::abs(tol * q), std::abs(e * q))) {
        e = d;
        d = p / q;
      } else {
        d = m;
        e = m;
      }
    } else {
      d = m;
      e = m;
    }
    a = b;
    fa = fb;
    b += std::abs(d) > tol ? d : (m > 0.0 ? tol : -tol);
    fb = f(b);
    ++evaluations;
  }
  return RootResult{b, fb, evaluations, false};
}

// [Brent1973, ch. 5] (localmin).
MinimumResult brent_minimum(const std::function<double(double)>& f, double a, double b,
                            double x_tol, int max_evaluations) {
  const double golden = 0.5 * (3.0 - std::sqrt(5.0));
  const double sqrt_eps = std::sqrt(std::numeric_limits<double>::epsilon());
  double x = a + golden * (b - a), w = x, v = x;
  double fx = f(x), fw = fx, fv = fx;
  double d = 0.0, e = 0.0;
  int evaluations = 1;
  while (evaluations < max_evaluations) {
    const double mid = 0.5 * (a + b);
    const double tol = sqrt_eps * std::abs(x) + x_tol / 3.0;
    const double tol2 = 2.0 * tol;
    if (std::abs(x - mid) <= tol2 - 0.5 * (b - a)) return {x, fx, evaluations, true};
    bool parabolic = false;
    if (std::abs(e) > tol) {
      // Parabola through (v, fv), (w, fw), (x, fx).
      double r = (x - w) * (fx - fv);
      double q = (x - v) * (fx - fw);
      double p = (x - v) * q - (x - w) * r;
      q = 2.0 * (q - r);
      if (q > 0.0) p = -p;
      q = std::abs(q);
      const double e_prev = e;
      if (std::abs(p) < std::abs(0.5 * q * e_prev) && p > q * (a - x) && p < q * (b - x)) {
        e = d;
        d = p / q;
        const double u = x + d;
        if (u - a < tol2 || b - u < tol2) d = x < mid ? tol : -tol;
        parabolic = true;
      }
    }
    if (!parabolic) {
      e = (x < mid ? b : a) - x;
      d = golden * e;
    }
    const double u = x + (std::abs(d) >= tol ? d : (d > 0.0 ? tol : -tol));
    const double fu = f(u);
    ++evaluations;
    if (fu <= fx) {
      (u < x ? b : a) = x;
      v = w;
      fv = fw;
      w = x;
      fw = fx;
      x = u;
      fx = fu;
    } else {
      (u < x ? a : b) = u;
      if (fu <= fw || w == x) {
        v = w;
        fv = fw;
        w = u;
        fw = fu;
      } else if (fu <= fv || v == x || v == w) {
        v = u;
        fv = fu;
      }
    }
  }
  return {x, fx, evaluations, false};
}

}  // namespace cutdyn
