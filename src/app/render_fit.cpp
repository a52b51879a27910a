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
  out << fmt::format("  noise of the table (from the residuals): {} % of |G|{}{}\n",
                     human(100.0 * f.noise.proportional, 2),
                     f.noise.floor_m_per_n > 0.0
                         ? " and a floor of " + human(f.noise.floor_m_per_n, 2) + " m/N"
                         : std::string(),
                     f.noise_weighted       ? " (the fit weighted for it)"
                     : f.coherence_weighted ? " (the fit weighted by the coherence)"
                                            : "");
  for (const std::string& n : f.notes) out << "  note: " << n << "\n";
  if (f.modes.empty()) return;
  out << fmt::format("\n  {:>4}  {:>12}  {:>13}  {:>17}  {:>14}   1σ: {:>9}  {:>9}  {:>11}\n",
                     "mode", "natural_hz", "damping_ratio", "stiffness_n_per_m", "residue phase",
                     "Hz", "ζ", "N/m");
  for (std::size_t i = 0; i < f.modes.size(); ++i) {
    const FittedMode& m = f.modes[i];
    out << fmt::format("  {:>4}  {:>12}  {:>13}  {:>17}  {:>13}°       {:>9}  {:>9}  {:>11}\n",
                       i + 1, human(m.natural_hz, 6), human(m.damping_ratio, 4),
                       human(m.stiffness_n_per_m, 4), human(m.residue_phase_deg, 3),
                       human(m.natural_hz_sigma, 2), human(m.damping_ratio_sigma, 2),
                       human(m.stiffness_sigma_n_per_m, 2));
  }
}

// The measured FRF, the fit (modes, residual terms and explicit poles outside the band) and the
// modes alone as every time-domain method uses them (complex residues kept, no residual
// terms; docs/models/modal-fitting.md §10): magnitude (log), phase, real and imaginary part,
// the modes marked; and the table's coherence where it has one.
io::PlotFigure figure(const FitJobReport& r) {
  enum class Part { kMagnitude, kPhase, kReal, kImaginary };
  const auto series = [](const MeasuredFrf& t, const char* title, const char* style,
                         const char* colour, Part part) {
    io::PlotSeries s{title, t.frequency_hz, {}, style, false, colour};
    for (const std::complex<double>& g : t.receptance_m_per_n) {
      switch (part) {
        case Part::kMagnitude: s.y.push_back(std::abs(g)); break;
        case Part::kPhase: s.y.push_back(std::arg(g) * 180.0 / std::numbers::pi); break;
        case Part::kReal: s.y.push_back(g.real()); break;
        case Part::kImaginary: s.y.push_back(g.imag()); break;
      }
    }
    return io::envelope(s, 2000);
  };
  const MeasuredFrf used = sample_frf(r.fit.model, r.fit.direction, r.fitted.frequency_hz);
  std::vector<io::PlotMark> marks;
  for (const FittedMode& m : r.fit.modes)
    marks.push_back({m.natural_hz, human(m.natural_hz, 4) + " Hz"});
  std::vector<io::PlotSpec> panels;
  for (const auto& [part, label] :
       {std::pair{Part::kMagnitude, "receptance magnitude (m/N)"}, std::pair{Part::kPhase, "phase (°)"},
        std::pair{Part::kReal, "real part (m/N)"}, std::pair{Part::kImaginary, "imaginary part (m/N)"}}) {
    io::PlotSpec panel;
    panel.x_label = "frequency (Hz)";
    panel.y_label = label;
    panel.y_log = part == Part::kMagnitude;
    panel.series.push_back(series(r.read.frf, "measured", "lines", "#999999", part));
    panel.series.push_back(series(r.fitted, "fit (with residual terms)", "lines", "#D55E00", part));
    if (!r.fit.model.modes.empty())
      panel.series.push_back(series(used, "modes used by every method", "lines", "#0072B2", part));
    panel.x_marks = marks;
    panels.push_back(std::move(panel));
  }
  if (!r.read.frf.coherence.empty()) {  // what the fit weighed by (§4.3)
    io::PlotSpec panel;
    panel.x_label = "frequency (Hz)";
    panel.y_label = "coherence γ²";
    panel.y_min = 0.0;
    panel.y_max = 1.0;
    panel.series.push_back(io::envelope(
        io::PlotSeries{"coherence", r.read.frf.frequency_hz, r.read.frf.coherence, "lines", false,
                       "#009E73"},
        2000));
    panel.x_marks = marks;
    panels.push_back(std::move(panel));
  }
  return {fmt::format("Modal fit: {} ({} modes in {}, RMS error {} %; the modes alone {} %)",
                      r.source, r.fit.modes.size(), to_string(r.fit.direction),
                      human(100.0 * r.fit.rms_relative_error, 3),
                      human(100.0 * r.fit.model_rms_relative_error, 3)),
          std::move(panels)};
}

}  // namespace cutdyn::app
