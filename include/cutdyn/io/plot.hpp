// Figures through gnuplot. Beside the figure `F.ext` we write `F.dat` (the data, one
// block per series) and `F.gp` (the script that draws it from F.dat, with relative
// paths), so that a user can restyle the figure and re-run `gnuplot F.gp` in that folder.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "cutdyn/io/output.hpp"

namespace cutdyn::io {

struct PlotSeries {
  std::string title;
  std::vector<double> x;
  std::vector<double> y;
  /// "lines", "points", "linespoints", or "stable-region" (a line with the area below it
  /// shaded, used for the stable side of a lobe diagram).
  std::string style = "lines";
  bool y2 = false;  // on the right-hand axis (PlotSpec::y2_label)
};

struct PlotSpec {
  std::string title;
  std::string x_label;
  std::string y_label;
  std::string y2_label;  // the right-hand axis, for series with y2 = true
  std::vector<PlotSeries> series;
  std::optional<double> y_min;
  std::optional<double> y_max;
  bool y_log = false;
};

/// Supported figure formats by extension: .svg, .png, .pdf. Anything else throws
/// cutdyn::InvalidInput naming the path and the supported extensions.
void check_figure_path(const std::filesystem::path& figure);

/// Writes F.dat and F.gp, runs gnuplot to make the figure, and registers all three with
/// `outputs` (so they appear only on commit). Throws std::runtime_error if gnuplot is
/// missing or fails (its stderr is included in the message).
void write_plot(const PlotSpec& spec, const std::filesystem::path& figure,
                OutputTransaction& outputs);

}  // namespace cutdyn::io
