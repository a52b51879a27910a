// `cutdyn fit`: modes fitted to a measured FRF file (docs/models/modal-fitting.md).
#include <fmt/format.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <string>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cutdyn/app/fit.hpp"
#include "cutdyn/app/report_json.hpp"
#include "cutdyn/io/output.hpp"
#include "cutdyn/io/plot.hpp"

namespace cutdyn::cli {
namespace {

// "--modes auto" or a whole number; "--band LO:HI" in Hz.
app::FitRequest fit_request(const FitArgs& args) {
  app::FitRequest r;
  r.file = args.file;
  Validator v;
  if (args.modes != "auto") {
    std::size_t used = 0;
    int n = 0;
    try {
      n = std::stoi(args.modes, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != args.modes.size() || n < 1 || n > 40)
      v.add("--modes = " + args.modes + ": must be auto or a whole number from 1 to 40");
    r.fit.modes = n;
  }
  if (!args.band.empty()) {
    const auto colon = args.band.find(':');
    double lo = 0.0, hi = 0.0;
    bool ok = colon != std::string::npos;
    try {
      std::size_t a = 0, b = 0;
      lo = std::stod(args.band.substr(0, colon), &a);
      hi = std::stod(args.band.substr(colon + 1), &b);
      ok = ok && a == colon && b == args.band.size() - colon - 1;
    } catch (const std::exception&) {
      ok = false;
    }
    if (!ok || !std::isfinite(lo) || !std::isfinite(hi) || lo < 0.0 || hi <= lo)
      v.add("--band = " + args.band + ": must be LO:HI in Hz with 0 <= LO < HI");
    r.fit.lo_hz = lo;
    r.fit.hi_hz = hi;
  }
  if (!args.format.empty()) {
    r.file_options.format = parse_frf_format(args.format);
    if (!r.file_options.format) v.add("--format = " + args.format + ": must be frf, csv or uff");
  }
  if (!args.direction.empty()) r.direction = args.direction == "y" ? Direction::kY : Direction::kX;
  v.throw_if_any("command line");
  return r;
}

void print_fit(const app::FitJobReport& r, std::ostream& out) {
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
io::PlotFigure fit_plot(const app::FitJobReport& r) {
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

}  // namespace

int run_fit(const FitArgs& args, std::ostream& out, std::ostream& err) {
  check_outputs(args.outputs);
  const app::FitRequest request = fit_request(args);
  const app::FitJobReport r = app::run_fit(request);
  print_fit(r, out);
  for (const std::string& w : r.warnings)
    err << "cutdyn: warning: " << r.source << ": " << w << "\n";
  io::OutputTransaction outputs;
  if (!args.outputs.csv.empty()) outputs.open(args.outputs.csv) << app::modes_toml(r);
  if (!args.outputs.json.empty()) io::write_json(outputs.open(args.outputs.json), app::to_json(r));
  if (!args.outputs.plot.empty()) io::write_plot(fit_plot(r), args.outputs.plot, outputs);
  commit_outputs(outputs, args.outputs, out);
  return 0;
}

}  // namespace cutdyn::cli
