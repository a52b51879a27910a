// One milling process, described once: the structure, the cutter, its engagement and the
// force law. The stability methods (stability/milling.hpp) and the time-domain simulation
// (simulate/milling_simulation.hpp) both take it; the case file's [tool], [operation],
// [cutting] and [force_law] tables are read into it.
//
// Tooth j of z sits at the angle φj(t) = Ω·t − Σ pitch, measured clockwise from the +y axis; it
// cuts inside the engagement window [φst, φex] ⊂ [0, π] with the chip h = s_z·sin φ plus the
// regeneration (docs/models/milling-stability.md, docs/models/milling-simulation.md).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cutdyn/modal/measured_frf.hpp"
#include "cutdyn/modal/modal_model.hpp"

namespace cutdyn {

/// The tooth's engagement window (rad, clockwise from +y).
struct EngagementWindow {
  double entry_rad = 0.0, exit_rad = 0.0;
};

/// The window for a radial immersion a_e/D: down-milling [acos(2a_e/D − 1), π], up-milling
/// [0, acos(1 − 2a_e/D)] [Altintas2012, ch. 2].
EngagementWindow engagement_window(double radial_immersion, bool down_milling);

/// The cutter ([tool]).
struct MillingTool {
  int teeth = 2;            // z
  double diameter_m = 0.0;  // D, needed with a helix
  double helix_rad = 0.0;   // β, 0 <= β < π/2
  /// Uneven pitch: z angles, pitch_rad[j] the angle by which tooth j trails tooth j − 1 (tooth
  /// 0 trails the last one), adding up to 2π. Empty: evenly spaced teeth.
  std::vector<double> pitch_rad;

  std::vector<std::string> validate() const;
  bool even_pitch() const { return pitch_rad.empty(); }
  std::vector<double> pitch_angles() const;  // pitch_rad, or z equal angles
  /// Angle by which the flute at depth a lags the tooth tip: 2·a·tanβ/D [Ermolaev2020].
  double lag_angle(double depth_m) const;
  /// Axial slices at depth a for the stability methods: lag of at most 0.5° each (1 for
  /// straight teeth).
  int slices(double depth_m) const;
};

/// How the cutter engages the work ([operation]): a radial immersion and a direction, or the
/// window itself.
struct MillingEngagement {
  double radial_immersion = 1.0;  // a_e / D, 0 < . <= 1
  bool down_milling = true;
  /// The window given directly (rad, 0 <= entry < exit <= π): when both are set they replace
  /// radial_immersion and down_milling, which then play no part.
  std::optional<double> entry_rad, exit_rad;

  std::vector<std::string> validate() const;
  EngagementWindow window() const;
  double entry_angle() const { return window().entry_rad; }
  double exit_angle() const { return window().exit_rad; }
  /// The radial width of the window as a fraction of D, (cos φst − cos φex)/2: a_e/D.
  double engaged_immersion() const;
};

/// Linear mechanistic law per unit width [Altintas2012, ch. 2]: Ft = Kt·b·h + Kte·b,
/// Fr = Kr·b·h + Kre·b.
struct MechanisticForceLaw {
  double kt_pa = 0.0;  // tangential cutting coefficient, N/m²
  double kr_pa = 0.0;  // radial cutting coefficient, N/m²
  double kte_n_per_m = 0.0;
  double kre_n_per_m = 0.0;

  std::vector<std::string> validate() const;
};

/// S1 law ([Ermolaev2020]; docs/models/milling-simulation.md, "Force laws"): P = c·U with
/// T2·dU/dt + U = X (the chip thickness), the flank contact force F = P0·e^(−X/T1); P at the
/// angle φrez and F at φskv from the tangent (towards the cutter's centre).
struct ErmolaevForceLaw {
  /// What U lags (docs/models/ermolaev2020-figures.md):
  /// kChip — the chip while the tooth cuts, U relaxing to 0 out of the cut (physical);
  /// kUnwindowed — X = s_z·sin θ around the whole revolution (negative out of the cut; the
  /// chip inside the window), the window applied to c·U after the lag, as [Ermolaev2020]
  /// eqs. 3 and 5 print it: the reading that reproduces the source's fig. 6a.
  enum class LagInput { kChip, kUnwindowed };

  double c_n_per_m = 0.0;  // cutting stiffness of the whole engaged flute, N/m
  double t2_s = 0.0;       // chip-formation time constant (0: no lag)
  double p0_n = 0.0;       // flank contact force scale, N
  double t1_m = 1.0;       // chip thickness over which the contact force falls by e
  double phi_rez_rad = 0.0;
  double phi_skv_rad = 0.0;
  LagInput lag_input = LagInput::kChip;
  /// Instead of t2_s: the lag as the cutter's rotation during T2, ω·T2 (rad), so that T2 scales
  /// with the tooth's passage (T2 = ℓ/v, a chip-formation length over the cutting speed).
  std::optional<double> t2_angle_rad{};

  /// T2 at the spindle speed ω (rad/s): t2_angle_rad/ω when given, else t2_s.
  double time_constant_s(double spindle_rad_s) const {
    return t2_angle_rad ? *t2_angle_rad / spindle_rad_s : t2_s;
  }
  std::vector<std::string> validate() const;
};

struct MillingProcess {
  ModalModel modal;  // modes in x (feed) and y; none: a rigid cutter (simulation only)
  /// Measured receptances, beside or instead of `modal`: the zero-order and multi-frequency
  /// methods take the tables (plus `modal`'s response), the others the fitted modes.
  std::optional<MeasuredStructure> measured;
  MillingTool tool;
  MillingEngagement engagement;
  MechanisticForceLaw cutting;  // the linear law: the stability methods use it
  /// The S1 law: when given, the simulation uses it instead of `cutting`.
  std::optional<ErmolaevForceLaw> s1_law;

  /// What any use needs: valid modes in x and y, tool, engagement and laws (coefficients may
  /// be 0). Problems name the member ("tool.teeth", "engagement.entry_rad", …).
  std::vector<std::string> validate() const;
  /// validate() and what a stability analysis needs besides: at least one mode, every mode
  /// damped, Kt > 0.
  std::vector<std::string> validate_for_stability() const;
  /// The modes the time-domain methods use: `modal` and the modes fitted to `measured`.
  ModalModel structure_modes() const;
};

}  // namespace cutdyn
