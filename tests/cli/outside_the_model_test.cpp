// Answers outside their model carry a word, and the figures say what they show: a speed above
// the spindle limit, a value in the wrong unit, a drive whose cut chatters; the lobes' depth
// axis fitted to the data, flip and fold marked, the limit and the target drawn; no notch
// reported as a pocket; standard output as a file for every command; a fit with no mode.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cutdyn/app/render.hpp"
#include "cutdyn/app/stability.hpp"
#include "cutdyn/io/case_file.hpp"
#include "cutdyn/stability/advice.hpp"
#include "support/cli_runner.hpp"
#include "support/temp_dir.hpp"

namespace cutdyn::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using testing::run_cutdyn;

class OutsideTheModel : public testing::TempDirTest {
 protected:
  std::string p(const std::string& name) const { return (dir_ / name).string(); }
  // milling-insperger (critical depth 0.07141 mm at 10 000 rpm) with the drives of ermolaev2020.
  std::string milling_with_drives() const {
    std::string text(*io::example_text("milling-insperger"));
    const std::string drives(*io::example_text("ermolaev2020"));
    text += "\n" + drives.substr(drives.find("[[drives]]"));
    std::ofstream(p("md.toml")) << text;
    return p("md.toml");
  }
};

TEST_F(OutsideTheModel, ADriveWhoseCutChattersSaysSo) {
  const std::string file = milling_with_drives();
  // 140 % of the critical depth: the simulation's verdict is chatter (as `simulate` gives it).
  const auto sim = run_cutdyn({"simulate", file, "--rpm", "10000", "--depth-mm", "0.1"});
  ASSERT_EQ(sim.code, 0) << sim.err;
  EXPECT_NE(sim.out.find("→ CHATTER"), std::string::npos) << sim.out;
  const auto r =
      run_cutdyn({"drive", file, "--rpm", "10000", "--depth-mm", "0.1", "--json", p("d.json")});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: " + file + ": the cut chatters at 10000 rpm, depth 0.1 mm"),
            std::string::npos)
      << r.err;
  const json d = json::parse(testing::read_file(p("d.json")));
  EXPECT_TRUE(d.at("chatter").get<bool>());
  EXPECT_EQ(d.at("warnings").size(), 1u);
  // Half the critical depth: stable, no word.
  const auto s = run_cutdyn({"drive", file, "--rpm", "10000", "--depth-mm", "0.035"});
  ASSERT_EQ(s.code, 0) << s.err;
  EXPECT_EQ(s.err.find("chatters"), std::string::npos) << s.err;
  // A sweep across the boundary flags the chattering points in its CSV and text.
  const auto w = run_cutdyn({"drive", file, "--rpm", "10000", "--sweep",
                             "simulate.depth_mm=0.035:0.065:0.1", "--out", p("w.csv")});
  ASSERT_EQ(w.code, 0) << w.err;
  const std::string csv = testing::read_file(p("w.csv"));
  EXPECT_NE(csv.find(",chatter\n"), std::string::npos) << csv;
  EXPECT_NE(w.out.find("  chatter\n"), std::string::npos) << w.out;
  EXPECT_NE(w.err.find("simulate.depth_mm = 0.1, the cut chatters"), std::string::npos) << w.err;
  EXPECT_EQ(w.err.find("simulate.depth_mm = 0.035, the cut chatters"), std::string::npos);
}

TEST_F(OutsideTheModel, ASpeedAboveTheSpindleLimitIsWarnedAbout) {
  const auto r = run_cutdyn({"check", "milling-insperger", "--rpm", "1e9", "--depth-mm", "0.01"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("warning: --rpm = 1e+09 rpm is above the spindle limit of 60000 rpm"),
            std::string::npos)
      << r.out;
  // Within the limit no word; the limit is the case's key.
  const auto ok =
      run_cutdyn({"check", "milling-insperger", "--rpm", "50000", "--depth-mm", "0.01"});
  EXPECT_EQ(ok.out.find("spindle limit"), std::string::npos) << ok.out;
  std::string text(*io::example_text("milling-insperger"));
  std::ofstream(p("slow.toml")) << "spindle_max_rpm = 8000\n" << text;
  const auto slow = run_cutdyn({"lobes", p("slow.toml")});
  ASSERT_EQ(slow.code, 0) << slow.err;
  EXPECT_NE(slow.err.find("lobes.rpm_max = 25000 rpm is above the spindle limit of 8000 rpm"),
            std::string::npos)
      << slow.err;
  // An absurd speed the methods cannot resolve is refused, not run for minutes.
  const auto turning =
      run_cutdyn({"check", "turning-ultrasonic", "--rpm", "2147483648", "--depth-mm", "1"});
  EXPECT_EQ(turning.code, 2);
  EXPECT_NE(turning.err.find("revolutions; the stability methods take at most 100"),
            std::string::npos)
      << turning.err;
  const auto crawl = run_cutdyn({"simulate", "milling-insperger", "--rpm", "30"});
  EXPECT_EQ(crawl.code, 2);  // (was std::bad_alloc, exit 1)
  EXPECT_NE(crawl.err.find("spans 922 periods of the 922 Hz mode"), std::string::npos) << crawl.err;
  const auto deep = run_cutdyn({"simulate", "milling-insperger", "--depth-mm", "1e308"});
  EXPECT_EQ(deep.code, 2);  // (was NaN in the report and exit 1)
  EXPECT_NE(deep.err.find("must be greater than 0 and at most 10000 mm"), std::string::npos)
      << deep.err;
}

TEST_F(OutsideTheModel, AUnitSlipIsNamedWithTheValueInTheProbableUnit) {
  std::string text(*io::example_text("milling-insperger"));
  const auto replace = [&](const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  };
  replace("kt_n_per_mm2 = 600", "kt_n_per_mm2 = 6e8");
  replace("diameter_mm = 20", "diameter_mm = 0.02");
  std::ofstream(p("slip.toml")) << text;
  const io::Case c = io::load_case_file(p("slip.toml"));
  ASSERT_EQ(c.warnings.size(), 2u);
  EXPECT_NE(c.warnings[0].find("cutting.kt_n_per_mm2 = 6e+08 N/mm² is far above"),
            std::string::npos)
      << c.warnings[0];
  EXPECT_NE(c.warnings[0].find("a value in Pa (N/m²)? In N/mm² that is 600"), std::string::npos)
      << c.warnings[0];
  EXPECT_NE(c.warnings[1].find("tool.diameter_mm = 0.02 mm is far below"), std::string::npos);
  EXPECT_NE(c.warnings[1].find("a value in metres? In mm that is 20"), std::string::npos);
  // A stiffness in N/mm.
  const io::Case soft = io::parse_case(
      "process = \"turning\"\n[[modes]]\ndirection = \"x\"\nnatural_hz = 228.8\n"
      "damping_ratio = 0.01\nstiffness_n_per_m = 2260\n[cutting]\nkf_n_per_mm2 = 850\n",
      "soft");
  ASSERT_EQ(soft.warnings.size(), 1u);
  EXPECT_NE(soft.warnings[0].find("a value in N/mm? In N/m that is 2.26e+06"), std::string::npos)
      << soft.warnings[0];
  // No example trips the table.
  for (const auto& [name, ignored] : io::examples())
    EXPECT_TRUE(io::load_example(name).warnings.empty()) << name;
}

TEST_F(OutsideTheModel, TheLobesFigureFitsTheDataAndTellsTheBoundariesApart) {
  // milling-variable-pitch: depths below 1 mm under a 3 mm limit, flip and fold rows.
  const io::Case c = io::load_example("milling-variable-pitch");
  app::LobesRequest request;
  request.target_depth_m = 0.2e-3;
  const app::LobesJobReport r = app::run_lobes(c, request);
  const io::PlotSpec f = app::figure(r);
  double top = 0.0;
  bool reached = false;
  for (const auto& p : r.lobes.points) {
    top = std::max(top, p.boundary.depth_m * 1e3);
    reached = reached || !p.boundary.found;
  }
  ASSERT_FALSE(reached);
  ASSERT_TRUE(f.y_max.has_value());
  EXPECT_NEAR(*f.y_max, 1.15 * top, 1e-12);
  EXPECT_LT(*f.y_max, c.lobes.depth_max_m * 1e3);
  std::vector<std::string> titles;
  for (const auto& s : f.series) titles.push_back(s.title);
  const auto has = [&](const std::string& start) {
    return std::any_of(titles.begin(), titles.end(),
                       [&](const std::string& t) { return t.rfind(start, 0) == 0; });
  };
  EXPECT_TRUE(has("fold boundary"));
  EXPECT_TRUE(has("target depth"));
  EXPECT_TRUE(has("recommended speed"));
  EXPECT_FALSE(has("depth limit"));
  // A case stable up to its limit at some speeds: the axis is the limit, drawn dashed.
  const app::LobesJobReport u = app::run_lobes(io::load_example("turning-ultrasonic"), {});
  const io::PlotSpec g = app::figure(u);
  EXPECT_DOUBLE_EQ(*g.y_max, 30.0);
  EXPECT_TRUE(std::any_of(g.series.begin(), g.series.end(), [](const io::PlotSeries& s) {
    return s.style == "dashed" && s.title.rfind("depth limit", 0) == 0;
  }));
}

TEST(Pockets, ANotchInAFlankIsNoPocket) {
  // A lobe's flank rising from 0.2 to 0.3 mm, with a dip of 5 % in it, then a drop: the peak
  // of the flank is a pocket, the rise after the dip is not.
  std::vector<LobePoint> pts;
  for (int i = 0; i <= 100; ++i) {
    LobePoint q;
    q.rpm = 9000.0 + 10.0 * i;
    double d = 0.2 + 0.001 * i;              // the flank
    if (i >= 40 && i <= 44) d *= 0.95;       // the notch
    if (i > 90) d = 0.29 - 0.02 * (i - 90);  // the drop after the peak
    q.boundary.depth_m = d * 1e-3;
    q.boundary.found = true;
    pts.push_back(q);
  }
  const auto pockets = stable_pockets(pts, 3);
  ASSERT_EQ(pockets.size(), 1u);
  EXPECT_EQ(pockets[0], 90u);
  const SpeedRange w = pocket_width(pts, 90);
  // 90 % of 0.29 mm = 0.261 mm: reached on the flank at i = 61, after the peak at i ≈ 91.45.
  EXPECT_NEAR(w.rpm_from, 9610.0, 1e-9);
  EXPECT_NEAR(w.rpm_to, 9914.5, 1e-9);
}

TEST_F(OutsideTheModel, StandardOutputIsAFileForEveryOutputOption) {
  // /dev/stdout is "-": the file on standard output, the report on stderr.
  const auto lobes = run_cutdyn({"lobes", "milling-insperger", "--out", "/dev/stdout"});
  ASSERT_EQ(lobes.code, 0) << lobes.err;
  EXPECT_EQ(lobes.out.rfind("spindle_rpm,critical_depth_mm", 0), 0u) << lobes.out;
  EXPECT_NE(lobes.err.find("cutdyn lobes: example milling-insperger"), std::string::npos);
  const auto twice =
      run_cutdyn({"lobes", "milling-insperger", "--out", "/dev/stdout", "--json", "-"});
  EXPECT_EQ(twice.code, 2);
  EXPECT_NE(twice.err.find("name the same file"), std::string::npos) << twice.err;
  // /dev/stderr: the file on standard error, the report stays on standard output.
  const auto err = run_cutdyn({"check", "milling-insperger", "--rpm", "9000", "--depth-mm", "0.05",
                               "--json", "/dev/stderr"});
  ASSERT_EQ(err.code, 0) << err.err;
  EXPECT_NE(err.out.find("cutdyn check"), std::string::npos);
  EXPECT_EQ(json::parse(err.err.substr(err.err.find('{'))).at("command"), "check");
  // The monitor's calibration and band on standard output are JSON and nothing else.
  const auto drive = run_cutdyn({"drive", "--currents", p("cur.csv")});
  ASSERT_EQ(drive.code, 0) << drive.err;
  const auto calibrate = run_cutdyn({"monitor", "calibrate", "--base", "zheng2012", "--measure",
                                     "space-vector", "--out", "/dev/stdout"});
  ASSERT_EQ(calibrate.code, 0) << calibrate.err;
  EXPECT_NO_THROW((void)json::parse(calibrate.out)) << calibrate.out;
  EXPECT_NE(calibrate.err.find("cutdyn monitor calibrate"), std::string::npos) << calibrate.err;
  std::ofstream(p("sv.json")) << calibrate.out;
  const auto teach =
      run_cutdyn({"monitor", "teach", "--calib", p("sv.json"), p("cur.csv"), "--out", "-"});
  ASSERT_EQ(teach.code, 0) << teach.err;
  EXPECT_NO_THROW((void)json::parse(teach.out)) << teach.out;
  EXPECT_NE(teach.err.find("cutdyn monitor teach"), std::string::npos) << teach.err;
  const auto estimate =
      run_cutdyn({"monitor", "estimate", "--calib", p("sv.json"), p("cur.csv"), "--out", "-"});
  ASSERT_EQ(estimate.code, 0) << estimate.err;
  EXPECT_EQ(estimate.out.rfind("time_s,axis,force_n", 0), 0u) << estimate.out.substr(0, 200);
  EXPECT_NE(estimate.err.find("cutdyn monitor estimate"), std::string::npos) << estimate.err;
}

TEST_F(OutsideTheModel, AFitThatFindsNoModeWritesNoModesFile) {
  const std::string frf = std::string(CUTDYN_EXAMPLES_DIR) + "/frf/tool_x.csv";
  const auto r = run_cutdyn({"fit", frf, "--band", "100:200", "--out", p("m.toml")});
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("no mode found in the band 100–200 Hz, so no [[modes]] to write"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(p("m.toml")));
  // Without --out the fit reports it (no file to stand for a structure).
  const auto report = run_cutdyn({"fit", frf, "--band", "100:200"});
  EXPECT_EQ(report.code, 0) << report.err;
}

}  // namespace
}  // namespace cutdyn::cli
