// Figures through gnuplot. Beside the figure `F.ext` we write `F.dat` (the data, one
// block per series) and `F.gp` (the script that draws it from F.dat, with relative
// paths), so that a user can restyle the figure and re-run `gnuplot F.gp` in that folder.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cutdyn/io/output.hpp"

namespace cutdyn::io {

struct PlotSeries {
  std::string title;
  std::vector<double> x;
  std::vector<double> y;
  /// "lines", "points", "linespoints", "stable-region" (a line with the area below it
  /// shaded, used for the stable side of a lobe diagram), "dashed" (a dashed line, for a
  /// limit) or "marker" (large points, for a chosen value).
  std::string style = "lines";
  bool y2 = false;         // on the right-hand axis (PlotSpec::y2_label)
  std::string color = "";  // "#rrggbb"; empty: the next colour of the palette
};

/// A vertical line across a panel at x, with a short label at its top (a time, a value).
struct PlotMark {
  double x = 0.0;
  std::string label;
};

/// One panel: its axes and series. The key (legend) is drawn below the panel, outside the
/// data.
struct PlotSpec {
  std::string title;
  std::string x_label;
  std::string y_label;
  std::string y2_label;  // the right-hand axis, for series with y2 = true
  std::vector<PlotSeries> series;
  std::vector<PlotMark> x_marks;
  std::optional<double> y_min;
  std::optional<double> y_max;
  bool y_log = false;
};

/// Panels stacked from top to bottom in one figure file (gnuplot's multiplot), under one
/// title. A figure of one panel is drawn as that panel alone.
struct PlotFigure {
  std::string title;
  std::vector<PlotSpec> panels;
};

/// The series thinned for drawing, to at most 3·buckets points: the samples are cut into
/// `buckets` runs of consecutive points, and each run keeps its smallest and its largest y
/// and its first non-finite value (a gap), in their order, so that peaks, the envelope of a
/// dense oscillation and its growth or decay survive. A series of at most 2·buckets points
/// is returned as it is.
PlotSeries envelope(const PlotSeries& series, std::size_t buckets);

struct Case;

/// The axis label of a case key a sweep varies (the TOML path of `with_value`): in words
/// with its unit, from the case's field tables: "spindle speed (rpm)" for simulate.rpm,
/// "natural frequency, modes[0] (Hz)"; the key itself when it has no label.
std::string case_key_label(const Case& c, std::string_view key);

/// Supported figure formats by extension: .svg, .png, .pdf. Anything else throws
/// cutdyn::InvalidInput naming the path and the supported extensions.
void check_figure_path(const std::filesystem::path& figure);

/// The files a figure F.ext is written as: F.ext, F.dat and F.gp, in one folder.
std::vector<std::filesystem::path> figure_files(const std::filesystem::path& figure);

/// Writes F.dat and F.gp, runs gnuplot to make the figure, and registers all three with
/// `outputs` (so they appear only on commit). Throws std::runtime_error if gnuplot is
/// missing or fails (its stderr is included in the message).
void write_plot(const PlotSpec& spec, const std::filesystem::path& figure,
                OutputTransaction& outputs);
/// The same for a figure of panels: F.dat holds the blocks of every panel's series in order
/// (one gnuplot index each), F.gp draws them panel by panel.
void write_plot(const PlotFigure& figure_spec, const std::filesystem::path& figure,
                OutputTransaction& outputs);

}  // namespace cutdyn::io
