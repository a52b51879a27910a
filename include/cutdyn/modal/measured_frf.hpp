// A frequency response function given as a table (measured, or sampled from modes).
//
// Receptance G(f) = displacement / force in m/N at strictly increasing frequencies f (Hz).
// Between two points the real and imaginary parts are interpolated linearly; outside the
// table there is no value (a stability method that needs one there is told so).
#pragma once

#include <Eigen/Dense>
#include <complex>
#include <optional>
#include <string>
#include <vector>

#include "cutdyn/modal/modal_model.hpp"

namespace cutdyn {

struct MeasuredFrf {
  std::vector<double> frequency_hz;                      // strictly increasing, >= 0, finite
  std::vector<std::complex<double>> receptance_m_per_n;  // one per frequency, finite
  /// The ordinary coherence γ² (0…1) of each point when the measurement gave it, else empty:
  /// how much of the response the force explains there, which sets the point's noise (the fit
  /// weighs by it: docs/models/modal-fitting.md §4.3).
  std::vector<double> coherence;

  /// Problems as "frequency_hz[i] = value Hz: rule"; empty when valid (at least 3 points).
  std::vector<std::string> validate() const;
  double min_hz() const { return frequency_hz.empty() ? 0.0 : frequency_hz.front(); }
  double max_hz() const { return frequency_hz.empty() ? 0.0 : frequency_hz.back(); }
  bool covers(double f_hz) const { return f_hz >= min_hz() && f_hz <= max_hz(); }
  /// G at f (linear interpolation of real and imaginary parts). Precondition: covers(f).
  std::complex<double> at(double f_hz) const;
};

/// a + b on a's frequencies inside the band both cover (tool and workpiece compliances add for
/// the relative displacement). Throws cutdyn::InvalidInput when the bands do not overlap in at
/// least 3 of a's points.
MeasuredFrf add_frf(const MeasuredFrf& a, const MeasuredFrf& b);

/// The measured receptances of a structure: direct in x and in y, and the cross receptance
/// (x response to a y force, taken equal to the reverse) where it was measured; plus modes
/// fitted to them, which the time-domain methods use.
struct MeasuredStructure {
  std::optional<MeasuredFrf> xx, yy, xy;
  ModalModel fitted;  // modes fitted to xx and yy
  /// How the modes were had, one line per direct table ("x: 2 modes fitted over 50–3000 Hz,
  /// RMS error 1.4 %"), and the fit's warnings: what a report shows of the structure.
  std::vector<std::string> fit_notes, fit_warnings;
  /// Receptance matrix over `directions` at ω (rad/s): the tables interpolated, zero outside
  /// each table's band.
  Eigen::MatrixXcd at(const std::vector<Direction>& directions, double omega_rad_s) const;
  /// The same, written into g (resized, its storage reused).
  void at(const std::vector<Direction>& directions, double omega_rad_s, Eigen::MatrixXcd& g) const;
  const MeasuredFrf* direct(Direction d) const { return d == Direction::kX ? ptr(xx) : ptr(yy); }
  /// The highest frequency any table reaches (Hz).
  double max_hz() const;

 private:
  static const MeasuredFrf* ptr(const std::optional<MeasuredFrf>& f) { return f ? &*f : nullptr; }
};

/// The receptance over `directions` at ω of the measured tables plus the modes of `given`
/// (a structure measured in part and modelled in part).
Eigen::MatrixXcd combined_receptance(const ModalModel& given, const MeasuredStructure& measured,
                                     const std::vector<Direction>& directions, double omega_rad_s);
/// The same, written into g (resized, its storage reused).
void combined_receptance(const ModalModel& given, const MeasuredStructure& measured,
                         const std::vector<Direction>& directions, double omega_rad_s,
                         Eigen::MatrixXcd& g);

/// The modes of `given` and those fitted to `measured` (if any): what the time-domain methods
/// take of a structure measured in part or in whole.
ModalModel with_fitted_modes(const ModalModel& given,
                             const std::optional<MeasuredStructure>& measured);

/// The receptance of `model` in `direction` sampled at `frequency_hz`.
MeasuredFrf sample_frf(const ModalModel& model, Direction direction,
                       const std::vector<double>& frequency_hz);

/// n frequencies evenly spaced from lo_hz to hi_hz inclusive (n >= 2).
std::vector<double> linear_frequencies(double lo_hz, double hi_hz, int n);

}  // namespace cutdyn
