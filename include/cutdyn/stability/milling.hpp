// Regenerative chatter in milling [Altintas1995; Insperger2004; Ding2010];
// docs/models/milling-stability.md.
//
// Tooth j of z sits at the angle φj(t) = Ω·t + 2πj/z, measured clockwise from the +y axis (as in
// the milling simulation, docs/models/milling-simulation.md). In cut (φst < φj < φex) it takes the
// chip h = Δx·sin φj + Δy·cos φj (Δ = r(t) − r(t − τ), r the cutter's displacement) and pushes the
// cutter with
//     Fx = −Ft·cos φj − Fr·sin φj,   Fy = Ft·sin φj − Fr·cos φj,   Ft = Kt·a·h, Fr = Kr·a·h.
// Summed over the teeth: F = (a/2)·Kt·A(t)·Δ with Altintas' directional matrix A(t), so the
// neutral description has H(t) = −(Kt/2)·A(t), period and delay τ = 60/(n·z).
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "cutdyn/process/milling.hpp"
#include "cutdyn/stability/critical_depth.hpp"
#include "cutdyn/stability/delayed_system.hpp"
#include "cutdyn/stability/full_discretization.hpp"
#include "cutdyn/stability/lobes.hpp"
#include "cutdyn/stability/method.hpp"

namespace cutdyn {

/// The neutral description at spindle speed `rpm` and depth `depth_m`: x = the modal states of
/// the x and y modes, y = (x, y) displacements of the cutter, H(t) = −(Kt/2)·A(t) per unit
/// depth with exact means and Fourier coefficients. A helical cutter is cut into axial slices
/// (model.slices(depth)), each a straight tooth lagging by its share of the lag angle, and H is
/// their average: it depends on the depth, which straight teeth do not. Even pitch: one delay
/// τ = T = 60/(rpm·z) and H of period T. Uneven pitch: one delay term per tooth,
/// τj = pitch_j/Ωs, each with the period of one revolution.
DelayedSystem milling_system(const MillingProcess& model, double rpm, double depth_m = 0.0);

enum class MillingMethod {
  kZeroOrder,                // Altintas & Budak 1995: multi-frequency with no harmonics
  kMultiFrequency,           // with `harmonics` harmonics of the (mean) tooth-passing frequency
  kFullDiscretization,       // spectral radius by Arnoldi on the matrix-free period map
  kFullDiscretizationDense,  // spectral radius of the dense transition matrix
};

/// "zero-order", "multi-frequency", "full-discretization", "full-discretization-dense".
const char* to_string(MillingMethod method);

/// The milling method for the one asked: auto → the full discretization; zero-order and
/// closed-form → the zero-order solution.
MillingMethod milling_method(StabilityMethod asked);

struct MillingStabilityOptions {
  MillingMethod method = MillingMethod::kFullDiscretization;
  double depth_max_m = 1e-3;
  /// Multi-frequency: at least this many harmonics of the tooth-passing frequency (uneven
  /// pitch: z× as many of the spindle's), raised until the window covers every mode
  /// (multi_frequency_harmonics) unless `exact_harmonics`.
  int harmonics = 5;
  bool exact_harmonics = false;
  /// Multi-frequency: every eigenvalue of K by the dense solver, as before 2026-12-02
  /// (MultiFrequencyOptions::dense_eigenvalues; for comparisons and benchmarks).
  bool dense_eigenvalues = false;
  /// Multi-frequency: frequency samples at the sharpest mode's equal steps, as before
  /// 2026-12-02 evening (MultiFrequencyOptions::uniform_step; for comparisons and benchmarks).
  bool uniform_frequency_step = false;
  /// Full discretization: quadratic interpolation (order 2) on steps of at most 1/32 of the
  /// shortest period of the structure — where a tooth cuts, of the structure stiffened by the
  /// cut at the boundary, with at least 8 steps per contact window — and the boundary
  /// confirmed on half the step (up to 3 halvings): within 0.012 % of the converged one on
  /// the tests' cases (docs/models/milling-stability.md, "The step and its convergence
  /// check"). depth_max_m is taken from above.
  FdOptions fd{.max_step_fraction = 1.0 / 32.0, .window_steps = 8, .refinements = 3, .order = 2};
  double rel_tol = 1e-3;  // critical depth, full discretization and helix iterations
  int coarse_steps = 16;  // depth scan before Brent's method (unstable islands)
  /// Lobes by the full discretization (trace_milling_lobes): start each speed's depth search
  /// from its neighbours' critical depths (fd_critical_depth_from_hint), with the same guard
  /// against a lower crossing as the coarse scan. false: every speed searched on its own
  /// (coarse scan, then Brent), as before 2026-11-24.
  bool warm_start = true;

  /// The members a user sets (core/fields.hpp): depth_max_mm, harmonics, rel_tol,
  /// coarse_steps; validate() walks them.
  static std::span<const Field<MillingStabilityOptions>> fields();
  std::vector<std::string> validate() const;
};

struct MillingBoundary {
  CriticalDepth boundary;
  int lobe = 0;  // whole chatter waves per (mean) tooth period
};

/// Critical depth at one speed. The zero-order solution does not depend on the helix (the
/// mean of H over a period is the same for every slice). With a helix, the depth-dependent H
/// is handled by the full discretization's depth search directly, and by the multi-frequency
/// method through the margin a − w_crit(H(a)) (coarse scan, then Brent).
MillingBoundary milling_critical_depth(const MillingProcess& model, double rpm,
                                       const MillingStabilityOptions& options);

/// The same with the full discretization's depth search started from `hint_depth_m`, the
/// critical depth at a neighbouring speed (fd_critical_depth_from_hint: the same boundary
/// to rel_tol, verified against a lower crossing on the coarse grid). The other methods
/// ignore the hint.
MillingBoundary milling_critical_depth(const MillingProcess& model, double rpm,
                                       const MillingStabilityOptions& options,
                                       double hint_depth_m);

/// The hint for a speed from the computed speeds next to it (LobesOptions/trace_lobes_warm's
/// `near`, nearest first): none (0) when the nearest has no boundary; when the first three
/// are on one lobe with one bifurcation, the parabola through their ln(depth), in speed
/// (`close`: fd_critical_depth_from_hint straddles it); with two such neighbours, the line
/// (interpolation around a refined speed, extrapolation along a run); kept within a factor 2
/// of the nearest; else the nearest's depth, or the smaller of the two around a refined
/// speed.
struct MillingDepthHint {
  double depth_m = 0.0;  // 0: none
  bool close = false;    // from three speeds along one lobe
};
MillingDepthHint milling_depth_prediction(double rpm, const std::vector<const LobePoint*>& near);
/// milling_depth_prediction's depth.
double milling_depth_hint(double rpm, const std::vector<const LobePoint*>& near);

/// The lobes of `model` over `grid`, as `cutdyn lobes` traces them. Full discretization with
/// options.warm_start: trace_lobes_warm with milling_depth_hint; otherwise trace_lobes with
/// milling_critical_depth at every speed on its own.
LobesReport trace_milling_lobes(const MillingProcess& model, const MillingStabilityOptions& options,
                                const LobesOptions& grid,
                                const std::function<void(int done, int total)>& progress = {});

/// Where `method` is known to be weak for this cut over rpm_min..rpm_max, the warning a front
/// end prints with its results (docs/models/milling-stability.md, "How far the methods
/// agree"); empty where the method is within its stated tolerance. Today: the zero-order
/// method at partial immersion (window under 180°) or with the tooth frequency below half the
/// lowest mode's.
std::optional<std::string> milling_method_caveat(const MillingProcess& model, MillingMethod method,
                                                 double rpm_min, double rpm_max);

/// The same search carried on to at least `depth_m`, with the same coarse depth step
/// (depth_max_m / coarse_steps): the first unstable depth is found on the same grid points, so
/// the critical depth at a speed does not depend on how far the search goes (`cutdyn check`
/// at any depth agrees with the lobes). Throws cutdyn::InvalidInput (where = "stability
/// search") when that would take more than kMaxSearchExtension × depth_max_m.
inline constexpr double kMaxSearchExtension = 64.0;
MillingStabilityOptions extend_search(const MillingStabilityOptions& options, double depth_m);

/// Altintas' directional matrix per tooth in cut, per unit Kt·a/2, at angle φ (Kr = kr/kt).
Eigen::Matrix2d milling_directional_matrix(double phi, double kr_ratio);

}  // namespace cutdyn
