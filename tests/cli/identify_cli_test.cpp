// `cutdyn identify`: its text, the [cutting] table of --out read back by the case loader,
// --json against the job's report, the figure's data, and bad input refused with nothing
// written.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cutdyn/app/case_models.hpp"
#include "cutdyn/app/identify.hpp"
#include "cutdyn/app/report_json.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/io/case_file.hpp"
#include "support/cli_runner.hpp"
#include "support/plot_data.hpp"
#include "support/temp_dir.hpp"

namespace cutdyn::cli {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;
using Result = testing::CliResult;

const std::string kExampleForces =
    (fs::path(CUTDYN_SOURCE_DIR) / "examples" / "forces" / "milling-insperger-mean-forces.csv")
        .string();

Result cutdyn(const std::vector<std::string>& args) { return testing::run_cutdyn(args); }

class IdentifyCli : public testing::TempDirTest {
 protected:
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name), std::ios::binary) << text;
    return path(name);
  }
  // A run that must fail with exit 2, name `needle` on stderr and write no file.
  void expect_rejected(const std::vector<std::string>& args, const std::string& needle) {
    const auto before = testing::listing(dir_);
    const Result r = cutdyn(args);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_THAT(r.err, HasSubstr(needle));
    EXPECT_EQ(r.err.rfind("cutdyn: error: ", 0), 0u) << r.err;
    EXPECT_EQ(testing::listing(dir_), before) << "a rejected run wrote files";
  }
  // The job on the same inputs, for comparison.
  static app::IdentifyJobReport job() {
    app::IdentifyRequest request;
    request.force_files = {kExampleForces};
    return app::run_identify(app::load_case("", "milling-insperger"), request);
  }
};

TEST_F(IdentifyCli, PrintsTheCoefficientsAndResiduals) {
  const Result r = cutdyn({"identify", "milling-insperger", kExampleForces});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out.rfind("cutdyn identify: example milling-insperger with 6 cuts from " +
                            kExampleForces + "\n",
                        0),
            0u)
      << r.out;
  EXPECT_THAT(r.out, HasSubstr("2 teeth, engagement 0° … 180°"));
  EXPECT_THAT(r.out, HasSubstr("Kt (N/mm²)"));
  EXPECT_THAT(r.out, HasSubstr("Kre (N/mm)"));
  EXPECT_THAT(r.out, HasSubstr("milling-insperger-mean-forces.csv:12"));  // the last cut
  EXPECT_EQ(r.err, "");  // no warnings for the example
  EXPECT_THAT(cutdyn({"--help"}).out, HasSubstr("identify"));
  EXPECT_THAT(cutdyn({"identify", "--help"}).out, HasSubstr("[cutting] table"));
}

TEST_F(IdentifyCli, OutIsACuttingTableTheCaseLoaderReadsBack) {
  const Result r =
      cutdyn({"identify", "milling-insperger", kExampleForces, "--out", path("cutting.toml")});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("wrote " + path("cutting.toml")));
  const std::string table = testing::read_file(path("cutting.toml"));
  // The example case with its [cutting] table replaced by the one written.
  std::string text(*io::example_text("milling-insperger"));
  const auto at = text.find("\n[cutting]");
  ASSERT_NE(at, std::string::npos);
  text.replace(at + 1, text.find("\n[", at + 1) - at, table + "\n");
  const io::Case back = io::parse_case(text, "back.toml");
  const app::IdentifyJobReport j = job();
  EXPECT_NEAR(*back.cutting.kt_pa, j.fit.kt.value, 1e-12 * j.fit.kt.value);
  EXPECT_NEAR(*back.cutting.kr_pa, j.fit.kr.value, 1e-12 * j.fit.kr.value);
  EXPECT_NEAR(*back.cutting.kte_n_per_m, j.fit.kte.value, 1e-12 * j.fit.kte.value);
  EXPECT_NEAR(*back.cutting.kre_n_per_m, j.fit.kre.value, 1e-12 * j.fit.kre.value);

  // "-": the table on standard output, the report on standard error.
  const Result dash = cutdyn({"identify", "milling-insperger", kExampleForces, "--out", "-"});
  ASSERT_EQ(dash.code, 0) << dash.err;
  EXPECT_EQ(dash.out, table);
  EXPECT_THAT(dash.err, HasSubstr("cutdyn identify: "));
}

TEST_F(IdentifyCli, JsonHoldsTheJobsNumbers) {
  const Result r =
      cutdyn({"identify", "milling-insperger", kExampleForces, "--json", path("i.json")});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(testing::read_file(path("i.json")));
  const app::IdentifyJobReport j = job();
  EXPECT_EQ(doc["schema_version"], app::kJsonSchemaVersion);
  EXPECT_EQ(doc["command"], "identify");
  EXPECT_EQ(doc["source"], "example milling-insperger");
  EXPECT_EQ(doc["teeth"], 2);
  EXPECT_EQ(doc["exit_deg"].get<double>(), 180.0);
  EXPECT_EQ(doc["force_files"][0], kExampleForces);
  ASSERT_EQ(doc["coefficients"].size(), 4u);
  for (const app::IdentifiedValue& v : j.values) {
    const auto& k = doc["coefficients"][v.key];
    EXPECT_EQ(k["value"].get<double>(), v.value.value) << v.key;
    EXPECT_EQ(k["std_error"].get<double>(), v.value.std_error) << v.key;
    EXPECT_EQ(k["ci95_low"].get<double>(), v.value.ci95_low) << v.key;
    EXPECT_EQ(k["ci95_high"].get<double>(), v.value.ci95_high) << v.key;
    EXPECT_EQ(k["unit"], v.unit);
    EXPECT_TRUE(k["determined"].get<bool>());
  }
  EXPECT_EQ(doc["coefficients"]["kt_n_per_mm2"]["case_value"].get<double>(), 600.0);
  EXPECT_TRUE(doc["coefficients"]["kte_n_per_mm"]["case_value"].is_null());
  ASSERT_EQ(doc["samples"].size(), j.samples.size());
  for (std::size_t i = 0; i < j.samples.size(); ++i) {
    const auto& s = doc["samples"][i];
    EXPECT_EQ(s["label"], j.samples[i].measured.label);
    EXPECT_EQ(s["feed_per_tooth_mm"].get<double>(),
              units::m_to_mm(j.samples[i].measured.feed_per_tooth_m));
    EXPECT_EQ(s["fitted_fy_n"].get<double>(), j.samples[i].fitted_fy_n);
    EXPECT_EQ(s["residual_fx_n"].get<double>(), j.samples[i].residual.fx_n);
    EXPECT_FALSE(s.contains("fz_n"));
  }
  EXPECT_EQ(doc["r_squared"]["y"].get<double>(), j.fit.r_squared_y);
  EXPECT_TRUE(doc["r_squared"]["z"].is_null());
  EXPECT_EQ(doc["degrees_of_freedom"], 4);
  EXPECT_EQ(doc["t_quantile"].get<double>(), j.fit.t_quantile);
  EXPECT_TRUE(doc["warnings"].empty());
  EXPECT_EQ(doc["case"]["tool"]["teeth"], 2);
}

using testing::plot_block;

TEST_F(IdentifyCli, PlotShowsForcePerDepthAgainstFeed) {
  const Result r =
      cutdyn({"identify", "milling-insperger", kExampleForces, "--plot", path("f.svg")});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string gp = testing::read_file(path("f.gp"));
  const std::string dat = testing::read_file(path("f.dat"));
  EXPECT_THAT(gp, HasSubstr("feed per tooth (mm)"));
  EXPECT_THAT(gp, HasSubstr("mean force on the cutter per unit axial depth (N/mm)"));
  const app::IdentifyJobReport j = job();
  // Measured points: the samples' forces over their depth (2 mm).
  const auto fy = plot_block(dat, "Fy measured");
  ASSERT_EQ(fy.size(), 6u) << dat;
  EXPECT_NEAR(fy[0].first, 0.025, 1e-12);
  EXPECT_NEAR(fy[0].second, 40.015 / 2.0, 1e-9);
  // Fitted lines: at zero feed the edge forces alone; in slotting (docs/models/
  // identification.md) F̄x/a = −(z/π)·Kre and F̄y/a = (z/π)·Kte per mm of depth.
  const auto fx_line = plot_block(dat, "Fx (feed direction) fitted");
  const auto fy_line = plot_block(dat, "Fy fitted");
  ASSERT_EQ(fx_line.size(), 2u) << dat;
  ASSERT_EQ(fy_line.size(), 2u) << dat;
  const double kte = j.fit.kte.value / 1e3, kre = j.fit.kre.value / 1e3;  // N/mm
  EXPECT_NEAR(fx_line[0].second, -(2 / units::kPi) * kre, 1e-9);
  EXPECT_NEAR(fy_line[0].second, (2 / units::kPi) * kte, 1e-9);
  // Its slope (z/4)·Kt per mm of feed and depth.
  const double kt = j.fit.kt.value / 1e6;  // N/mm²
  EXPECT_NEAR((fy_line[1].second - fy_line[0].second) / (fy_line[1].first - fy_line[0].first),
              0.5 * kt, 1e-6 * kt);
  EXPECT_TRUE(plot_block(dat, "Fz (axial) measured").empty());
}

TEST_F(IdentifyCli, BadInputExitsTwoAndWritesNothing) {
  const std::string out = path("c.toml");
  expect_rejected({"identify", "milling-insperger", path("missing.csv"), "--out", out},
                  "missing.csv: cannot read the file");
  const std::string bad =
      write("bad.csv", "feed_per_tooth_mm,depth_mm,fx_n,fy_n\n0.05,2,-40,55\n0.1,2,-50,x\n");
  expect_rejected({"identify", "milling-insperger", bad, "--out", out, "--json", path("i.json")},
                  "line 3, column fy_n: \"x\" is not a number");
  expect_rejected({"identify", "turning-ultrasonic", kExampleForces, "--out", out},
                  "process = \"turning\"");
  const std::string no_tool =
      write("no-tool.toml", "process = \"milling\"\n[operation]\nradial_immersion = 1\n");
  expect_rejected({"identify", no_tool, kExampleForces, "--out", out},
                  "tool: missing (required by `cutdyn identify`");
  // An output naming an input (a force file, the case file) would overwrite it.
  const std::string forces = write("forces.csv", testing::read_file(kExampleForces));
  expect_rejected({"identify", "milling-insperger", forces, "--json", forces},
                  "--json = " + forces + ": it is an input of the command");
  expect_rejected({"identify", no_tool, forces, "--out", no_tool},
                  "--out = " + no_tool + ": it is an input of the command");
  expect_rejected({"identify", "milling-insperger", kExampleForces, "--plot", path("f.txt")},
                  "f.txt");
  expect_rejected({"identify", "milling-insperger"}, "FORCES is required");
  expect_rejected(
      {"identify", "milling-insperger", kExampleForces, "--out", path("no-folder/c.toml")},
      "does not exist");
  EXPECT_THAT(testing::read_file(no_tool), HasSubstr("[operation]"));  // untouched
  EXPECT_EQ(testing::read_file(forces), testing::read_file(kExampleForces));
}

TEST_F(IdentifyCli, WarningsGoToStandardError) {
  // Two feeds: exact values, no intervals, warned about.
  const std::string two =
      write("two.csv", "feed_per_tooth_mm,depth_mm,fx_n,fy_n\n0.05,2,-40,55\n0.1,2,-52,87\n");
  const Result r = cutdyn({"identify", "milling-insperger", two});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(r.err,
              HasSubstr("cutdyn: warning: example milling-insperger: only 2 distinct feeds"));
  EXPECT_THAT(r.out, Not(HasSubstr("warning")));
  EXPECT_THAT(r.out, HasSubstr("0 degrees of freedom\n"));
  EXPECT_THAT(r.out, Not(HasSubstr("(t = ")));
}

}  // namespace
}  // namespace cutdyn::cli
