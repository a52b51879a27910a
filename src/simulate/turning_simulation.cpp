#include "cutdyn/simulate/turning_simulation.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/simulate/detail/modal_stepper.hpp"
#include "cutdyn/simulate/growth_estimate.hpp"

namespace cutdyn {

std::vector<std::string> TurningSimulationOptions::validate() const {
  Validator v;
  v.require_positive("rpm", rpm, "rpm");
  v.require_positive("depth_m", depth_m, "m");
  v.require_positive("feed_m", feed_m, "m");
  v.require(duration_s > 0.0 && duration_s <= 1000.0, "duration_s", duration_s, "s",
            "must be greater than 0 and at most 1000");
  v.require(initial_displacement_m > 0.0 && initial_displacement_m < 1.0, "initial_displacement_m",
            initial_displacement_m, "m",
            "must be positive (the disturbance whose growth decides chatter) and below 1 m");
  v.require(max_step_fraction > 0.0 && max_step_fraction <= 0.1, "max_step_fraction",
            max_step_fraction, "", "must be greater than 0 and at most 0.1");
  v.require(max_recorded_samples >= 2, "max_recorded_samples", max_recorded_samples, "",
            "must be at least 2");
  return v.problems();
}

TurningSimulationResult simulate_turning(const TurningProcess& model,
                                         const TurningSimulationOptions& o) {
  Validator v;
  v.merge(model.validate());
  v.merge(o.validate());
  v.throw_if_any("turning simulation");

  const ModalModel modes = model.structure_modes();  // fitted to a measured FRF too
  const auto ss = modal_state_space(modes, {Direction::kX});
  const auto d = ss.A.rows();
  const double tau = 60.0 / o.rpm;

  // Step: divides the revolution; resolves the structure and the vibration.
  double w_top = 0.0;
  for (const Mode& m : modes.modes) w_top = std::max(w_top, m.natural_rad_s);
  double h_target = o.max_step_fraction * units::kTwoPi / w_top;
  ContactWindow window;  // g ≡ 1
  double duty = 1.0;
  if (model.vibration) {
    const DutyCycle dc = model.vibration->at_rpm(o.rpm);
    window = dc.window();
    duty = dc.ratio;
    if (dc.ratio < 1.0) h_target = std::min(h_target, dc.period_s / 16.0);
  }
  const auto per_rev = static_cast<long long>(std::ceil(tau / h_target));
  const double h = tau / static_cast<double>(per_rev);
  const auto steps = static_cast<long long>(std::ceil(o.duration_s / h));
  constexpr long long kMaxSteps = 200'000'000;
  if (steps > kMaxSteps || per_rev > kMaxSteps / 10) {
    throw InvalidInput(
        {"duration_s = " + format_value(o.duration_s) + " s at " + format_value(o.rpm) +
         " rpm: needs " + std::to_string(steps) + " steps of " + format_value(h) + " s (and " +
         std::to_string(per_rev) + " per revolution); the limit is " + std::to_string(kMaxSteps) +
         " (shorten the run or raise the speed)"},
        "turning simulation");
  }

  const ModalStepper stepper(modes, {Direction::kX}, h);
  const Eigen::RowVectorXd c = ss.C.row(0);
  const double c_gamma_end = (c * stepper.gamma_end())(0, 0);  // C·Γ1

  TurningSimulationResult out;
  out.duty_cycle = duty;
  out.step_s = h;
  out.steps = steps;
  const double kw = model.kf_pa * o.depth_m;
  // Static deflection under the mean force r·Kf·w·h0: each mode deflects by F/k.
  const double f_mean = duty * kw * o.feed_m;
  Eigen::VectorXd x0 = Eigen::VectorXd::Zero(d);
  for (Eigen::Index i = 0; i < d / 2; ++i)
    x0(2 * i) = f_mean / modes.modes[static_cast<std::size_t>(i)].stiffness_n_per_m;
  out.static_deflection_m = c * x0;
  // Runaway: a vibration of a thousand feeds is far beyond any cut (and before overflow).
  const double runaway_bound = 1e3 * (o.feed_m + o.initial_displacement_m);

  // Two runs in step: [0] with the initial displacement (the one reported), [1] without. The
  // forced response is common to both; their difference is the free regenerative response.
  struct Run {
    Eigen::VectorXd x;
    std::vector<double> surface;  // S over the last revolution, ring buffer
    Eigen::VectorXd start_force = Eigen::VectorXd::Zero(1), end_force = Eigen::VectorXd::Zero(1);
    double y = 0.0, force = 0.0, chip = 0.0;
  };
  std::array<Run, 2> runs;
  for (Run& r : runs) {
    r.x = x0;
    r.surface.assign(static_cast<std::size_t>(per_rev), out.static_deflection_m);
  }
  runs[0].x(0) += o.initial_displacement_m;
  for (Run& r : runs) r.y = c * r.x;

  const long long stride = std::max<long long>(1, steps / o.max_recorded_samples + 1);
  // The difference of the runs' states every quarter of the shortest mode period: the free
  // response of a delay equation with constant coefficients (the pulses of the assisted cut
  // are averaged at this spacing) is a sum of c_i·e^(λ_i·t), for its dominant root.
  const long long sample_steps =
      std::max<long long>(1, std::llround(0.25 * units::kTwoPi / w_top / h));
  std::vector<std::vector<double>> samples_all;
  std::vector<double> sample_time_s;
  double rev_min = 1e300, rev_max = -1e300, diff_min = 1e300, diff_max = -1e300;
  double g_before = window.mean(-h, 0.0);  // window mean over the step ending at the node
  long long k = 0;
  int reported = -1;  // the last hundredth of the run reported
  for (; k < steps; ++k) {
    if (o.progress && static_cast<int>(k * 100 / steps) != reported) {
      reported = static_cast<int>(k * 100 / steps);
      o.progress(reported, 100);
    }
    const double t = static_cast<double>(k) * h;
    const double g = window.mean(t, t + h);
    for (Run& r : runs) {
      // Node k: y from the predictor (force held from the last node; error O(h³)) when k > 0.
      Eigen::VectorXd base;
      if (k > 0) {
        base = stepper.phi() * r.x + stepper.gamma_start() * r.start_force;
        r.y = (c * base)(0) + c_gamma_end * r.start_force(0);
      }
      double& s_slot = r.surface[static_cast<std::size_t>(k % per_rev)];  // holds S(t − τ)
      r.chip = o.feed_m + s_slot - r.y;
      double cutting = 0.0;
      if (r.chip > 0.0) {
        cutting = kw * r.chip;  // [Chikishev2018, eq. 8] without the window
        s_slot = r.y;
      } else {
        s_slot += o.feed_m;
        if (!out.lost_contact) {
          out.lost_contact = true;
          out.contact_loss_time_s = t;
        }
      }
      r.force = g * cutting;
      // First-order hold over the step ending here (window mean of that step) [Ding2010].
      if (k > 0) {
        r.end_force(0) = g_before * cutting;
        r.x = base + stepper.gamma_end() * r.end_force;
        r.y = c * r.x;
      }
      r.start_force(0) = g * cutting;
    }
    g_before = g;
    const double y = runs[0].y, diff = runs[0].y - runs[1].y;
    if (k % stride == 0) {
      out.time_s.push_back(t);
      out.displacement_m.push_back(y);
      out.force_n.push_back(runs[0].force);
      out.chip_thickness_m.push_back(runs[0].chip);
    }
    rev_min = std::min(rev_min, y);
    rev_max = std::max(rev_max, y);
    diff_min = std::min(diff_min, diff);
    diff_max = std::max(diff_max, diff);
    if ((k + 1) % sample_steps == 0) {
      samples_all.emplace_back(static_cast<std::size_t>(d));
      for (Eigen::Index i = 0; i < d; ++i)
        samples_all.back()[static_cast<std::size_t>(i)] = runs[0].x(i) - runs[1].x(i);
      sample_time_s.push_back(t + h);
    }
    if ((k + 1) % per_rev == 0) {
      out.revolution_time_s.push_back(t + h);
      out.revolution_amplitude_m.push_back(0.5 * (rev_max - rev_min));
      out.perturbation_amplitude_m.push_back(0.5 * (diff_max - diff_min));
      rev_min = diff_min = 1e300;
      rev_max = diff_max = -1e300;
    }
    bool runaway = false;
    for (const Run& r : runs)
      runaway = runaway || !(std::abs(r.y - out.static_deflection_m) <= runaway_bound);
    if (runaway) {  // also catches NaN
      out.status = SimulationStatus::kRunaway;
      out.stop_time_s = t;
      ++k;
      break;
    }
  }
  out.steps = k;
  if (out.status == SimulationStatus::kCompleted) out.stop_time_s = static_cast<double>(k) * h;

  // Growth rate of the difference, over the revolutions from the third (the first two carry
  // the start of the regeneration) up to the first loss of contact (after it the runs are no
  // longer linear) or a 1e9-fold decay (rounding): the largest multiplier present in its
  // samples, or, where a few multipliers do not explain them, least squares on the logarithm of
  // its per-revolution amplitude.
  std::vector<double> log_amplitude;
  const std::size_t first = out.perturbation_amplitude_m.size() >= 6 ? 2 : 0;
  double fit_from = 0.0, fit_to = 0.0;
  for (std::size_t j = first; j < out.perturbation_amplitude_m.size(); ++j) {
    const double tj = out.revolution_time_s[j];
    if (out.lost_contact && tj - tau > out.contact_loss_time_s) break;
    const double a = out.perturbation_amplitude_m[j];
    if (!(a > 1e-9 * o.initial_displacement_m)) break;
    if (log_amplitude.empty()) fit_from = tj - tau;
    fit_to = tj;
    log_amplitude.push_back(std::log(a));
  }
  std::vector<std::vector<double>> samples;
  for (std::size_t i = 0; i < samples_all.size(); ++i)
    if (sample_time_s[i] > fit_from && sample_time_s[i] <= fit_to + 0.5 * h &&
        !(out.lost_contact && sample_time_s[i] >= out.contact_loss_time_s))
      samples.push_back(samples_all[i]);
  const int count = static_cast<int>(log_amplitude.size());
  const double revolution_s = tau;
  if (const auto multiplier = dominant_multiplier(samples)) {
    out.growth_rate_per_s = multiplier->growth_per_period / (static_cast<double>(sample_steps) * h);
    out.growth_components = multiplier->components;
    out.growth_settled = true;
  } else if (count >= 2) {
    out.growth_rate_per_s = index_slope(log_amplitude) / revolution_s;
    out.growth_settled = slope_settled(log_amplitude);
  }
  out.chatter = out.status == SimulationStatus::kRunaway || out.growth_rate_per_s > 0.0 ||
                (count < 2 && out.lost_contact);
  // (A runaway, or a loss of contact before any fit, is chatter whatever the estimate.)
  if (out.status == SimulationStatus::kRunaway || (count < 2 && out.lost_contact))
    out.growth_settled = true;
  return out;
}

}  // namespace cutdyn
