// Feed drives under the cutting load (models.md S1.7; docs/models/feed-drive.md).
//
// A feed axis moves the cutter relative to the workpiece along its direction n (feed: +x). The
// cut resists that motion with Fn = −F·n, F the force on the cutter (eq. 11 as a projection,
// the decision of models.md: in up-milling Fn > 0, in down-milling the cut can pull the axis,
// Fn < 0). The transmission turns Fn into the load torque on the motor shaft, lever-arm form
// Mc = (d/2)·iΣ·Fn + Mc0 (eq. 12) or ball-screw form Mc = Fn·p/(2π·η·i) + Mc0, with the idle
// torque Mc0 opposing the motion. Two drive models:
// * static characteristic (eq. 13): Ω(t) = Ω0 − Mc(t)/|β|, speed drop ΔΩ = Mc/|β|, static
//   error δ = Mc/(Ω0·|β|);
// * dynamic: motor and load inertia J, viscous loss b, a PI speed loop with a torque (current)
//   limit and anti-windup: J·dΩ/dt = Te − Mc(t) − b·Ω, Te = sat(Kp·e + Ki·∫e), e = Ω0 − Ω;
//   the ripple then depends on the frequency of the load.
// The non-uniformity coefficient kδ = (Ωmax − Ωmin)/(Ωmax + Ωmin) (eq. 1, decision) has the
// verdicts kδ <= 0.2 acceptable, > 0.4 unstable drive; δ <= 10 % is required. The table's
// position error is the integral of the speed deviation times the travel per motor radian.
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
  /// Load torque Mc for an axis force Fn (N) while moving forward, N·m [Ermolaev2020, eq. 12].
  double load_torque(double axis_force_n) const;
  /// Torque per newton of axis force (without Mc0): (d/2)·iΣ or p/(2π·η·i).
  double torque_per_newton() const;
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

enum class Verdict { kAcceptable, kMarginal, kUnstable };
const char* to_string(Verdict v);
/// kδ <= 0.2 acceptable, 0.2 < kδ <= 0.4 marginal, > 0.4 unstable [Ermolaev2020, p. 15].
Verdict nonuniformity_verdict(double k_delta);

struct FeedDriveResult {
  // Traces, at the force trace's instants.
  std::vector<double> time_s, axis_force_n, load_torque_nm, speed_rad_s, motor_torque_nm,
      position_error_m;
  // Summary over the whole trace.
  double commanded_speed_rad_s = 0.0;  // Ω0
  /// Ω0 > 0. An axis that does not move (across the feed) has no kδ or δ: they stay 0.
  bool moving = false;
  double mean_load_torque_nm = 0.0;
  double torque_ripple_nm = 0.0;    // ΔMc = (max − min)/2
  double speed_ripple_rad_s = 0.0;  // ΔΩ = (max − min)/2
  double k_delta = 0.0;             // (Ωmax − Ωmin)/(Ωmax + Ωmin)
  Verdict k_delta_verdict = Verdict::kAcceptable;
  double static_error = 0.0;    // δ = mean Mc/(Ω0·|β|) (static model; the PI loop removes it)
  bool static_error_ok = true;  // δ <= 10 %
  /// Peak-to-peak of the table's position error about uniform motion at the mean actual
  /// speed: travel per radian × ∫(Ω − Ω̄) dt (the mean speed error is δ).
  double position_error_pp_m = 0.0;
};

/// The drive of `axis` under the force on the cutter (time_s, fx, fy, fz; equal lengths, time
/// increasing) at the commanded table speed `feed_speed_m_per_s`. The dynamic model starts
/// at the steady state under the mean load (or under the first sample's load). Throws
/// cutdyn::InvalidInput on bad input.
FeedDriveResult simulate_feed_drive(const FeedAxis& axis, const std::vector<double>& time_s,
                                    const std::vector<double>& fx_n,
                                    const std::vector<double>& fy_n,
                                    const std::vector<double>& fz_n, double feed_speed_m_per_s,
                                    bool start_at_mean_load = true);

/// Torque ripple (half-range) for an axis force between f_min and f_max along a force at the
/// angle θ to the axis: ΔMc = ½·T'·cos θ·(Fmax − Fmin), T' the torque per newton; for the
/// lever form this is eq. 14, ΔMc = ¼·d·iΣ·cos θ·(Fmax − Fmin).
double torque_ripple(const Transmission& t, double force_min_n, double force_max_n,
                     double angle_rad);

}  // namespace cutdyn
