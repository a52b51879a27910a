#include "cutdyn/io/plot.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "cutdyn/core/error.hpp"
#include "cutdyn/io/case_file.hpp"
#include "io/case_fields.hpp"
#include "support/temp_dir.hpp"

namespace cutdyn::io {
namespace {
namespace fs = std::filesystem;

using testing::read_file;

using testing::listing;

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// A lobe-like boundary (stable below it) and a flat reference line.
PlotSpec lobe_spec() {
  PlotSpec spec;
  spec.title = "Stability lobes";
  spec.x_label = "Spindle speed [rpm]";
  spec.y_label = "Critical depth [mm]";
  PlotSeries lobes{"Stable below", {}, {}, "stable-region"};
  for (int i = 0; i <= 200; ++i) {
    const double rpm = 500.0 + 22.5 * i;
    const double phase = std::fmod(rpm / 900.0, 1.0);
    lobes.x.push_back(rpm);
    lobes.y.push_back(1.0 + 6.0 * phase * phase * phase * phase * (rpm / 5000.0));
  }
  spec.series.push_back(lobes);
  spec.series.push_back(PlotSeries{"Absolute limit", {500.0, 5000.0}, {1.0, 1.0}, "lines"});
  spec.y_min = 0.0;
  return spec;
}

// Sets PATH for the life of the object.
class ScopedPath {
 public:
  explicit ScopedPath(const std::string& value) {
    if (const char* old = std::getenv("PATH")) old_ = old;
    ::setenv("PATH", value.c_str(), 1);
  }
  ~ScopedPath() {
    if (old_) {
      ::setenv("PATH", old_->c_str(), 1);
    } else {
      ::unsetenv("PATH");
    }
  }
  ScopedPath(const ScopedPath&) = delete;
  ScopedPath& operator=(const ScopedPath&) = delete;

 private:
  std::optional<std::string> old_;
};

class PlotTest : public testing::TempDirTest {};

// ---- check_figure_path ----------------------------------------------------------------

TEST(PlotFigurePath, AcceptsSvgPngPdf) {
  EXPECT_NO_THROW(check_figure_path("out/lobes.svg"));
  EXPECT_NO_THROW(check_figure_path("lobes.png"));
  EXPECT_NO_THROW(check_figure_path("/tmp/lobes.pdf"));
  EXPECT_NO_THROW(check_figure_path("LOBES.PNG"));
}

TEST(PlotFigurePath, RejectsOtherExtensionsAsInvalidInput) {
  try {
    check_figure_path("out/lobes.jpg");
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where(), "out/lobes.jpg");
    ASSERT_EQ(e.problems().size(), 1u);
    EXPECT_EQ(e.problems()[0], "unsupported figure format \".jpg\": use .svg, .png or .pdf");
  }
  try {
    check_figure_path("out/lobes");
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where(), "out/lobes");
    ASSERT_EQ(e.problems().size(), 1u);
    EXPECT_TRUE(contains(e.problems()[0], ".svg, .png or .pdf")) << e.problems()[0];
  }
}

// ---- write_plot ---------------------------------------------------------------------------

TEST_F(PlotTest, PngDataAndScriptAppearTogetherOnCommit) {
  OutputTransaction outputs;
  write_plot(lobe_spec(), dir_ / "F.png", outputs);
  for (const std::string& name : listing(dir_)) {
    EXPECT_EQ(name[0], '.') << "visible before commit: " << name;
  }
  outputs.commit();
  ASSERT_EQ(listing(dir_), (std::vector<std::string>{"F.dat", "F.gp", "F.png"}));

  const std::string png = read_file(dir_ / "F.png");
  ASSERT_GT(png.size(), 1000u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));

  // The data: one block per series, separated by two blank lines, values round-trip.
  const std::string dat = read_file(dir_ / "F.dat");
  EXPECT_TRUE(contains(dat, "# Stable below\n")) << dat;
  EXPECT_TRUE(contains(dat, "\n500 1\n")) << dat;  // first lobe point
  EXPECT_TRUE(contains(dat, "\n1175 ")) << dat;    // 500 + 22.5 * 30
  EXPECT_TRUE(contains(dat, "\n\n\n# Absolute limit\n")) << dat;
  EXPECT_TRUE(contains(dat, "\n5000 1\n")) << dat;
  EXPECT_TRUE(contains(dat, "Spindle speed [rpm]")) << dat;

  // The script: relative names only, terminal by extension, one index per series.
  const std::string gp = read_file(dir_ / "F.gp");
  EXPECT_TRUE(contains(gp, "set terminal pngcairo size 1200,800 enhanced font 'Sans,12'")) << gp;
  EXPECT_TRUE(contains(gp, "set output \"F.png\"")) << gp;
  EXPECT_TRUE(contains(gp, "data = \"F.dat\"")) << gp;
  EXPECT_TRUE(contains(gp, "data index 0 using 1:2 with filledcurves y1=0")) << gp;
  EXPECT_TRUE(contains(gp, "data index 1 using 1:2 with lines")) << gp;
  EXPECT_TRUE(contains(gp, "set yrange [0:*]")) << gp;
  // The key below the axes, outside the data.
  EXPECT_TRUE(contains(gp, "set key outside below center horizontal")) << gp;
  EXPECT_FALSE(contains(gp, "set key top")) << gp;
  EXPECT_FALSE(contains(gp, "multiplot")) << gp;  // one panel: drawn alone
  EXPECT_FALSE(contains(gp, dir_.string())) << gp;
}

TEST_F(PlotTest, SeriesOnTheRightHandAxis) {
  PlotSpec spec;
  spec.title = "force and vibration";
  spec.x_label = "t";
  spec.y_label = "F";
  spec.y2_label = "x";
  spec.series = {PlotSeries{"F", {0, 1, 2}, {1, 2, 1}, "lines"},
                 PlotSeries{"x", {0, 1, 2}, {5, -5, 5}, "lines", true}};
  OutputTransaction outputs;
  write_plot(spec, dir_ / "R.png", outputs);
  outputs.commit();
  const std::string gp = read_file(dir_ / "R.gp");
  EXPECT_TRUE(contains(gp, "data index 0 using 1:2 with lines")) << gp;
  EXPECT_TRUE(contains(gp, "data index 1 using 1:2 axes x1y2 with lines")) << gp;
  EXPECT_TRUE(contains(gp, "set y2label \"x\"")) << gp;
  EXPECT_TRUE(contains(gp, "set border 11")) << gp;
  EXPECT_GT(read_file(dir_ / "R.png").size(), 1000u);
  // Each block names its own axis.
  const std::string dat = read_file(dir_ / "R.dat");
  EXPECT_TRUE(contains(dat, "# F\n# columns: 1 = t, 2 = F\n")) << dat;
  EXPECT_TRUE(contains(dat, "# x\n# columns: 1 = t, 2 = x\n")) << dat;
}

TEST_F(PlotTest, PanelsAreStackedInOneFigureWithTheirOwnAxes) {
  PlotSpec top;
  top.title = "whole run";
  top.x_label = "time (s)";
  top.y_label = "displacement (µm)";
  top.series = {PlotSeries{"x", {0, 1, 2}, {1, -2, 3}, "lines"}};
  top.x_marks = {PlotMark{1.5, "last rev"}};
  PlotSpec bottom;
  bottom.title = "last revolution";
  bottom.x_label = "time (s)";
  bottom.y_label = "force (N)";
  bottom.y2_label = "angle (deg)";
  bottom.series = {PlotSeries{"|F|", {1.5, 2}, {10, 12}, "lines"},
                   PlotSeries{"angle", {1.5, 2}, {0, 90}, "lines", true}};
  bottom.y_log = true;
  OutputTransaction outputs;
  write_plot(PlotFigure{"Two panels", {top, bottom}}, dir_ / "P.png", outputs);
  outputs.commit();
  ASSERT_EQ(listing(dir_), (std::vector<std::string>{"P.dat", "P.gp", "P.png"}));
  EXPECT_EQ(read_file(dir_ / "P.png").substr(0, 4), "\x89PNG");

  const std::string gp = read_file(dir_ / "P.gp");
  EXPECT_TRUE(contains(gp, "set terminal pngcairo size 1200,1280 ")) << gp;  // taller
  EXPECT_TRUE(contains(gp, "set multiplot layout 2,1 title \"Two panels\"")) << gp;
  EXPECT_TRUE(contains(gp, "set lmargin 12\nset rmargin 12\n")) << gp;  // axes lined up
  EXPECT_TRUE(contains(gp, "set title \"whole run\"")) << gp;
  EXPECT_TRUE(contains(gp, "set title \"last revolution\"")) << gp;
  EXPECT_TRUE(contains(gp, "set ylabel \"displacement (µm)\"")) << gp;
  EXPECT_TRUE(contains(gp, "set ylabel \"force (N)\"")) << gp;
  // The blocks are numbered across the panels; the second panel starts afresh.
  EXPECT_TRUE(contains(gp, "plot data index 0 using 1:2 with lines linestyle 1 title \"x\"\n"))
      << gp;
  EXPECT_TRUE(contains(gp, "plot data index 1 using 1:2 with lines linestyle 1")) << gp;
  EXPECT_TRUE(contains(gp, "data index 2 using 1:2 axes x1y2 with lines linestyle 2")) << gp;
  EXPECT_TRUE(contains(gp, "unset arrow\nunset label\nunset logscale\n")) << gp;
  EXPECT_TRUE(contains(gp, "unset multiplot\n")) << gp;
  EXPECT_LT(gp.find("set arrow from first 1.5, graph 0"), gp.find("# Panel 2"));
  EXPECT_LT(gp.find("# Panel 2"), gp.find("set logscale y"));

  const std::string dat = read_file(dir_ / "P.dat");
  EXPECT_TRUE(contains(dat, "# panel 1 of 2: whole run\n# mark at time (s) = 1.5: last rev\n# x\n"))
      << dat;
  EXPECT_TRUE(contains(dat,
                       "\n\n\n# panel 2 of 2: last revolution\n# |F|\n"
                       "# columns: 1 = time (s), 2 = force (N)\n1.5 10\n"))
      << dat;
  EXPECT_TRUE(contains(dat, "# angle\n# columns: 1 = time (s), 2 = angle (deg)\n")) << dat;

  // And the script redraws it.
  fs::remove(dir_ / "P.png");
  const std::string command = "cd '" + dir_.string() + "' && gnuplot P.gp 2>/dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0);
  EXPECT_EQ(read_file(dir_ / "P.png").substr(0, 4), "\x89PNG");
}

TEST_F(PlotTest, LimitsMarkersMarksAndColours) {
  PlotSpec spec;
  spec.title = "plan";
  spec.x_label = "S0 (mm)";
  spec.y_label = "t0 (min)";
  spec.y2_label = "Δ1 (mm)";
  spec.series = {PlotSeries{"t0", {10, 20, 30}, {40, 25, 18}, "lines"},
                 PlotSeries{"limit", {10, 30}, {0.25, 0.25}, "dashed", true, "#D55E00"},
                 PlotSeries{"chosen", {22}, {24.7}, "marker", false, "#000000"}};
  spec.x_marks = {PlotMark{22, "S0 = 22 mm"}};
  OutputTransaction outputs;
  write_plot(spec, dir_ / "M.svg", outputs);
  outputs.commit();
  const std::string gp = read_file(dir_ / "M.gp");
  EXPECT_TRUE(contains(gp, "set style line 1 linecolor rgb '#0072B2'")) << gp;  // the palette
  EXPECT_TRUE(contains(gp, "set style line 2 linecolor rgb '#D55E00'")) << gp;
  EXPECT_TRUE(contains(gp, "set style line 3 linecolor rgb '#000000'")) << gp;
  EXPECT_TRUE(contains(gp,
                       "data index 1 using 1:2 axes x1y2 with lines linestyle 2 dashtype 2 "
                       "title \"limit\""))
      << gp;
  EXPECT_TRUE(contains(gp,
                       "data index 2 using 1:2 with points linestyle 3 pointtype 7 "
                       "pointsize 2.2 title \"chosen\""))
      << gp;
  EXPECT_TRUE(contains(gp, "set arrow from first 22, graph 0 to first 22, graph 1 nohead")) << gp;
  EXPECT_TRUE(contains(gp, "set label \"S0 = 22 mm\" at first 22, graph 1")) << gp;
  EXPECT_TRUE(contains(read_file(dir_ / "M.dat"), "# mark at S0 (mm) = 22: S0 = 22 mm\n"));
  EXPECT_TRUE(contains(read_file(dir_ / "M.svg"), "<svg"));

  spec.series[2].color = "black";
  EXPECT_THROW(write_plot(spec, dir_ / "N.svg", outputs), std::logic_error);
  spec.series[2].color = "#000000";
  spec.x_marks[0].x = std::nan("");
  EXPECT_THROW(write_plot(spec, dir_ / "N.svg", outputs), std::logic_error);
  EXPECT_THROW(write_plot(PlotFigure{"none", {}}, dir_ / "N.svg", outputs), std::logic_error);
}

// ---- envelope -------------------------------------------------------------------------------

TEST(PlotEnvelope, KeepsEachBucketsLowestAndHighestInOrder) {
  PlotSeries dense{"x", {}, {}, "lines", true};
  const int n = 100000;
  for (int i = 0; i < n; ++i) {
    const double t = 1e-4 * i;
    dense.x.push_back(t);
    dense.y.push_back(std::exp(0.3 * t) * std::sin(2 * 3.141592653589793 * 503.0 * t));
  }
  const PlotSeries thin = envelope(dense, 1000);
  EXPECT_EQ(thin.title, "x");
  EXPECT_TRUE(thin.y2);
  ASSERT_LE(thin.x.size(), 2000u);
  EXPECT_GE(thin.x.size(), 1900u);
  EXPECT_TRUE(std::is_sorted(thin.x.begin(), thin.x.end()));
  // The extremes survive exactly, and the envelope still grows (e^0.3t over 10 s: ×20).
  EXPECT_EQ(*std::max_element(thin.y.begin(), thin.y.end()),
            *std::max_element(dense.y.begin(), dense.y.end()));
  EXPECT_EQ(*std::min_element(thin.y.begin(), thin.y.end()),
            *std::min_element(dense.y.begin(), dense.y.end()));
  const double early = *std::max_element(thin.y.begin(), thin.y.begin() + 100);
  const double late = *std::max_element(thin.y.end() - 100, thin.y.end());
  EXPECT_GT(late / early, 15.0);
  // Every point kept is a point of the series.
  for (std::size_t i = 0; i < thin.x.size(); i += 97) {
    const auto k = static_cast<std::size_t>(std::llround(thin.x[i] / 1e-4));
    EXPECT_EQ(thin.y[i], dense.y[k]);
  }
}

TEST(PlotEnvelope, ShortSeriesStayAndGapsStayGaps) {
  const PlotSeries few{"few", {0, 1, 2, 3}, {3, 1, 2, 0}, "lines"};
  EXPECT_EQ(envelope(few, 2).y, few.y);
  EXPECT_EQ(envelope(few, 0).y, few.y);
  PlotSeries gappy{"gappy", {}, {}, "lines"};
  for (int i = 0; i < 40; ++i) {
    gappy.x.push_back(i);
    gappy.y.push_back(i >= 10 && i < 20 ? std::nan("") : (i % 2 ? 1.0 : -1.0));
  }
  const PlotSeries thin = envelope(gappy, 4);  // buckets of 10: the second is all gap
  ASSERT_EQ(thin.y.size(), 7u);
  EXPECT_EQ(thin.x, (std::vector<double>{0, 1, 10, 20, 21, 30, 31}));
  EXPECT_TRUE(std::isnan(thin.y[2]));
}

// ---- case_key_label ---------------------------------------------------------------------------

TEST(PlotCaseKeyLabel, SweptKeysInWordsWithTheirUnits) {
  const Case milling = load_example("milling-insperger");
  EXPECT_EQ(case_key_label(milling, "simulate.rpm"), "spindle speed (rpm)");
  EXPECT_EQ(case_key_label(milling, "operation.feed_per_tooth_mm"), "feed per tooth (mm)");
  EXPECT_EQ(case_key_label(milling, "modes[1].natural_hz"), "natural frequency, modes[1] (Hz)");
  EXPECT_EQ(case_key_label(milling, "modes[0].damping_ratio"), "damping ratio ζ, modes[0]");
  EXPECT_EQ(case_key_label(milling, "operation.radial_immersion"), "radial immersion a_e/D");
  EXPECT_EQ(case_key_label(milling, "cutting.kt_n_per_mm2"),
            "tangential cutting coefficient Kt (N/mm²)");
  EXPECT_EQ(case_key_label(milling, "force_law.t2_s"), "chip-formation time constant T2 (s)");
  EXPECT_EQ(case_key_label(milling, "drives[0].stiffness_nm_s_per_rad"),
            "drive stiffness |β|, drives[0] (N·m·s/rad)");
  // In turning kt_n_per_mm2 is the old name of the feed-direction coefficient.
  const Case turning = load_example("turning-ultrasonic");
  EXPECT_EQ(case_key_label(turning, "cutting.kt_n_per_mm2"),
            "feed-direction cutting coefficient Kf (N/mm²)");
  // A plan case's tables: the cutter's diameter, not the milling tool's.
  const Case plan = load_example("bore-plan");
  EXPECT_EQ(case_key_label(plan, "cutter.diameter_mm"), "cutter diameter D (mm)");
  EXPECT_EQ(case_key_label(plan, "process.accuracy_coefficient"), "accuracy coefficient k");
  // Not a key of the tables: the key itself.
  EXPECT_EQ(case_key_label(milling, "simulate.nope"), "simulate.nope");
  EXPECT_EQ(case_key_label(milling, "nope"), "nope");
}

TEST(PlotCaseKeyLabel, EveryNumberKeyHasALabel) {
  for (const detail::Section& section : detail::case_sections())
    for (const detail::Field& field : section.fields)
      if (field.numeric()) {
        EXPECT_FALSE(field.label.empty()) << section.name << "." << field.key;
        EXPECT_NE(field.label, field.key) << section.name << "." << field.key;
      }
}

TEST_F(PlotTest, ScriptRedrawsTheFigureInItsFolder) {
  OutputTransaction outputs;
  write_plot(lobe_spec(), dir_ / "F.png", outputs);
  outputs.commit();
  fs::remove(dir_ / "F.png");
  const std::string command = "cd '" + dir_.string() + "' && gnuplot F.gp 2>/dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0);
  EXPECT_EQ(read_file(dir_ / "F.png").substr(0, 4), "\x89PNG");
}

TEST_F(PlotTest, SvgAndPdfUseTheirTerminals) {
  OutputTransaction outputs;
  write_plot(lobe_spec(), dir_ / "a.svg", outputs);
  write_plot(lobe_spec(), dir_ / "b.pdf", outputs);
  outputs.commit();
  EXPECT_EQ(listing(dir_),
            (std::vector<std::string>{"a.dat", "a.gp", "a.svg", "b.dat", "b.gp", "b.pdf"}));
  EXPECT_TRUE(contains(read_file(dir_ / "a.svg"), "<svg"));
  EXPECT_EQ(read_file(dir_ / "b.pdf").substr(0, 5), "%PDF-");
  EXPECT_TRUE(contains(read_file(dir_ / "a.gp"), "set terminal svg size 900,600 dynamic"));
  EXPECT_TRUE(contains(read_file(dir_ / "b.gp"), "set terminal pdfcairo size 7in,4.5in"));
}

TEST_F(PlotTest, WithoutCommitNoFileIsLeft) {
  {
    OutputTransaction outputs;
    write_plot(lobe_spec(), dir_ / "F.png", outputs);
    EXPECT_FALSE(listing(dir_).empty());  // the scratch folder
  }
  EXPECT_TRUE(listing(dir_).empty());
}

TEST_F(PlotTest, UnsupportedExtensionThrowsInvalidInputAndWritesNothing) {
  {
    OutputTransaction outputs;
    EXPECT_THROW(write_plot(lobe_spec(), dir_ / "F.jpg", outputs), InvalidInput);
    outputs.commit();
  }
  EXPECT_TRUE(listing(dir_).empty());
}

TEST_F(PlotTest, MissingFolderThrowsNamingIt) {
  OutputTransaction outputs;
  const fs::path figure = dir_ / "missing" / "F.png";
  try {
    write_plot(lobe_spec(), figure, outputs);
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(contains(e.what(), figure.string())) << e.what();
  }
}

TEST_F(PlotTest, TextIsEscapedAndNeverRunAsACommand) {
  const fs::path marker = dir_ / "ran";
  PlotSpec spec = lobe_spec();
  spec.title = "Say \"hi\" \\ `touch " + marker.string() + "` a_p";
  spec.series[1].title = "it's \"quoted\"";
  OutputTransaction outputs;
  write_plot(spec, dir_ / "F.png", outputs);
  outputs.commit();
  EXPECT_FALSE(fs::exists(marker));
  const std::string gp = read_file(dir_ / "F.gp");
  EXPECT_TRUE(contains(gp, "set title \"Say \\\"hi\\\" \\\\ \\140touch ")) << gp;
  EXPECT_TRUE(contains(gp, "a_p\" noenhanced")) << gp;
  EXPECT_TRUE(contains(gp, "title \"it's \\\"quoted\\\"\"")) << gp;
}

TEST_F(PlotTest, LogScaleEmptySeriesAndGapsStillDraw) {
  PlotSpec spec = lobe_spec();
  spec.y_log = true;
  spec.y_min = 0.5;
  spec.series[0].y[10] = std::nan("");
  spec.series[0].y[11] = std::numeric_limits<double>::infinity();
  spec.series.insert(spec.series.begin() + 1, PlotSeries{"Nothing", {}, {}, "points"});
  OutputTransaction outputs;
  write_plot(spec, dir_ / "F.png", outputs);
  outputs.commit();
  const std::string dat = read_file(dir_ / "F.dat");
  EXPECT_TRUE(contains(dat, " NaN\n")) << dat;
  EXPECT_TRUE(contains(dat,
                       "# Nothing\n# columns: 1 = Spindle speed [rpm], 2 = Critical depth "
                       "[mm]\nNaN NaN\n\n\n# Absolute limit"))
      << dat;
  const std::string gp = read_file(dir_ / "F.gp");
  EXPECT_TRUE(contains(gp, "set logscale y")) << gp;
  EXPECT_TRUE(contains(gp, "with filledcurves x1")) << gp;
  EXPECT_TRUE(contains(gp, "data index 2 using 1:2 with lines")) << gp;
}

TEST_F(PlotTest, NoDataAtAllStillDrawsEmptyAxes) {
  PlotSpec spec;
  spec.series.push_back(PlotSeries{"empty", {}, {}, "lines"});
  OutputTransaction outputs;
  write_plot(spec, dir_ / "F.png", outputs);
  outputs.commit();
  EXPECT_EQ(read_file(dir_ / "F.png").substr(0, 4), "\x89PNG");
}

TEST_F(PlotTest, ProgrammingErrorsInTheSpecAreLogicErrors) {
  OutputTransaction outputs;
  PlotSpec spec = lobe_spec();
  spec.series[1].y.pop_back();
  EXPECT_THROW(write_plot(spec, dir_ / "F.png", outputs), std::logic_error);
  spec = lobe_spec();
  spec.series[1].style = "bars";
  EXPECT_THROW(write_plot(spec, dir_ / "F.png", outputs), std::logic_error);
  EXPECT_THROW(write_plot(PlotSpec{}, dir_ / "F.png", outputs), std::logic_error);
}

TEST_F(PlotTest, MissingGnuplotThrowsAndLeavesNothing) {
  const fs::path empty_bin = dir_ / "bin";
  fs::create_directory(empty_bin);
  {
    OutputTransaction outputs;
    ScopedPath path(empty_bin.string());
    try {
      write_plot(lobe_spec(), dir_ / "F.png", outputs);
      FAIL() << "expected std::runtime_error";
    } catch (const std::runtime_error& e) {
      EXPECT_TRUE(contains(e.what(), "gnuplot is not installed")) << e.what();
    }
  }
  EXPECT_EQ(listing(dir_), std::vector<std::string>{"bin"});
}

TEST_F(PlotTest, GnuplotFailureCarriesItsStderrAndLeavesNothing) {
  const fs::path bin = dir_ / "bin";
  fs::create_directory(bin);
  {
    std::ofstream fake(bin / "gnuplot");
    fake << "#!/bin/sh\necho \"line 3: boom in $2\" >&2\nexit 3\n";
  }
  fs::permissions(bin / "gnuplot", fs::perms::owner_all);
  {
    OutputTransaction outputs;
    ScopedPath path(bin.string());
    try {
      write_plot(lobe_spec(), dir_ / "F.png", outputs);
      FAIL() << "expected std::runtime_error";
    } catch (const std::runtime_error& e) {
      EXPECT_TRUE(contains(e.what(), "exit status 3")) << e.what();
      EXPECT_TRUE(contains(e.what(), "line 3: boom in F.gp")) << e.what();
    }
  }
  EXPECT_EQ(listing(dir_), std::vector<std::string>{"bin"});
}

}  // namespace
}  // namespace cutdyn::io
