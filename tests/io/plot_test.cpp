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
  EXPECT_TRUE(contains(gp, "set key top left")) << gp;
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
