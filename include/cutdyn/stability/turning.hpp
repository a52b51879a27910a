// Regenerative chatter in turning, conventional and vibration-assisted
// [Chikishev2018, eqs. 6–11]; docs/models/turning.md.
//
// One or more tool modes in the feed direction x; the feed force is
// F(t) = g(t)·Kt·w·(h0 + y(t − τ) − y(t)), with τ = 60/n the time of one revolution and g the
// contact window of the vibration (g ≡ 1 in conventional cutting). The model builds the
// neutral DelayedSystem, and every stability method of stability/ applies to it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cutdyn/forces/duty_cycle.hpp"
#include "cutdyn/modal/modal_model.hpp"
#include "cutdyn/stability/critical_depth.hpp"
#include "cutdyn/stability/delayed_system.hpp"
#include "cutdyn/stability/full_discretization.hpp"
#include "cutdyn/stability/method.hpp"

namespace cutdyn {

/// Vibration of the tool along the cutting direction. The duty cycle is either fixed or,
/// given the workpiece diameter D, computed at each spindle speed n from v = π·D·n/60.
struct VibrationAssist {
  double frequency_hz = 0.0;
  double amplitude_m = 0.0;                    // needed unless duty_cycle is fixed
  std::optional<double> workpiece_diameter_m;  // duty cycle from the cutting speed
  std::optional<double> duty_cycle;            // fixed duty cycle

  DutyCycle at_rpm(double rpm) const;
};

struct TurningModel {
  ModalModel modal;    // modes in direction x
  double kt_pa = 0.0;  // feed-direction cutting coefficient, N/m²
  std::optional<VibrationAssist> vibration;

  std::vector<std::string> validate() const;
  /// The same model without the vibration.
  TurningModel conventional() const;
};

/// The neutral description at spindle speed `rpm`: x = modal states, y = tool displacement
/// in x, H(t) = Kt·g(t) with g the contact window at that speed, τ = 60/rpm.
DelayedSystem turning_system(const TurningModel& model, double rpm);

enum class TurningMethod {
  kClosedForm,               // Tlusty; with vibration, the averaged theory (Kt → r·Kt)
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
void check_speed_domain(const TurningModel& model, double rpm);

TurningBoundary turning_critical_depth(const TurningModel& model, double rpm,
                                       const TurningStabilityOptions& options);

}  // namespace cutdyn
