// The modal fit's report rendered: the text and figure of `cutdyn fit`
// (docs/models/modal-fitting.md).
#include <fmt/format.h>

#include <complex>
#include <numbers>
#include <string>

#include "cutdyn/app/detail/text.hpp"
#include "cutdyn/app/render.hpp"

namespace cutdyn::app {

void write_text(std::ostream& out, const FitJobReport& r) {
  const FrfFit& f = r.fit;
  const MeasuredFrf& t = r.read.frf;
  out << "cutdyn fit: " << r.source << " (" << to_string(r.read.format) << ", "
      << to_string(r.read.quantity) << (r.read.units.empty() ? "" : ", " + r.read.units) << "; "
      << t.frequency_hz.size() << " points, " << human(t.min_hz()) << "–" << human(t.max_hz())
      << " Hz)\n";
  out << fmt::format("  {} mode{} in {}{} over {}–{} Hz ({} points), RMS relative error {} %{}\n",
                     f.modes.size(), f.modes.size() == 1 ? "" : "s", to_string(f.direction),
                     f.automatic ? " (chosen from the stabilisation diagram)" : "", human(f.lo_hz),
                     human(f.hi_hz), f.points, human(100.0 * f.rms_relative_error, 3),
                     f.converged ? "" : " (not converged)");
  for (const std::string& n : f.notes) out << "  note: " << n << "\n";
  if (f.modes.empty()) return;
  out << fmt::format("\n  {:>4}  {:>12}  {:>13}  {:>17}  {:>14}\n", "mode", "natural_hz",
                     "damping_ratio", "stiffness_n_per_m", "residue phase");
  for (std::size_t i = 0; i < f.modes.size(); ++i) {
    const FittedMode& m = f.modes[i];
    out << fmt::format("  {:>4}  {:>12}  {:>13}  {:>17}  {:>13}°\n", i + 1, human(m.natural_hz, 6),
                       human(m.damping_ratio, 4), human(m.stiffness_n_per_m, 4),
                       human(m.residue_phase_deg, 3));
  }
}

// Magnitude (log) and phase of the measured and the fitted FRF, the modes marked.
io::PlotFigure figure(const FitJobReport& r) {
  const auto series = [](const MeasuredFrf& t, const char* title, const char* style,
                         const char* colour, bool phase) {
    io::PlotSeries s{title, t.frequency_hz, {}, style, false, colour};
    for (const std::complex<double>& g : t.receptance_m_per_n)
      s.y.push_back(phase ? std::arg(g) * 180.0 / std::numbers::pi : std::abs(g));
    return io::envelope(s, 2000);
  };
  std::vector<io::PlotMark> marks;
  for (const FittedMode& m : r.fit.modes)
    marks.push_back({m.natural_hz, human(m.natural_hz, 4) + " Hz"});
  io::PlotSpec magnitude, phase;
  magnitude.x_label = phase.x_label = "frequency (Hz)";
  magnitude.y_label = "receptance magnitude (m/N)";
  magnitude.y_log = true;
  phase.y_label = "phase (°)";
  for (bool p : {false, true}) {
    io::PlotSpec& panel = p ? phase : magnitude;
    panel.series.push_back(series(r.read.frf, "measured", "lines", "#999999", p));
    panel.series.push_back(series(r.fitted, "fitted", "lines", "#D55E00", p));
    panel.x_marks = marks;
  }
  return {
      fmt::format("Modal fit: {} ({} modes in {}, RMS error {} %)", r.source, r.fit.modes.size(),
                  to_string(r.fit.direction), human(100.0 * r.fit.rms_relative_error, 3)),
      {magnitude, phase}};
}

}  // namespace cutdyn::app
