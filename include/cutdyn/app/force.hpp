// The force job: the cutting and thrust forces of an orthogonal (turning) cut, conventional
// or vibration-assisted (pulsed, with its duty cycle), from given coefficients or predicted
// from a [material] by Oxley's theory.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cutdyn/app/case_models.hpp"
#include "cutdyn/forces/duty_cycle.hpp"
#include "cutdyn/io/case_file.hpp"

namespace cutdyn::app {

/// One point of Oxley's prediction around the case's cut, at another uncut chip thickness.
struct ChipThicknessPoint {
  double uncut_chip_thickness_m = 0.0;
  double cutting_force_n = 0.0, thrust_force_n = 0.0, shear_angle_rad = 0.0;
};

struct ForceJobReport {
  double kc_pa = 0.0, kf_pa = 0.0;       // cutting- and feed-direction coefficients used
  std::optional<OxleyPrediction> oxley;  // where they were predicted from [material]
  double uncut_chip_thickness_m = 0.0, width_m = 0.0;
  std::optional<double> speed_m_per_s;
  DutyCycle duty_cycle;  // conventional: ratio 1
  bool vibration = false;
  PulsedForces forces;
  // With Oxley's theory and no vibration: the prediction from h/4 to 2h (15 thicknesses;
  // those outside the theory's validity left out).
  std::vector<ChipThicknessPoint> around;
};

/// Needs [cutting] uncut_chip_thickness_mm and width_mm, and kc/kt or a [material] (with
/// speed and rake); with a [vibration] its duty cycle or the cutting speed. Throws
/// cutdyn::InvalidInput naming the case and every missing key.
ForceJobReport run_force(const io::Case& c);

}  // namespace cutdyn::app
