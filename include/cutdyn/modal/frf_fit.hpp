// Modal fitting: the modes (natural frequency, damping, modal stiffness) of a measured
// receptance, for a case file's [[modes]].
//
// Model fitted over a band of the table (docs/models/modal-fitting.md §1), s = iω:
//   G(ω) = Σ_r [ A_r/(s − λ_r) + A_r*/(s − λ_r*) ] + lower(ω) + upper(ω)      (m/N)
// with poles λ_r = −ζ_r·ωn_r + i·ωn_r·sqrt(1 − ζ_r²) and complex residues A_r [Ewins2000,
// ch. 2]; lower = −L2/ω² + i·L3/ω³ and upper = U0 + i·ω·U1 − ω²·U2 stand for the modes below
// and above the band: the classical residual mass and flexibility [Ewins2000, ch. 4] and the
// next term of each one's series (a decision, docs/models/modal-fitting.md §1). A real
// (proportionally damped) mode has A = −i·ωn²/(2·k·ωd), ωd = ωn·sqrt(1 − ζ²), which is the
// receptance 1/(k(1 − r² + 2iζr)) of cutdyn's Mode.
//
// Method (§2–§4): poles of the least-squares complex-frequency (LSCF) estimator over model
// orders 1…n [Guillaume2003; Peeters2004], a stabilisation diagram, then all parameters
// refined by Levenberg–Marquardt on the relatively weighted complex error [Marquardt1963].
#pragma once

#include <array>
#include <complex>
#include <optional>
#include <string>
#include <vector>

#include "cutdyn/modal/measured_frf.hpp"
#include "cutdyn/modal/modal_model.hpp"

namespace cutdyn {

/// The most modes a fit may be asked for (its cost grows with the cube of the order).
inline constexpr int kMaxFitModes = 40;

struct FrfFitOptions {
  int modes = 0;  // number of modes to fit; 0 = chosen from the diagram
  std::optional<double> lo_hz = std::nullopt;  // band to fit; default: the whole table
  std::optional<double> hi_hz = std::nullopt;
  int max_modes = 12;     // upper limit of the automatic choice (and of the diagram's orders)
  bool residuals = true;  // fit residual terms for the modes outside the band (FrfResiduals)
};

/// One fitted mode.
struct FittedMode {
  double natural_hz = 0.0;
  double natural_rad_s = 0.0;      // ωn = |λ|
  double damping_ratio = 0.0;      // ζ = −Re λ / |λ|
  double stiffness_n_per_m = 0.0;  // k = ωn²/(2·ωd·|A|), from the residue's magnitude
  std::complex<double> pole;       // λ, rad/s
  std::complex<double> residue;    // A, m/(N·s)
  /// Phase of A relative to the real-mode residue −i·|A|, degrees in (−180, 180]: 0 for a
  /// real (proportionally damped) mode.
  double residue_phase_deg = 0.0;
  /// RMS over the band of |G_r(ω)| / |G_measured(ω)|, G_r this mode's pair of terms: its share
  /// of the response on the scale of the fit error.
  double contribution = 0.0;
  /// Standard uncertainties (1σ) from the fit's covariance (docs/models/modal-fitting.md §4.2)
  /// and the covariance of (natural_hz, damping_ratio, stiffness_n_per_m), in those units.
  double natural_hz_sigma = 0.0, damping_ratio_sigma = 0.0, stiffness_sigma_n_per_m = 0.0;
  std::array<std::array<double, 3>, 3> covariance{};
};

/// A physical pole (0 < ζ < 0.5, inside the band) of the LSCF estimate at one model order.
struct StabilisationPoint {
  int order = 0;  // number of poles of the estimate (denominator degree)
  double natural_hz = 0.0;
  double damping_ratio = 0.0;
  /// A physical pole of the order before lies within 1 % in frequency and 5 % in damping.
  bool stable = false;
};

/// The residual terms fitted (docs/models/modal-fitting.md §1), 0 when unused, ω in rad/s:
///   lower (modes below the band):  −L2/ω² + i·L3/ω³
///   upper (modes above the band):  U0 + i·ω·U1 − ω²·U2
/// L2 is the inverse of the classical residual mass (−1/(M·ω²)), U0 the residual flexibility;
/// L3, U1 and U2 are the next terms of the series of the outside modes' receptance; an explicit
/// pole beyond an edge (FrfFit::outside_modes) takes their place on its side, and they are 0.
struct FrfResiduals {
  bool lower_used = false;  // only when the band starts above 0 Hz
  bool upper_used = false;
  double l2_per_kg = 0.0;
  double l3_per_kg_s = 0.0;
  double u0_m_per_n = 0.0;
  double u1_m_s_per_n = 0.0;
  double u2_m_s2_per_n = 0.0;
};

/// The noise of the table as the fit's residuals show it (docs/models/modal-fitting.md §4.1):
/// each part (real, imaginary) of a point scatters with the standard deviation
/// sqrt((proportional·|G|)² + floor²).
struct FrfNoise {
  double proportional = 0.0;   // relative, e.g. 0.01 for 1 %
  double floor_m_per_n = 0.0;  // additive, m/N
};

struct FrfFit {
  Direction direction = Direction::kX;
  double lo_hz = 0.0, hi_hz = 0.0;  // the band fitted
  int points = 0;                   // table points in the band
  bool automatic = false;           // the number of modes was chosen from the diagram
  std::vector<FittedMode> modes;    // by increasing natural frequency
  /// Explicit poles outside the band that stand for modes beyond it (§1.1): part of the fit
  /// (and of fitted_frf inside the band), not of `modes` or `model`.
  std::vector<FittedMode> outside_modes;
  FrfResiduals residuals;
  double rms_relative_error = 0.0;  // sqrt(mean |G_fit − G|² / |G|²) over the band
  /// The same error of `model` alone (the modes, complex residues kept, without the residual
  /// terms): what the time-domain methods of a case with [[frf]] tables use (§10).
  double model_rms_relative_error = 0.0;
  FrfNoise noise;                   // estimated from the residuals
  /// The fit was weighted for the noise's floor (§4.1) rather than relatively.
  bool noise_weighted = false;
  /// The fit was weighted by the table's coherence (§4.3), which then stands for the noise's
  /// shape (the floor's weights of §4.1 are not applied).
  bool coherence_weighted = false;
  int iterations = 0;               // Levenberg–Marquardt iterations of the final fit
  bool converged = false;
  std::vector<StabilisationPoint> stabilisation;
  std::vector<std::string> warnings;
  /// What the automatic choice did that asks nothing of the user: the poles it dropped as
  /// standing for no mode (noise, a second pole on one mode), each with its reason.
  std::vector<std::string> notes;
  /// The modes (ωn, ζ, k and the residue's phase φ) acting in `direction`: one structure for
  /// every method (docs/models/modal-fitting.md §10).
  ModalModel model;
};

/// Fits modes to `frf` over the band of `options`. Throws InvalidInput (where() = "fit",
/// problems naming the field: "frf.frequency_hz[3]", "band", "modes") for an invalid table, a
/// band with fewer than 10 table points, or more modes than a quarter of the band's points; a
/// fit that finds nothing or fits badly is reported in `warnings`, never thrown.
FrfFit fit_modes(const MeasuredFrf& frf, Direction direction, const FrfFitOptions& options = {});

/// The fitted model (complex residues, and the residual terms inside the fitted band only —
/// they stand for modes outside it) at `frequency_hz` (finite, >= 0, strictly increasing).
MeasuredFrf fitted_frf(const FrfFit& fit, const std::vector<double>& frequency_hz);

}  // namespace cutdyn
