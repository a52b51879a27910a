#include "cutdyn/stability/turning.hpp"

#include <cmath>
#include <cstdio>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/stability/multi_frequency.hpp"
#include "cutdyn/stability/tlusty.hpp"

namespace cutdyn {

DelayedSystem turning_system(const TurningProcess& model, double rpm) {
  const auto ss = modal_state_space(model.structure_modes(), {Direction::kX});
  DelayedSystem s;
  s.A0 = ss.A;
  s.E = ss.B;
  s.C = ss.C;
  if (model.measured) {
    s.measured_response = [given = model.modal, measured = *model.measured,
                           directions = std::vector<Direction>{Direction::kX}](double w,
                                                                  Eigen::MatrixXcd& g) {
      combined_receptance(given, measured, directions, w, g);
    };
  }
  s.delay_s = 60.0 / rpm;  // [Chikishev2018, eq. 6]: one revolution
  const Eigen::MatrixXd kt = Eigen::MatrixXd::Constant(1, 1, model.kf_pa);
  if (model.vibration) {
    const DutyCycle dc = model.vibration->at_rpm(rpm);
    const ContactWindow g = dc.window();
    s.H = windowed_coefficient(kt, g.period_s, g.duty_cycle, g.start_s);
  } else {
    s.H = constant_coefficient(kt);
  }
  return s;
}

TurningMethod turning_method(StabilityMethod asked, bool vibration) {
  switch (asked) {
    case StabilityMethod::kZeroOrder:
    case StabilityMethod::kClosedForm:
      return TurningMethod::kClosedForm;
    case StabilityMethod::kMultiFrequency:
      return TurningMethod::kMultiFrequency;
    case StabilityMethod::kFullDiscretization:
      return TurningMethod::kFullDiscretization;
    case StabilityMethod::kFullDiscretizationDense:
      return TurningMethod::kFullDiscretizationDense;
    case StabilityMethod::kAuto:
      break;
  }
  return vibration ? TurningMethod::kFullDiscretization : TurningMethod::kClosedForm;
}

const char* to_string(TurningMethod method) {
  switch (method) {
    case TurningMethod::kClosedForm:
      return "closed-form";
    case TurningMethod::kMultiFrequency:
      return "multi-frequency";
    case TurningMethod::kFullDiscretization:
      return "full-discretization";
    case TurningMethod::kFullDiscretizationDense:
      return "full-discretization-dense";
  }
  return "?";
}

std::span<const Field<TurningStabilityOptions>> TurningStabilityOptions::fields() {
  using O = TurningStabilityOptions;
  static const Field<O> list[] = {
      make_field(stability_fields::kDepthMax, &O::depth_max_m),
      make_field(stability_fields::kHarmonics, &O::harmonics),
  };
  return list;
}

std::vector<std::string> TurningStabilityOptions::validate() const {
  Validator v;
  check_fields(*this, fields(), v);
  for (const std::string& p : fd.validate()) v.add("fd." + p);
  return v.problems();
}

namespace {
std::string rounded(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}
}  // namespace

void check_speed_domain(const TurningProcess& model, double rpm) {
  // The frequency and multiplier scans resolve the delay phase, so their work grows with the
  // number of vibration cycles in one revolution; bound it rather than run for hours.
  constexpr double kMaxModeCycles = 20000.0;
  constexpr double kMaxVibrationPeriods = 500000.0;
  // With vibration the period is the vibration's: revolutions within it multiply the steps
  // (0.4 s at 100 per period, a minute at 800; 100 is 1.2e8 rpm at 20 kHz).
  constexpr double kMaxRevolutionsPerVibration = 100.0;
  Validator v;
  v.require_positive("spindle speed", rpm, "rpm");
  v.throw_if_any();
  const double tau = 60.0 / rpm;
  const double f_top = units::rad_per_s_to_hz(model.structure_modes().max_natural_rad_s());
  if (tau * f_top > kMaxModeCycles) {
    v.add("spindle speed = " + rounded(rpm) + " rpm: one revolution spans " +
          rounded(std::round(tau * f_top)) + " periods of the " + rounded(f_top) +
          " Hz mode; the stability methods take at most " + rounded(kMaxModeCycles) +
          " (raise the speed)");
  }
  if (model.vibration && tau * model.vibration->frequency_hz > kMaxVibrationPeriods) {
    v.add("spindle speed = " + rounded(rpm) + " rpm: one revolution spans " +
          rounded(std::round(tau * model.vibration->frequency_hz)) +
          " vibration periods; the stability methods take at most " +
          rounded(kMaxVibrationPeriods) + " (raise the speed)");
  }
  if (model.vibration && rpm / 60.0 > kMaxRevolutionsPerVibration * model.vibration->frequency_hz) {
    v.add("spindle speed = " + rounded(rpm) + " rpm: one period of the " +
          rounded(model.vibration->frequency_hz) + " Hz vibration spans " +
          rounded(rpm / 60.0 / model.vibration->frequency_hz) +
          " revolutions; the stability methods take at most " +
          rounded(kMaxRevolutionsPerVibration) + " (lower the speed)");
  }
  v.throw_if_any();
}

TurningBoundary turning_critical_depth(const TurningProcess& model, double rpm,
                                       const TurningStabilityOptions& o) {
  Validator v;
  v.merge(model.validate());
  v.merge(o.validate());
  v.throw_if_any("turning stability");
  check_speed_domain(model, rpm);
  TurningBoundary out;
  out.duty_cycle = model.vibration ? model.vibration->at_rpm(rpm).ratio : 1.0;
  const double tau = 60.0 / rpm;
  switch (o.method) {
    case TurningMethod::kClosedForm: {
      if (model.measured) {  // Tlusty's solution is the averaged one on the tabulated FRF
        MultiFrequencyOptions mf;
        mf.harmonics = 0;
        mf.depth_max_m = o.depth_max_m;
        TurningProcess averaged = model;
        averaged.kf_pa *= out.duty_cycle;
        averaged.vibration.reset();
        out.boundary = multi_frequency_critical_depth(turning_system(averaged, rpm), mf);
        break;
      }
      const auto t = tlusty_critical_depth(model.modal, Direction::kX, out.duty_cycle * model.kf_pa,
                                           tau, o.depth_max_m);
      out.boundary = t.boundary;
      break;
    }
    case TurningMethod::kMultiFrequency: {
      MultiFrequencyOptions mf;
      mf.harmonics = o.harmonics;
      mf.depth_max_m = o.depth_max_m;
      out.boundary = multi_frequency_critical_depth(turning_system(model, rpm), mf);
      break;
    }
    case TurningMethod::kFullDiscretization:
    case TurningMethod::kFullDiscretizationDense: {
      FdOptions fd = o.fd;
      fd.depth_max_m = o.depth_max_m;
      const DelayedSystem s = turning_system(model, rpm);
      out.boundary = o.method == TurningMethod::kFullDiscretization
                         ? fd_critical_depth(s, fd)
                         : fd_critical_depth_dense(s, fd);
      break;
    }
  }
  out.lobe = out.boundary.found ? static_cast<int>(std::floor(out.boundary.chatter_hz * tau)) : 0;
  return out;
}

}  // namespace cutdyn
