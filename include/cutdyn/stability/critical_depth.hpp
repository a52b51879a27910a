// What every per-speed stability method returns.
#pragma once

namespace cutdyn {

/// How stability is lost at the critical depth, from the critical Floquet multiplier μ:
/// a complex pair crossing the unit circle (secondary Hopf, quasi-periodic chatter), μ = −1
/// (flip, period doubling) or μ = +1 (fold). Frequency-domain methods see only kHopf.
enum class Bifurcation { kNone, kHopf, kFlip, kFold };

const char* to_string(Bifurcation b);  // "none", "hopf", "flip", "fold"

/// Classifies a critical multiplier by its argument θ ∈ [−π, π].
Bifurcation classify_multiplier(double theta);

struct CriticalDepth {
  /// Smallest width of cut (m) at which the process loses stability at this speed; equal to
  /// the search limit when `found` is false.
  double depth_m = 0.0;
  /// Frequency (Hz) of the vibration that sets in at that depth; 0 when not found.
  double chatter_hz = 0.0;
  /// False when the process stays stable up to the search limit.
  bool found = false;
  Bifurcation bifurcation = Bifurcation::kNone;  // kNone when not found or not classified
  /// Work done: matrix evaluations, eigenvalue problems or stability tests.
  long long evaluations = 0;
  /// Boundary candidates the method could not resolve (see BoundaryScanReport); when
  /// non-zero the depth may be too large. Reported by the lobe tracer as a warning.
  int unresolved = 0;
  /// The method's approximation could not be made to cover this case (e.g. the
  /// multi-frequency window could not reach every mode's frequency): the depth may be wrong.
  /// Reported by the lobe tracer as a warning.
  bool truncated = false;
  /// The full discretization's boundary still moved by more than the search tolerance when
  /// the step was halved the last time allowed (FdOptions::refinements): the depth may be off
  /// by more than the tolerance. Reported by the lobe tracer as a warning.
  bool unconverged = false;
};

}  // namespace cutdyn
