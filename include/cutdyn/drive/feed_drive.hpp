// Feed drives under the cutting load ([Ermolaev2020]; docs/models/feed-drive.md).
//
// A feed axis moves the cutter relative to the workpiece along its direction n (feed: +x). The
// cut resists that motion with Fn = −F·n, F the force on the cutter (eq. 11 as a projection, a
// decision of docs/models/feed-drive.md: in up-milling Fn > 0, in down-milling the cut can pull
// the axis, Fn < 0). The transmission turns Fn into the load torque on the motor shaft, lever-arm
// form Mc = (d/2)·iΣ·Fn + Mc0 (eq. 12) or ball-screw form Mc = Fn·p/(2π·η·i) + Mc0, with the idle
// torque Mc0 opposing the motion; a load that aids the motion (Fn < 0) back-drives the screw and
// passes through the back-driving efficiency η' = 2 − 1/η instead: Mc = Fn·p·η'/(2π·i) + Mc0.
// Two drive models:
// * static characteristic (eq. 13): Ω(t) = Ω0 − Mc(t)/|β|, speed drop ΔΩ = Mc/|β|, static
//   error δ = Mc/(Ω0·|β|);
// * dynamic: motor and load inertia J, viscous loss b, a PI speed loop with a torque (current)
//   limit and anti-windup: J·dΩ/dt = Te − Mc(t) − b·Ω, Te = sat(Kp·e + Ki·∫e), e = Ω0 − Ω;
//   the ripple then depends on the frequency of the load.
// The non-uniformity coefficient kδ = ΔΩ/Ω̄ = 2(Ωmax − Ωmin)/(Ωmax + Ωmin) (eq. 1, range over
// mean) has the verdicts kδ <= 0.2 acceptable, 0.2 < kδ <= 0.4 marginal, above 0.4 beyond the
// source's limit for regulated drives (the source says the drive "loses stability" there; these
// linear models cannot, so the verdict says which limit is exceeded). δ = (Ω0 − Ω̄)/Ω0 <= 10 % is
// required. The table's position error is the integral of the speed deviation times the travel
// per motor radian. Every summary is of the periodic steady state, detected from the speed trace
// at the forcing period (docs/models/feed-drive.md); a run that does not reach it says so.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cutdyn/drive/motor_currents.hpp"

namespace cutdyn {

/// How the motor drives the table.
struct Transmission {
  enum class Kind { kLeverArm, kBallScrew };
  Kind kind = Kind::kBallScrew;
  // Lever-arm form (eq. 12): the output element's diameter d and the total ratio iΣ
  // (output speed / motor speed).
  double output_diameter_m = 0.0;
  double ratio = 1.0;
  // Ball-screw form: lead p, efficiency η, gear reduction i (motor speed / screw speed).
  double lead_m = 0.0;
  double efficiency = 1.0;
  double gear_ratio = 1.0;
  double idle_torque_nm = 0.0;  // Mc0

  std::vector<std::string> validate() const;
  /// Table travel per radian of the motor: (d/2)·iΣ or p/(2π·i), m/rad.
  double travel_per_rad() const;
  /// Load torque Mc for an axis force Fn (N) while moving forward, N·m [Ermolaev2020, eq. 12]:
  /// torque_per_newton(Fn)·Fn + Mc0.
  double load_torque(double axis_force_n) const;
  /// Torque per newton of a resisting axis force (without Mc0): (d/2)·iΣ or p/(2π·η·i).
  double torque_per_newton() const;
  /// Torque per newton for the axis force Fn: torque_per_newton() when Fn resists the motion
  /// (Fn >= 0); for an aiding force (Fn < 0) the ball screw is back-driven and passes the force
  /// through the back-driving efficiency η' = 2 − 1/η: p·η'/(2π·i). The lever form has no losses.
  double torque_per_newton(double axis_force_n) const;
  /// η' = 2 − 1/η (at most 1, negative for a self-locking screw, η < 0.5); 1 for the lever form.
  double back_driving_efficiency() const;
};

struct FeedDrive {
  enum class Model { kStatic, kDynamic };
  Transmission transmission;
  Model model = Model::kStatic;
  // Static characteristic: |β|, the slope of torque against speed, N·m·s/rad.
  double stiffness_nm_s_per_rad = 0.0;
  // Dynamic drive.
  double inertia_kg_m2 = 0.0;  // motor + load reflected to the motor shaft
  double viscous_nm_s_per_rad = 0.0;
  double kp_nm_s_per_rad = 0.0;  // speed-loop gains
  double ki_nm_per_rad = 0.0;
  double torque_limit_nm = 0.0;  // |Te| <= limit (the current limit × KT); 0: none

  std::vector<std::string> validate() const;
};

/// The load on one axis: its direction (unit vector in x, y, z) and the drive.
struct FeedAxis {
  std::string name = "x";
  double direction[3] = {1.0, 0.0, 0.0};
  FeedDrive drive;
  std::optional<PmsmMotor> motor;  // for phase currents
};

/// The non-uniformity verdicts of [Ermolaev2020, p. 15].
enum class Verdict { kAcceptable, kMarginal, kBeyondLimit };
/// "acceptable", "marginal", "beyond-limit" (the JSON's token).
const char* to_string(Verdict v);
/// What the verdict means, for people: "acceptable (≤ 0.2)", "marginal (0.2 … 0.4)",
/// "non-uniform beyond the source's 0.4 limit for regulated drives".
const char* describe(Verdict v);
/// kδ <= 0.2 acceptable, 0.2 < kδ <= 0.4 marginal, > 0.4 beyond the limit [Ermolaev2020, p. 15].
Verdict nonuniformity_verdict(double k_delta);
/// kδ = 2(Ωmax − Ωmin)/(Ωmax + Ωmin) [Ermolaev2020, eq. 1]. Where the mid-range speed is not
/// forward (Ωmax + Ωmin <= 0) the ratio has no meaning: it returns 2 (its value at Ωmin = 0),
/// beyond every limit; simulate_feed_drive then warns that the motor stalls or reverses.
double nonuniformity(double speed_min, double speed_max);

/// How the periodic steady state is found (docs/models/feed-drive.md).
struct SteadyStateOptions {
  /// The forcing period (s): the response is periodic at it in the steady state. 0: unknown,
  /// the dynamic drive's summary is then of the whole trace and marked as not checked.
  double period_s = 0.0;
  /// A period counts as steady when it differs from the next by at most this fraction of the
  /// speed's peak-to-peak in the last period (and the geometric tail of the differences too).
  double relative_tolerance = 0.01;
};

struct FeedDriveResult {
  // Traces, at the force trace's instants.
  std::vector<double> time_s, axis_force_n, load_torque_nm, speed_rad_s, motor_torque_nm,
      position_error_m;
  /// A speed loop with an integrator (dynamic, Ki > 0): the table's lag behind its programmed
  /// position that the cut's load causes, travel × (∫(Ω0 − Ω)dt − (Mc0 + b·Ω0)/Ki) — in the
  /// steady state travel·(Mc̄ − Mc0)/Ki plus the ripple's share; > 0 behind. Empty otherwise
  /// (the static characteristic and a P-only loop drift: their mean speed error is δ).
  std::vector<double> load_lag_m;
  // The periodic steady state: whole forcing periods from `steady_from_s` to the end of the
  // trace (the whole trace for the static model without a period, which has no transient of its
  // own, and for a dynamic drive without a period, which is then marked `steady_checked` false).
  bool steady_checked = false;  // a period was given and the detection ran
  bool steady = true;           // the response became periodic within the run
  double steady_from_s = 0.0;   // start of the summary window
  int steady_periods = 0;       // whole periods in the summary window (0: no period given)
  /// Largest change of Ω between the last two periods, rad/s (0 if not checked).
  double periodicity_change_rad_s = 0.0;
  /// Warnings: the steady state not reached, or not checked. Never a silent number.
  std::vector<std::string> warnings;
  // Summary over the steady window.
  double commanded_speed_rad_s = 0.0;  // Ω0
  /// Ω0 > 0. An axis that does not move (across the feed) has no kδ or δ: they stay 0.
  bool moving = false;
  double mean_load_torque_nm = 0.0;
  double torque_ripple_nm = 0.0;    // ΔMc = (max − min)/2
  double mean_speed_rad_s = 0.0;    // Ω̄, the time average
  double speed_ripple_rad_s = 0.0;  // (max − min)/2
  double k_delta = 0.0;             // 2(Ωmax − Ωmin)/(Ωmax + Ωmin)
  Verdict k_delta_verdict = Verdict::kAcceptable;
  /// δ = (Ω0 − Ω̄)/Ω0: for the static model mean Mc/(Ω0·|β|); for a PI loop ≈ 0; a P-only loop
  /// keeps the error (Mc̄ + b·Ω̄)/(Kp·Ω0).
  double static_error = 0.0;
  bool static_error_ok = true;  // δ <= 10 %
  /// Peak-to-peak of the table's position error about uniform motion at the mean actual
  /// speed: travel per radian × ∫(Ω − Ω̄) dt (the mean speed error is δ).
  double position_error_pp_m = 0.0;
  /// The load lag of largest magnitude over the steady window (signed); none without it.
  std::optional<double> load_lag_max_m;
};

/// The drive of `axis` under the force on the cutter (time_s, fx, fy, fz; equal lengths, time
/// increasing) at the commanded table speed `feed_speed_m_per_s`. The dynamic model starts
/// at the equilibrium under the mean load (or under the first sample's load): Ω = Ω0 with the
/// integrator carrying the torque, or for a P-only loop Ω = (Kp·Ω0 − Mc)/(Kp + b). The summary
/// is of the periodic steady state at `steady.period_s` (see FeedDriveResult). Throws
/// cutdyn::InvalidInput on bad input.
FeedDriveResult simulate_feed_drive(const FeedAxis& axis, const std::vector<double>& time_s,
                                    const std::vector<double>& fx_n,
                                    const std::vector<double>& fy_n,
                                    const std::vector<double>& fz_n, double feed_speed_m_per_s,
                                    bool start_at_mean_load = true,
                                    const SteadyStateOptions& steady = {});

/// Torque ripple (half-range) for an axis force between f_min and f_max along a force at the
/// angle θ to the axis: ΔMc = ½·T'·cos θ·(Fmax − Fmin), T' the torque per newton; for the
/// lever form this is eq. 14, ΔMc = ¼·d·iΣ·cos θ·(Fmax − Fmin).
double torque_ripple(const Transmission& t, double force_min_n, double force_max_n,
                     double angle_rad);

}  // namespace cutdyn
