// What every per-speed stability method returns.
#pragma once

namespace cutdyn {

struct CriticalDepth {
  /// Smallest width of cut (m) at which the process loses stability at this speed; equal to
  /// the search limit when `found` is false.
  double depth_m = 0.0;
  /// Frequency (Hz) of the vibration that sets in at that depth; 0 when not found.
  double chatter_hz = 0.0;
  /// False when the process stays stable up to the search limit.
  bool found = false;
  /// Work done: matrix evaluations, eigenvalue problems or stability tests.
  long long evaluations = 0;
  /// Boundary candidates the method could not resolve (see BoundaryScanReport); when
  /// non-zero the depth may be too large. Reported by the lobe tracer as a warning.
  int unresolved = 0;
};

}  // namespace cutdyn
