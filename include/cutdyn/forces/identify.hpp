// Milling cutting coefficients identified from measured mean forces (the average-force
// method of [Altintas2012, ch. 2]); docs/models/identification.md.
//
// Tooth angle φ measured clockwise from +y (as stability/milling.hpp and the milling
// simulation), chip h = c·sin φ, and per tooth in cut the force on the cutter
//     Fx = −Ft·cos φ − Fr·sin φ,   Fy = Ft·sin φ − Fr·cos φ,   Fz = Fa,
//     Ft = Kt·a·h + Kte·a,   Fr = Kr·a·h + Kre·a,   Fa = Ka·a·h + Kae·a.
// Averaged over a revolution, z evenly or unevenly spaced straight or helical teeth with the
// window [φst, φex] give mean forces linear in the feed per tooth c:
//     F̄/a = (z/2π)·(c·A·(Kt, Kr) + B·(Kte, Kre)),   F̄z/a = (z/2π)·(c·Ka·Is + Kae·(φex − φst)),
// with A and B the 2×2 window matrices of WindowIntegrals. A straight line of F̄/a against c
// per direction, fitted by least squares over test cuts at several feeds, gives slope and
// intercept, hence the six coefficients, with standard errors and Student-t 95 % intervals
// [Abramowitz1964, 26.7.3–26.7.4].
#pragma once

#include <Eigen/Dense>
#include <optional>
#include <string>
#include <vector>

namespace cutdyn {

/// The cut the test forces come from: z teeth and the engagement window (rad, 0 <= entry <
/// exit <= π), e.g. from engagement_window(a_e/D, down) of stability/milling.hpp.
struct IdentifyCut {
  int teeth = 2;
  double entry_rad = 0.0;
  double exit_rad = 3.141592653589793;

  /// Problems as "cut.field = value unit: rule"; empty when valid.
  std::vector<std::string> validate() const;
};

/// The coefficients of the linear milling force law (SI: Pa = N/m², N/m). The axial pair is
/// zero when not identified.
struct CuttingCoefficients {
  double kt_pa = 0.0, kr_pa = 0.0, ka_pa = 0.0;
  double kte_n_per_m = 0.0, kre_n_per_m = 0.0, kae_n_per_m = 0.0;
};

/// The window's integrals (docs/models/identification.md, "Closed forms"):
/// Isc = ∫sinφ·cosφ dφ, Iss = ∫sin²φ dφ, Ic = ∫cosφ dφ, Is = ∫sinφ dφ over [φst, φex].
/// chip = [[−Isc, −Iss], [Iss, −Isc]] maps (Kt, Kr) and edge = [[−Ic, −Is], [Is, −Ic]] maps
/// (Kte, Kre) to (F̄x, F̄y)·2π/(z·a) (the chip one per unit c). Both are a rotation times a
/// gain, √det.
struct WindowIntegrals {
  double isc = 0.0, iss = 0.0, ic = 0.0, is = 0.0, width_rad = 0.0;
  Eigen::Matrix2d chip_matrix() const;
  Eigen::Matrix2d edge_matrix() const;
};
WindowIntegrals window_integrals(double entry_rad, double exit_rad);

/// Closed-form mean force over a revolution (N), (F̄x, F̄y, F̄z), of `cut` at feed per tooth
/// c (m) and axial depth a (m). Preconditions: cut.validate() empty, c >= 0, a >= 0.
Eigen::Vector3d mean_milling_force(const IdentifyCut& cut, const CuttingCoefficients& k,
                                   double feed_per_tooth_m, double depth_m);

/// One test cut: its mean forces on the cutter over whole revolutions.
struct MeanForce {
  double feed_per_tooth_m = 0.0;  // c, > 0
  double depth_m = 0.0;           // a, the axial depth of cut, > 0
  double fx_n = 0.0, fy_n = 0.0;  // mean force on the cutter (x = feed direction)
  std::optional<double> fz_n;     // axial, along +z where Fa > 0 (all samples or none)
  std::string label;              // where it came from ("forces.csv:4"), for messages
  int revolutions = 0;            // whole revolutions averaged (0: a mean given as such)
};

/// An identified coefficient (SI) and its uncertainty from the fit.
struct IdentifiedCoefficient {
  double value = 0.0;
  /// false without residual degrees of freedom (one sample per distinct feed and only two
  /// feeds): std_error and the interval are then 0 and meaningless.
  bool uncertainty_known = false;
  double std_error = 0.0;
  double ci95_low = 0.0, ci95_high = 0.0;  // value ∓ t(0.975, dof)·std_error
  /// Known uncertainty and the 95 % interval excludes zero.
  bool determined() const { return uncertainty_known && (ci95_low > 0.0 || ci95_high < 0.0); }
};

/// Measured minus fitted mean force of one sample (N).
struct SampleResidual {
  std::string label;
  double fx_n = 0.0, fy_n = 0.0;
  std::optional<double> fz_n;
};

struct CoefficientFit {
  IdentifiedCoefficient kt, kr, kte, kre;        // Pa, Pa, N/m, N/m
  std::optional<IdentifiedCoefficient> ka, kae;  // with fz in every sample
  std::vector<SampleResidual> residuals;         // one per sample, in order
  double r_squared_x = 0.0, r_squared_y = 0.0;   // of F̄/a against c, per direction
  std::optional<double> r_squared_z;
  /// Residual standard deviation of F̄/a per direction over the rms of |(F̄x, F̄y)|/a.
  double relative_residual = 0.0;
  int samples = 0, distinct_feeds = 0;
  int degrees_of_freedom = 0;  // per direction: samples − 2
  double t_quantile = 0.0;     // t(0.975, dof); 0 without dof
  /// Gains √det of the window's chip and edge matrices over slotting's (π/2 and 2): the
  /// coefficients' errors are the force errors amplified by their inverse.
  double chip_gain_ratio = 0.0, edge_gain_ratio = 0.0;
  std::vector<std::string> warnings;

  CuttingCoefficients coefficients() const;
};

/// Fits the coefficients to `samples` (linear least squares of F̄/a against c, one line per
/// direction, docs/models/identification.md). Throws cutdyn::InvalidInput for an invalid cut,
/// a sample with a non-positive or non-finite feed or depth, non-finite forces, fz in some
/// samples only, or fewer than two distinct feeds. Warnings: fewer than three distinct feeds,
/// feeds close together, no degrees of freedom, a narrow window, a coefficient not determined
/// (its 95 % interval includes zero), a negative coefficient, a poor fit.
CoefficientFit identify_coefficients(const IdentifyCut& cut, const std::vector<MeanForce>& samples);

/// A force record of one test cut at constant feed, depth and spindle speed.
struct ForceSeries {
  std::vector<double> time_s;  // strictly increasing
  std::vector<double> fx_n, fy_n;
  std::vector<double> fz_n;  // empty: no axial force
  double rpm = 0.0;
  double feed_per_tooth_m = 0.0;
  double depth_m = 0.0;
  std::string label;  // e.g. the file name, for messages
};

/// The mean forces over the largest whole number N of revolutions (60/rpm s each) that fits in
/// the record, the last N·T seconds (the end of a record is the settled cut; trim an exit
/// from the cut off first): trapezoidal rule over [t_end − N·T, t_end], the value at the start
/// interpolated linearly. Throws cutdyn::InvalidInput (where = label) for mismatched lengths,
/// fewer than 2 samples, non-finite values, time not strictly increasing, non-positive rpm,
/// feed or depth, or a record shorter than one revolution.
MeanForce mean_over_revolutions(const ForceSeries& series);

/// mean_over_revolutions of each record (one per feed), every record's problems together.
std::vector<MeanForce> mean_forces(const std::vector<ForceSeries>& series);

/// Quantile of Student's t distribution with `dof` >= 1 degrees of freedom at probability p in
/// (0, 1), from its exact distribution function for whole dof [Abramowitz1964, 26.7.3–26.7.4].
double student_t_quantile(double p, int dof);

}  // namespace cutdyn
