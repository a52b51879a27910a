// Regenerative chatter in turning, conventional and vibration-assisted
// [Chikishev2018, eqs. 6–11]; docs/models/turning.md.
//
// One or more tool modes in the feed direction x; the feed force is
// F(t) = g(t)·Kf·w·(h0 + y(t − τ) − y(t)), with τ = 60/n the time of one revolution and g the
// contact window of the vibration (g ≡ 1 in conventional cutting). The model builds the
// neutral DelayedSystem, and every stability method of stability/ applies to it.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "cutdyn/process/turning.hpp"
#include "cutdyn/stability/critical_depth.hpp"
#include "cutdyn/stability/delayed_system.hpp"
#include "cutdyn/stability/full_discretization.hpp"
#include "cutdyn/stability/method.hpp"

namespace cutdyn {

/// The neutral description at spindle speed `rpm`: x = modal states, y = tool displacement
/// in x, H(t) = Kf·g(t) with g the contact window at that speed, τ = 60/rpm.
DelayedSystem turning_system(const TurningProcess& model, double rpm);

enum class TurningMethod {
  kClosedForm,               // Tlusty; with vibration, the averaged theory (Kf → r·Kf)
  kMultiFrequency,           // Hill's method with `harmonics` harmonics of the vibration
  kFullDiscretization,       // first-order full discretization, reduced form
  kFullDiscretizationDense,  // the same discretization, dense transition matrix (slow)
};

const char* to_string(TurningMethod method);

/// The turning method for the one asked: auto → the closed form without vibration, else the
/// full discretization; zero-order and closed-form → the closed form.
TurningMethod turning_method(StabilityMethod asked, bool vibration);

struct TurningStabilityOptions {
  TurningMethod method = TurningMethod::kFullDiscretization;
  double depth_max_m = 0.03;
  int harmonics = 5;
  FdOptions fd;  // depth_max_m is taken from above

  /// The members a user sets (core/fields.hpp): depth_max_mm, harmonics.
  static std::span<const Field<TurningStabilityOptions>> fields();
  std::vector<std::string> validate() const;
};

struct TurningBoundary {
  CriticalDepth boundary;
  double duty_cycle = 1.0;  // r at this speed
  int lobe = 0;             // whole chatter waves per revolution
};

/// Throws cutdyn::InvalidInput if `rpm` is not positive, or so slow that one revolution
/// spans more than 20 000 periods of the highest mode or 500 000 vibration periods (the
/// scans' work grows with that number).
void check_speed_domain(const TurningProcess& model, double rpm);

TurningBoundary turning_critical_depth(const TurningProcess& model, double rpm,
                                       const TurningStabilityOptions& options);

}  // namespace cutdyn
