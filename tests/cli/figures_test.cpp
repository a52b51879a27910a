// The figures of the commands, read from the .gp and .dat files written beside them: axes
// in words with units, the series and marks a machinist reads, and data that agree with the
// command's own JSON.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cutdyn/io/case_file.hpp"
#include "support/cli_runner.hpp"
#include "support/plot_data.hpp"
#include "support/temp_dir.hpp"

namespace cutdyn::cli {
namespace {

namespace fs = std::filesystem;

using Result = testing::CliResult;
using Points = std::vector<std::pair<double, double>>;

Result cutdyn(const std::vector<std::string>& args) { return testing::run_cutdyn(args); }

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

std::size_t count(const std::string& text, const std::string& part) {
  std::size_t n = 0;
  for (auto at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

// The points of the .dat block whose series is called `title` (empty if there is none).
using testing::plot_block;

class Figures : public testing::TempDirTest {
 protected:
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string read(const std::string& name) const { return testing::read_file(dir_ / name); }
  nlohmann::json json(const std::string& name) const {
    return nlohmann::json::parse(std::ifstream(path(name)));
  }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name)) << text;
    return path(name);
  }
};

TEST_F(Figures, SimulateSweepLabelsTheKeyAndTheMetricInWordsAndPlotsPercent) {
  const Result r = cutdyn({"simulate", "ermolaev2020", "--sweep", "force_law.t2_s=0:0.1:0.3",
                           "--json", path("w.json"), "--plot", path("w.png")});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string gp = read("w.gp");
  EXPECT_TRUE(contains(gp, "set xlabel \"chip-formation time constant T2 (s)\"\n")) << gp;
  EXPECT_TRUE(contains(gp, "set ylabel \"force pulsation ΔP (%)\"\n")) << gp;
  EXPECT_TRUE(contains(gp, "set title \"Force pulsation ΔP over a sweep of force_law.t2_s\""))
      << gp;
  EXPECT_FALSE(contains(gp, "label \"force_pulsation\"")) << gp;
  // The data in percent: 100 × the JSON's fraction, at the swept values.
  const auto doc = json("w.json");
  const Points points = plot_block(read("w.dat"), "force pulsation ΔP");
  ASSERT_EQ(points.size(), 4u) << read("w.dat");
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_DOUBLE_EQ(points[i].first, doc["points"][i]["value"].get<double>());
    EXPECT_NEAR(points[i].second, 100.0 * doc["points"][i]["force_pulsation"].get<double>(), 1e-9);
  }
  // No run chatters (the chip comes from the feed alone): no chatter marks.
  EXPECT_TRUE(plot_block(read("w.dat"), "chatter (vibration grows)").empty());
}

TEST_F(Figures, SimulateSweepOfAnIndexedKeyNamesTheElement) {
  const Result r = cutdyn({"simulate", "ermolaev2020", "--sweep", "modes[1].natural_hz=400:100:500",
                           "--metric", "vibration_pp_y_um", "--plot", path("w.png")});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string gp = read("w.gp");
  EXPECT_TRUE(contains(gp, "set xlabel \"natural frequency, modes[1] (Hz)\"")) << gp;
  EXPECT_TRUE(contains(gp, "set ylabel \"vibration in y, peak to peak (µm)\"")) << gp;
}

TEST_F(Figures, MillingSimulationShowsTheWholeRunAndTheLastRevolutions) {
  const Result r = cutdyn({"simulate", "milling-insperger", "--depth-mm", "0.08", "--out",
                           path("s.csv"), "--json", path("s.json"), "--plot", path("s.png")});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string gp = read("s.gp"), dat = read("s.dat");
  EXPECT_TRUE(contains(gp, "set multiplot layout 2,1")) << gp;
  EXPECT_TRUE(contains(gp, "set terminal pngcairo size 1200,1280")) << gp;
  EXPECT_TRUE(contains(gp, "unset multiplot")) << gp;
  EXPECT_TRUE(contains(dat, "# panel 1 of 2: Cutter displacement")) << dat;
  EXPECT_TRUE(contains(dat, "# panel 2 of 2: Force on the cutter over the last")) << dat;

  // The displacement over the whole run, thinned to its envelope: from the first to the last
  // instant of the CSV, peaks kept, a few thousand points.
  std::vector<double> time, x;
  {
    std::ifstream csv(path("s.csv"));
    std::string line;
    std::getline(csv, line);
    while (std::getline(csv, line)) {
      std::vector<double> cells;
      std::istringstream in(line);
      for (std::string cell; std::getline(in, cell, ',');) cells.push_back(std::stod(cell));
      time.push_back(cells[0]);
      x.push_back(cells[4]);
    }
  }
  ASSERT_GT(time.size(), 10000u);
  const Points shown = plot_block(dat, "x (feed)");
  ASSERT_FALSE(shown.empty()) << dat;
  EXPECT_LE(shown.size(), 6000u);
  EXPECT_NEAR(shown.front().first, time.front(), 1e-9);
  EXPECT_NEAR(shown.back().first, time.back(), 1e-6 * time.back());
  double shown_max = -1e300, max = -1e300;
  for (const auto& p : shown) shown_max = std::max(shown_max, p.second);
  for (double v : x) max = std::max(max, v);
  EXPECT_NEAR(shown_max, max, 1e-6 * std::abs(max));
  EXPECT_FALSE(plot_block(dat, "y").empty());  // the case has modes in y too

  // The window of the summary is marked, and the forces are shown over it.
  EXPECT_TRUE(contains(gp, "set arrow from first ")) << gp;
  EXPECT_TRUE(contains(gp, "last 5 rev (below)")) << gp;
  const Points force = plot_block(dat, "|F|");
  ASSERT_FALSE(force.empty());
  EXPECT_GT(force.front().first, 0.5 * time.back());
  EXPECT_TRUE(contains(gp, "set key outside below")) << gp;
}

TEST_F(Figures, MillingSimulationDrawsNoTraceForADirectionWithoutModes) {
  std::string text(*io::example_text("ermolaev2020"));
  const auto y_mode = text.find("[[modes]]\ndirection = \"y\"");
  ASSERT_NE(y_mode, std::string::npos);
  text.erase(y_mode, text.find("[force_law]") - y_mode);
  const Result r = cutdyn({"simulate", write("x-only.toml", text), "--plot", path("x.png")});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string dat = read("x.dat");
  EXPECT_FALSE(plot_block(dat, "x (feed)").empty()) << dat;
  EXPECT_TRUE(plot_block(dat, "y").empty()) << dat;
  EXPECT_EQ(count(dat, "# columns: 1 = time (s), 2 = cutter displacement (µm)"), 1u) << dat;
}

TEST_F(Figures, DriveShowsTheSpeedRippleBesideEpsilon) {
  const Result r = cutdyn({"drive", "--json", path("d.json"), "--plot", path("d.png")});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string gp = read("d.gp"), dat = read("d.dat");
  EXPECT_TRUE(contains(gp, "set multiplot layout 2,1")) << gp;
  EXPECT_TRUE(contains(gp, "set ylabel \"ε along the axis (µm)\"")) << gp;
  EXPECT_TRUE(contains(gp, "set ylabel \"motor speed − mean (rad/s)\"")) << gp;
  const auto doc = json("d.json");
  for (const auto& axis : doc["axes"]) {
    const std::string name = axis["axis"].get<std::string>();
    // The speed about its mean: centred on 0, as wide as the reported ripple ±ΔΩ.
    const std::string prefix = "\n# axis " + name + ": mean ";
    const auto at = dat.find(prefix);
    ASSERT_NE(at, std::string::npos) << dat;
    const std::string title = dat.substr(at + 3, dat.find('\n', at + 1) - at - 3);
    const Points speed = plot_block(dat, title);
    ASSERT_FALSE(speed.empty()) << title;
    double lo = 1e300, hi = -1e300;
    for (const auto& p : speed) {
      lo = std::min(lo, p.second);
      hi = std::max(hi, p.second);
    }
    const double ripple = axis["speed_ripple_rad_s"].get<double>();
    EXPECT_LE(lo, 0.0) << title;
    EXPECT_GE(hi, 0.0) << title;
    EXPECT_NEAR(0.5 * (hi - lo), ripple, 0.05 * ripple + 1e-12) << title;
    EXPECT_TRUE(contains(dat, "# axis " + name + ": ε ")) << dat;
  }
}

TEST_F(Figures, DriveSweepLabelsTheKeyAndPlotsTheStaticErrorInPercent) {
  const Result r = cutdyn({"drive", "--sweep", "simulate.rpm=600:600:1200", "--metric",
                           "static_error", "--json", path("w.json"), "--plot", path("w.png")});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string gp = read("w.gp");
  EXPECT_TRUE(contains(gp, "set xlabel \"spindle speed (rpm)\"")) << gp;
  EXPECT_TRUE(contains(gp, "set ylabel \"static speed error δ (%)\"")) << gp;
  EXPECT_TRUE(contains(gp, "over a sweep of simulate.rpm")) << gp;
  const auto doc = json("w.json");
  const Points x = plot_block(read("w.dat"), "axis x");
  ASSERT_EQ(x.size(), 2u) << read("w.dat");
  for (std::size_t i = 0; i < x.size(); ++i) {
    EXPECT_DOUBLE_EQ(x[i].first, doc["points"][i]["value"].get<double>());
    EXPECT_NEAR(x[i].second, 100.0 * doc["points"][i]["axes"][0]["static_error"].get<double>(),
                1e-12);
  }
}

TEST_F(Figures, PlanGivesS0AndHTheirOwnAxesAndMarksThePlanAndTheLimit) {
  const Result r = cutdyn({"plan", "--json", path("p.json"), "--plot", path("p.png")});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string gp = read("p.gp"), dat = read("p.dat");
  const auto doc = json("p.json");
  EXPECT_TRUE(contains(gp, "set multiplot layout 2,1")) << gp;
  EXPECT_TRUE(contains(gp, "set xlabel \"axial feed S0 (mm)\"\n")) << gp;
  EXPECT_TRUE(contains(gp, "set xlabel \"offset h (mm)\"\n")) << gp;
  EXPECT_FALSE(contains(gp, "(mm) | offset")) << gp;  // no axis shared by S0 and h
  EXPECT_TRUE(contains(gp, "set y2label \"straightness error Δ1 (mm)\"")) << gp;

  // The limit Δ1 = k·t on the Δ1 axis, across the feeds drawn: k = 0.05, t = 5 mm.
  const Points limit = plot_block(dat, "limit Δ1 = k·t = 0.25 mm (right axis)");
  ASSERT_EQ(limit.size(), 2u) << dat;
  EXPECT_DOUBLE_EQ(limit[0].second, 0.25);
  EXPECT_DOUBLE_EQ(limit[1].second, 0.25);
  const Points delta1 = plot_block(dat, "Δ1 (right axis)");
  ASSERT_FALSE(delta1.empty());
  EXPECT_DOUBLE_EQ(limit[0].first, delta1.front().first);
  EXPECT_DOUBLE_EQ(limit[1].first, delta1.back().first);
  EXPECT_TRUE(contains(gp, "axes x1y2 with lines linestyle 3 dashtype 2")) << gp;

  // The chosen point on both panels: (S0, t0) and (h, t0), as the JSON has them.
  const double s0 = doc["axial_feed_mm"].get<double>(), h = doc["offset_mm"].get<double>(),
               t0 = doc["main_time_min"].get<double>();
  const auto chosen_at = dat.find("\n# chosen: S0 = ");
  ASSERT_NE(chosen_at, std::string::npos) << dat;
  const std::string chosen =
      dat.substr(chosen_at + 3, dat.find('\n', chosen_at + 1) - chosen_at - 3);
  EXPECT_EQ(count(dat, "# " + chosen + "\n"), 2u) << dat;
  const Points first = plot_block(dat, chosen);
  ASSERT_EQ(first.size(), 1u);
  EXPECT_NEAR(first[0].first, s0, 1e-12 * s0);
  EXPECT_NEAR(first[0].second, t0, 1e-12 * t0);
  const Points second = plot_block(dat.substr(dat.find("# panel 2 of 2")), chosen);
  ASSERT_EQ(second.size(), 1u);
  EXPECT_NEAR(second[0].first, h, 1e-12 * std::abs(h));
  EXPECT_NEAR(second[0].second, t0, 1e-12 * t0);
  EXPECT_EQ(count(gp, "with points linestyle"), 2u) << gp;
  EXPECT_EQ(count(gp, "set arrow from first "), 2u) << gp;  // S0 and h marked
}

}  // namespace
}  // namespace cutdyn::cli
