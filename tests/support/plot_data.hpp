// Reading back a figure's data file (io/plot.hpp writes F.dat: one block per series, headed
// by "# TITLE" and comment lines): what the figure tests compare against the reports.
#pragma once

#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace cutdyn::testing {

using PlotPoints = std::vector<std::pair<double, double>>;

/// The (x, y) points of the block of the series called `title` (empty when there is none).
inline PlotPoints plot_block(const std::string& dat, const std::string& title) {
  PlotPoints points;
  const auto at = dat.find("\n# " + title + "\n");
  if (at == std::string::npos) return points;
  std::istringstream in(dat.substr(at + 1));
  std::string line;
  while (std::getline(in, line) && !line.empty() && line[0] == '#') {
  }
  do {
    if (line.empty()) break;
    std::istringstream values(line);
    double x = 0.0, y = 0.0;
    values >> x >> y;
    points.emplace_back(x, y);
  } while (std::getline(in, line));
  return points;
}

}  // namespace cutdyn::testing
