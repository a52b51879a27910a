// First-order full discretization of the periodic delayed system (delayed_system.hpp)
// [Ding2010]; docs/models/turning.md §5.
//
// One period T is cut into steps t0 = 0 < t1 < ... < tn = T, with nodes on every jump of
// H(t). On step j (length hj) the structure is integrated exactly and the cutting term is
// taken with H at its mean over the step, H̄j, and the displacements y(t), y(t − τ) linear
// between the step's ends:
//     x(j+1) = Φ0j·x(j) + w·[W0j·E·H̄j·(ŷ(j) − y(j)) + W1j·E·H̄j·(ŷ(j+1) − y(j+1))],
//     Φ0j = e^(A0·hj),  W1j = (1/hj)∫0^hj e^(A0(hj−s))·s ds,  W0j = ∫0^hj e^(A0 s) ds − W1j,
// with ŷ(j) = y(tj − τ) interpolated linearly between the two nodes around it (order 1).
// Order 2 (docs/models/milling-stability.md, "Second-order interpolation") takes the
// difference ŷ − y quadratic through the nodes j − 1, j, j + 1, H as its mean plus its slope
// over the step, and ŷ by Lagrange on three nodes: the local error falls from O(h³) to O(h⁴),
// the critical depth's from O(h²) to O(h³), at about twice the work per step. Stacking
// x(j) and the past displacements gives the transition matrix Φ over one period (Ding's
// form); by Floquet theory the process is stable when every eigenvalue of Φ has modulus < 1.
//
// Two ways to use the map:
// * dense: build Φ and take its eigenvalues (the textbook method; dimension d + r·L with
//   L ≈ τ/h, so only for short delays);
// * reduced (default): a multiplier μ = e^(iθ) on the unit circle makes the map's solution
//   quasi-periodic, y(node + n) = μ·y(node), so the stacked history collapses onto the n
//   nodes of one period. The boundary condition becomes the eigenvalue problem of a matrix
//   of size 2r·(number of steps in contact), independent of the delay: w = 1/λ for every
//   real positive eigenvalue λ of K(θ). Scanning θ over [0, π] finds every depth at which a
//   multiplier of the same Φ crosses the unit circle, exactly, without forming Φ.
#pragma once

#include <complex>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cutdyn/stability/critical_depth.hpp"
#include "cutdyn/stability/delayed_system.hpp"

namespace cutdyn {

struct FdOptions {
  /// Longest step as a fraction of the shortest structural period 2π/max|pole(A0)|.
  double max_step_fraction = 1.0 / 64.0;
  /// If > 0: exactly this many steps per period (spread over the coefficient's segments in
  /// proportion to their length, at least one each); for a constant coefficient the period
  /// is then the delay itself, as in the textbook method. 0: steps from max_step_fraction and
  /// a constant coefficient is discretized with a period of one step that divides the
  /// delay.
  int steps_per_period = 0;
  /// Where a tooth cuts (a stretch between two breakpoints of H with H ≠ 0), at least this
  /// many steps: a narrow contact window is otherwise crossed in one or two steps (0: no
  /// minimum).
  int window_steps = 0;
  /// > 0: where a tooth cuts, a step is also at most max_step_fraction of the shortest period
  /// of the structure stiffened by the cut at this depth, 2π/max|eig(A0 − w·E·ΣHk·C)| — the
  /// cutting stiffness can be many times the structure's (0: the structure's periods only).
  /// The spectral-radius searches set it to the boundary they find when `refinements` > 0.
  double cutting_depth_m = 0.0;
  /// Spectral-radius searches: once the boundary is found, the grid is sized by the cut at it
  /// (cutting_depth_m) and the step halved (max_step_fraction and window_steps) until the
  /// boundary moves by less than max(rel_tol·depth, the search's tolerance), at most this many
  /// times; the answer is the finest grid's, CriticalDepth::unconverged when it still moved
  /// (0: one grid, as given; docs/models/milling-stability.md, "The step and its convergence
  /// check").
  int refinements = 0;
  double depth_max_m = 0.03;     // search limit
  double samples_per_turn = 16;  // multiplier-angle samples per 2π of μ^(−τ/T) phase
  /// Interpolation within a step: 1 linear [Ding2010], 2 quadratic (see above). The reduced
  /// method (fd_critical_depth) takes order 1 only.
  int order = 1;
  /// The spectral-radius searches (fd_critical_depth_by_radius, fd_critical_depth_from_hint)
  /// also find every flip crossing below their answer, and with several delays (uneven pitch)
  /// every fold crossing (FdDiscretization::first_real_crossing), so that an unstable island
  /// their depth grid steps over is not missed. false only to measure what that costs (the
  /// benchmarks).
  bool flip_crossings = true;

  std::vector<std::string> validate() const;
};

/// The time grid of one period, and the interpolation order used on it.
struct FdGrid {
  double period_s = 0.0;
  std::vector<double> nodes_s;  // n + 1 nodes, nodes_s.front() = 0, nodes_s.back() = T
  int order = 1;                // FdOptions::order
  int steps() const { return static_cast<int>(nodes_s.size()) - 1; }
};

FdGrid fd_grid(const DelayedSystem& system, const FdOptions& options);

// The functions below throw cutdyn::InvalidInput if the system or the options are invalid.

/// Transition matrix Φ over one period at width of cut `depth_m` (dense, textbook form).
Eigen::MatrixXd fd_transition_matrix(const DelayedSystem& system, const FdGrid& grid,
                                     double depth_m);

/// Largest |eigenvalue| of fd_transition_matrix.
double fd_spectral_radius(const DelayedSystem& system, const FdGrid& grid, double depth_m);

struct SpectralRadius {
  double value = 0.0;
  bool arnoldi = false;      // true: from Arnoldi iteration; false: from the dense matrix
  long long operations = 0;  // products with the period map in Arnoldi
};

/// Largest |eigenvalue| of the same map by Arnoldi iteration (Spectra, 3 eigenvalues of
/// largest modulus, 10 Krylov vectors) on the matrix-free map: O(n·d²) per product instead
/// of forming Φ. Falls back to the dense eigenvalues for small maps (≤ 30 rows) or when
/// Arnoldi does not converge (e.g. thousands of multipliers crowding the unit circle in
/// vibration-assisted turning).
SpectralRadius fd_spectral_radius_arnoldi(const DelayedSystem& system, const FdGrid& grid,
                                          double depth_m);

enum class RadiusSolver { kDense, kArnoldi };

/// The multiplier of largest modulus at one depth and its eigenvector: what the warm depth
/// search keeps of each evaluation (the last unstable one gives the chatter mode).
struct DominantMultiplier {
  double radius = 0.0;             // spectral radius |mu|
  std::complex<double> mu;         // the multiplier of largest modulus
  Eigen::VectorXcd vector;         // its eigenvector (state of the period map)
  long long operations = 0;        // products with the period map
  bool krylov = false;             // false: from the dense matrix
  /// Krylov: the products after which the test would likely have passed already (from the
  /// residuals' margin at acceptance): the next depth's ArnoldiOptions::first_test.
  int passes_after = 0;
  /// From the screening tolerance (ArnoldiOptions::screen_below): radius < screen_below, to
  /// about 1e-4 (at most 4e-5 from the full tolerance's over 5378 guard points of the tests).
  bool screened = false;
};

/// How the Arnoldi iteration of FdDiscretization::dominant_multiplier is run by a search that
/// evaluates many depths of one speed.
struct ArnoldiOptions {
  /// Krylov vectors at the first test of the Ritz values; 0: after the 8th and 9th products.
  /// A search passes the previous depth's DominantMultiplier::passes_after: nearby depths
  /// converge after nearly the same number of products, and each test not passed costs about
  /// two products. The acceptance is the same whatever the schedule.
  int first_test = 0;
  /// > 0: the caller asks only whether ρ < screen_below (the warm search's guard), so the
  /// iteration may stop at the screening tolerance, 1e-7 instead of `tolerance` (the residual
  /// test, relative), once the largest Ritz value is also below screen_below
  /// (DominantMultiplier::screened). A radius at or above it goes on to the full tolerance.
  double screen_below = 0.0;
  /// The residual test's tolerance (relative; Spectra's convergence test, as in
  /// spectral_radius_arnoldi). A depth search's bracket, which needs only the sign of ρ − 1,
  /// takes 1e-8: about one product less a decade.
  double tolerance = 1e-10;
};

/// The discretized system at one speed — step matrices and delay references, which do not
/// depend on the depth. Build it once and evaluate the period map at many depths.
class FdDiscretization {
 public:
  FdDiscretization(const DelayedSystem& system, const FdOptions& options);
  FdDiscretization(const DelayedSystem& system, const FdGrid& grid);
  ~FdDiscretization();
  FdDiscretization(FdDiscretization&&) noexcept;
  FdDiscretization& operator=(FdDiscretization&&) noexcept;

  const FdGrid& grid() const;
  Eigen::MatrixXd transition_matrix(double depth_m) const;
  double spectral_radius(double depth_m) const;                  // dense eigenvalues
  SpectralRadius spectral_radius_arnoldi(double depth_m) const;  // see below
  /// The multiplier of largest modulus at `depth_m`: how stability is lost there
  /// (hopf/flip/fold) and the frequency (Hz) of the harmonic that carries its eigenvector.
  std::pair<Bifurcation, double> dominant_mode(double depth_m, RadiusSolver solver) const;
  /// Spectral radius with the dominant multiplier and its eigenvector. kArnoldi: an
  /// unrestarted Arnoldi iteration (up to 30 Krylov vectors, orthogonalized twice) from the
  /// same fixed pseudo-random start at every call, stopped once the three Ritz values of
  /// largest modulus satisfy the residual test Spectra applies in spectral_radius_arnoldi
  /// (|residual| < 1e-10·|Ritz value|) — the same acceptance, without the restarts, tested
  /// from the 8th product on where the residuals' geometric fall says it may pass, so
  /// typically 9–14 products instead of Spectra's 11–17; if it does not converge, Spectra,
  /// then the dense eigenvalues.
  /// kDense: the dense matrix's eigenvalues and eigenvectors.
  DominantMultiplier dominant_multiplier(double depth_m, RadiusSolver solver) const;
  DominantMultiplier dominant_multiplier(double depth_m, RadiusSolver solver,
                                         const ArnoldiOptions& options) const;
  /// How stability is lost with that multiplier (as dominant_mode) and the chatter frequency.
  std::pair<Bifurcation, double> mode_of(const DominantMultiplier& dominant) const;
  /// The smallest depth in (0, below_m] at which −1 (kind kFlip) or +1 (kFold) is a
  /// multiplier of the period map — the edge of an unstable island, or the boundary itself —
  /// from one linear eigenvalue problem whose eigenvalues are the inverse depths of every
  /// such crossing (docs/models/milling-stability.md, "Unstable islands"); `found` false when
  /// there is none. bifurcation = kind, chatter_hz from the crossing's solution.
  CriticalDepth first_real_crossing(double below_m, Bifurcation kind = Bifurcation::kFlip) const;
  /// Spectral radius of the map at depth 0 without evaluating it: the map is then block
  /// triangular, its nonzero multipliers those of e^(A0·T), so ρ(0) = max e^(Re(pole)·T).
  double radius_without_cutting() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Critical depth by the reduced (multiplier-on-the-unit-circle) method.
CriticalDepth fd_critical_depth(const DelayedSystem& system, const FdOptions& options);

/// Critical depth from the spectral radius of the period map: a coarse depth scan brackets
/// the first unstable depth (so an unstable island above a stable band is not skipped), then
/// Brent's method on ρ − 1 to `rel_tol`. Below the answer, an island between two grid points is
/// sought where the grid's radii have a local maximum of at least 0.9 (golden sections), and
/// the first flip crossing (with several delays also fold) is taken when it is lower
/// (FdOptions::flip_crossings; docs/models/milling-stability.md, "Unstable islands and the
/// depth search"). The discretization is built once; each depth costs one spectral radius,
/// dense or by Arnoldi (with dense fallback). Bifurcation type and chatter frequency come from
/// the dominant multiplier just above the boundary (from the crossing's solution for a flip or
/// fold crossing). With FdOptions::refinements > 0 the boundary is then confirmed on finer
/// grids (sized by the cut at it, the step halved) and is the finest grid's; the same for every
/// search below.
CriticalDepth fd_critical_depth_by_radius(const DelayedSystem& system, const FdOptions& options,
                                          RadiusSolver solver, double rel_tol = 1e-6,
                                          int coarse_steps = 24);

/// The same for a system whose coefficient depends on the depth (a helical milling cutter,
/// whose H is the average over the engaged flute length): `system_at(w)` is the system at
/// depth w. The time grid is that of system_at(depth_max) (its periods and delays must not
/// depend on the depth); each depth rebuilds the step coefficients.
CriticalDepth fd_critical_depth_by_radius(
    const std::function<DelayedSystem(double depth_m)>& system_at, const FdOptions& options,
    RadiusSolver solver, double rel_tol = 1e-6, int coarse_steps = 24);

/// Critical depth from the spectral radius with the search started at `hint_depth_m`, the
/// critical depth at a neighbouring speed (docs/models/milling-stability.md, "Warm-started
/// depth search"). The same boundary as fd_critical_depth_by_radius, with the same
/// guarantee against a lower crossing: (1) from the hint, secant steps with a small
/// overshoot bracket an upward crossing of ρ − 1 and shrink the bracket [lo, hi] to the
/// exhaustive search's tolerance (rel_tol times the coarse grid point at or above hi); (2) the
/// guard: ρ < 1 is verified at every point of the coarse
/// depth grid (depth_max/coarse_steps apart, the grid of the exhaustive scan) below lo — the
/// exhaustive search's own condition for reporting a boundary in a higher grid cell; (3) if
/// the guard finds an unstable grid point or an island between grid points (as the exhaustive
/// search's probe), or the bracket cannot be made (stable up to
/// depth_max, no hint, a hint outside (0, depth_max]), the exhaustive search decides. The
/// mode (bifurcation, chatter frequency) is that of the dominant multiplier at hi, within
/// rel_tol above the boundary. `evaluations` counts every spectral radius. `hint_is_close`:
/// the hint is likely within a fraction of the tolerance (extrapolated along a smooth lobe),
/// and the first two depths straddle it 0.45 tolerance below and above (a bracket narrow
/// enough at once when the boundary is between them; otherwise the steps above go on from
/// there). The result meets the same conditions either way, and the flip (fold) crossings
/// below it are taken as in fd_critical_depth_by_radius.
CriticalDepth fd_critical_depth_from_hint(const DelayedSystem& system, const FdOptions& options,
                                          RadiusSolver solver, double rel_tol, int coarse_steps,
                                          double hint_depth_m, bool hint_is_close = false);

/// The same for a depth-dependent system (helical cutter), as fd_critical_depth_by_radius.
CriticalDepth fd_critical_depth_from_hint(
    const std::function<DelayedSystem(double depth_m)>& system_at, const FdOptions& options,
    RadiusSolver solver, double rel_tol, int coarse_steps, double hint_depth_m,
    bool hint_is_close = false);

/// Critical depth by the dense method: spectral radius on a coarse depth scan to bracket the
/// first unstable depth, then Brent's method to `rel_tol`. For cross-checks at short delays.
CriticalDepth fd_critical_depth_dense(const DelayedSystem& system, const FdOptions& options,
                                      double rel_tol = 1e-6, int coarse_steps = 24);

}  // namespace cutdyn
