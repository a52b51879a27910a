// The `cutdyn` command line, run in-process through cli::run (and once as a real process).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli/app.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/drive/equivalent_current.hpp"
#include "cutdyn/forces/oxley.hpp"
#include "cutdyn/io/case_file.hpp"
#include "cutdyn/plan/bore_milling.hpp"
#include "cutdyn/simulate/milling_simulation.hpp"
#include "cutdyn/stability/full_discretization.hpp"
#include "cutdyn/stability/milling.hpp"
#include "cutdyn/stability/tlusty.hpp"
#include "support/cli_runner.hpp"
#include "support/reference_cases.hpp"
#include "support/temp_dir.hpp"

namespace cutdyn::cli {
namespace {

namespace fs = std::filesystem;

using Result = testing::CliResult;

Result cutdyn(const std::vector<std::string>& args) { return testing::run_cutdyn(args); }

class Cli : public testing::TempDirTest {
 protected:
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name)) << text;
    return path(name);
  }
  // The default example with one line replaced.
  std::string variant(const std::string& from, const std::string& to) const {
    std::string text(*io::example_text("turning-ultrasonic"));
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    return write("case.toml", text);
  }
  std::vector<std::string> files() const { return testing::listing(dir_); }
  // A run that must fail with exit 2, name `needle` on stderr and leave no output file.
  void expect_rejected(std::vector<std::string> args, const std::string& needle) {
    const auto before = files();
    const Result r = cutdyn(args);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << "stderr: " << r.err;
    EXPECT_EQ(r.err.rfind("cutdyn: error: ", 0), 0u) << r.err;
    EXPECT_EQ(files(), before) << "a rejected run wrote files";
  }
};

std::vector<std::string> csv_lines(const std::string& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST_F(Cli, VersionHelpAndExamples) {
  EXPECT_EQ(cutdyn({"--version"}).out.rfind("cutdyn ", 0), 0u);
  const Result help = cutdyn({"--help"});
  EXPECT_EQ(help.code, 0);
  for (const char* cmd : {"example", "lobes", "check", "simulate", "force"})
    EXPECT_NE(help.out.find(cmd), std::string::npos) << cmd;
  EXPECT_NE(cutdyn({"lobes", "--help"}).out.find("--plot"), std::string::npos);
  const Result list = cutdyn({"example", "--list"});
  EXPECT_NE(list.out.find("turning-ultrasonic"), std::string::npos);
  const Result text = cutdyn({"example", "turning-ultrasonic"});
  EXPECT_EQ(text.out, std::string(*io::example_text("turning-ultrasonic")));
  // The printed example is a valid case file.
  EXPECT_NO_THROW(io::parse_case(text.out, "printed"));
}

TEST_F(Cli, LobesWritesCsvJsonAndPlotForTheDefaultCase) {
  const Result r =
      cutdyn({"lobes", "--out", path("l.csv"), "--json", path("l.json"), "--plot", path("l.svg")});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(files(), (std::vector<std::string>{"l.csv", "l.dat", "l.gp", "l.json", "l.svg"}));
  const auto lines = csv_lines(path("l.csv"));
  ASSERT_GT(lines.size(), 201u);  // header + 200 speeds + those the refinement adds
  EXPECT_EQ(lines[0].rfind("spindle_rpm,critical_depth_mm,chatter_hz,lobe", 0), 0u);
  double previous = 0.0;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const double rpm = std::stod(lines[i]);
    EXPECT_GT(rpm, previous);
    previous = rpm;
    EXPECT_EQ(lines[i].find("nan"), std::string::npos);
  }
  const auto doc = nlohmann::json::parse(std::ifstream(path("l.json")));
  EXPECT_EQ(doc["method"], "full-discretization");
  EXPECT_EQ(doc["case"]["vibration"]["duty_cycle"], 0.6);
  ASSERT_EQ(doc["points"].size(), lines.size() - 1);
  // At 500 rpm against the library's closed forms, in mm and Hz: conventional = Tlusty
  // exactly, vibration-assisted = averaged theory (Kt → 0.6·Kt, exact for f ≫ fn) within 0.1 %.
  const TurningProcess m = cutdyn::testing::table2_conventional();
  const auto tlusty = tlusty_critical_depth(m.modal, Direction::kX, m.kf_pa, 60.0 / 500.0, 0.03);
  const auto averaged =
      tlusty_critical_depth(m.modal, Direction::kX, 0.6 * m.kf_pa, 60.0 / 500.0, 0.03);
  const auto& first = doc["points"][0];
  EXPECT_NEAR(first["spindle_rpm"].get<double>(), 500.0, 1e-9);
  EXPECT_NEAR(first["conventional_depth_mm"].get<double>(), 1e3 * tlusty.boundary.depth_m, 1e-9);
  EXPECT_NEAR(first["critical_depth_mm"].get<double>(), 1e3 * averaged.boundary.depth_m,
              1e-3 * 1e3 * averaged.boundary.depth_m);
  EXPECT_NEAR(first["chatter_hz"].get<double>(), averaged.boundary.chatter_hz, 0.05);
  EXPECT_EQ(first["lobe"].get<int>(), averaged.lobe);
  EXPECT_NE(r.out.find("lowest critical depth"), std::string::npos);
}

TEST_F(Cli, LobesMethodsAgreeOnTheConventionalCase) {
  const std::string conventional(*io::example_text("turning-conventional"));
  const auto file = write("c.toml", conventional);
  std::vector<nlohmann::json> docs;
  for (const char* method : {"closed-form", "full-discretization", "multi-frequency"}) {
    const std::string out = path(std::string(method) + ".json");
    ASSERT_EQ(cutdyn({"lobes", file, "--method", method, "--json", out}).code, 0);
    docs.push_back(nlohmann::json::parse(std::ifstream(out)));
  }
  for (std::size_t i = 0; i < 200; i += 7) {
    const double exact = docs[0]["points"][i]["critical_depth_mm"];
    EXPECT_NEAR(docs[1]["points"][i]["critical_depth_mm"].get<double>(), exact, 0.01 * exact);
    EXPECT_NEAR(docs[2]["points"][i]["critical_depth_mm"].get<double>(), exact, 1e-6 * exact);
  }
}

TEST_F(Cli, CheckReportsStabilityAndMargin) {
  const Result stable =
      cutdyn({"check", "--rpm", "1400", "--depth-mm", "10", "--json", path("c.json")});
  ASSERT_EQ(stable.code, 0) << stable.err;
  EXPECT_NE(stable.out.find("STABLE"), std::string::npos);
  const auto doc = nlohmann::json::parse(std::ifstream(path("c.json")));
  EXPECT_TRUE(doc["stable"].get<bool>());
  const TurningProcess m = cutdyn::testing::table2_conventional();
  const double averaged_mm =
      1e3 * tlusty_critical_depth(m.modal, Direction::kX, 0.6 * m.kf_pa, 60.0 / 1400.0, 0.03)
                .boundary.depth_m;
  EXPECT_NEAR(doc["critical_depth_mm"].get<double>(), averaged_mm, 1e-3 * averaged_mm);
  EXPECT_NEAR(doc["margin"].get<double>(), 1.0 - 10.0 / doc["critical_depth_mm"].get<double>(),
              1e-12);
  EXPECT_FALSE(doc["conventional"]["stable"].get<bool>());  // 10 mm > 6.74 mm
  const Result unstable = cutdyn({"check", "--rpm", "1400", "--depth-mm", "12"});
  EXPECT_NE(unstable.out.find("UNSTABLE"), std::string::npos);
}

TEST_F(Cli, SimulateComparesBothProcesses) {
  const Result r = cutdyn({"simulate", "--duration-s", "1", "--out", path("s.csv"), "--json",
                           path("s.json"), "--plot", path("s.png")});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(std::ifstream(path("s.json")));
  ASSERT_EQ(doc["results"].size(), 2u);
  // 10 mm at 1400 rpm: below the vibration-assisted boundary (11.2 mm), above the
  // conventional one (6.7 mm).
  EXPECT_EQ(doc["results"][0]["process"], "vibration-assisted");
  EXPECT_FALSE(doc["results"][0]["chatter"].get<bool>());
  EXPECT_EQ(doc["results"][1]["process"], "conventional");
  EXPECT_TRUE(doc["results"][1]["chatter"].get<bool>());
  const auto lines = csv_lines(path("s.csv"));
  EXPECT_EQ(lines[0], "process,time_s,displacement_um,force_n,chip_thickness_um");
  EXPECT_GT(lines.size(), 1000u);
}

TEST_F(Cli, ForceReportsTheSourceTable1Values) {
  const Result r = cutdyn({"force", "--json", path("f.json")});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(std::ifstream(path("f.json")));
  EXPECT_NEAR(doc["duty_cycle"].get<double>(), 0.4095, 5e-4);
  EXPECT_NEAR(doc["mean_cutting_force_n"].get<double>(), 25.8, 0.05);
  EXPECT_NEAR(doc["mean_thrust_force_n"].get<double>(), 14.7, 0.05);
  EXPECT_NEAR(doc["cutting_force_n"].get<double>(), 63.0, 1e-9);
  EXPECT_NEAR(doc["vibration"]["period_s"].get<double>(), 50e-6, 1e-15);
  EXPECT_NEAR(doc["vibration"]["critical_speed_m_per_min"].get<double>(), 150.796, 1e-3);
}

TEST_F(Cli, ForcePredictsTheCoefficientsFromTheMaterial) {
  // The example oxley-aisi1045: AISI 1045, 200 m/min, 0.15 mm, 1.6 mm, rake −7°.
  const Result r =
      cutdyn({"force", "oxley-aisi1045", "--json", path("f.json"), "--plot", path("f.png")});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_GT(fs::file_size(path("f.png")), 1000u);  // forces against the chip thickness
  const auto doc = nlohmann::json::parse(std::ifstream(path("f.json")));
  const OrthogonalCut cut{200.0 / 60.0, 0.15e-3, 1.6e-3, units::deg_to_rad(-7.0), 20.0};
  const OxleyResult lib = oxley_orthogonal(*find_material("AISI1045"), cut);
  EXPECT_EQ(doc["coefficients"], "oxley");
  EXPECT_NEAR(doc["cutting_force_n"].get<double>(), lib.state.cutting_force_n, 1e-9);
  EXPECT_NEAR(doc["thrust_force_n"].get<double>(), lib.state.thrust_force_n, 1e-9);
  EXPECT_NEAR(doc["kc_n_per_mm2"].get<double>(), lib.kc_pa / 1e6, 1e-9);
  EXPECT_NEAR(doc["kf_n_per_mm2"].get<double>(), lib.kt_pa / 1e6, 1e-9);
  EXPECT_NEAR(doc["shear_angle_deg"].get<double>(), units::rad_to_deg(lib.state.phi_rad), 1e-9);
  EXPECT_NEAR(doc["chip_thickness_mm"].get<double>(), lib.state.chip_thickness_m * 1e3, 1e-9);
  EXPECT_NEAR(doc["oxley"]["interface_temperature_c"].get<double>(),
              lib.state.temperature_interface_c, 1e-9);
  EXPECT_EQ(doc["case"]["material"]["name"], "AISI1045");
  // Conventional cutting: the mean is the whole force.
  EXPECT_NEAR(doc["mean_cutting_force_n"].get<double>(), lib.state.cutting_force_n, 1e-9);
}

TEST_F(Cli, ForceWithVibrationGivesThePulsedMeansOfThePredictedForces) {
  const Result r = cutdyn({"force", "ultrasonic-force-aa5083", "--json", path("f.json")});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(std::ifstream(path("f.json")));
  const double duty = doc["duty_cycle"].get<double>();
  EXPECT_NEAR(duty, 0.4095, 5e-4);  // the source's table 1
  EXPECT_NEAR(doc["mean_cutting_force_n"].get<double>(),
              duty * doc["cutting_force_n"].get<double>(), 1e-9);
  EXPECT_NEAR(doc["mean_thrust_force_n"].get<double>(), duty * doc["thrust_force_n"].get<double>(),
              1e-9);
  EXPECT_NEAR(doc["cutting_force_n"].get<double>(), doc["kc_n_per_mm2"].get<double>() * 0.15 * 0.2,
              1e-9);
}

TEST_F(Cli, LobesUseThePredictedKt) {
  // The closed-form minimum depth 2ζ(1 + ζ)k/Kt with Kt from the theory.
  const Result r = cutdyn({"lobes", "oxley-aisi1045", "--json", path("l.json")});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("predicted for AISI1045 by Oxley's theory"), std::string::npos) << r.out;
  const OrthogonalCut cut{200.0 / 60.0, 0.15e-3, 1e-3, units::deg_to_rad(-7.0), 20.0};
  const double kt = oxley_orthogonal(*find_material("AISI1045"), cut).kt_pa;
  const auto doc = nlohmann::json::parse(std::ifstream(path("l.json")));
  double lowest = 1e9;
  for (const auto& p : doc["points"])
    lowest = std::min(lowest, p["critical_depth_mm"].get<double>());
  const double a_min = 2.0 * 0.01 * 1.01 * 2.26e8 / kt * 1e3;
  EXPECT_GT(lowest, a_min * (1.0 - 1e-9));
  EXPECT_LT(lowest, a_min * 1.02);  // 200 speeds sample the lobe bottoms closely
}

TEST_F(Cli, RejectsMaterialProblems) {
  const std::string base(*io::example_text("oxley-aisi1045"));
  const auto with = [&](const std::string& from, const std::string& to) {
    std::string text = base;
    text.replace(text.find(from), from.size(), to);
    return write("case.toml", text);
  };
  expect_rejected(
      {"force", with("name = \"AISI1045\"", "name = \"AISI1046\""), "--json", path("f.json")},
      "material.name = \"AISI1046\": is not in the material library (AISI1045");
  expect_rejected({"force", with("rake_deg = -7", ""), "--json", path("f.json")},
                  "cutting.rake_deg: missing (required by `cutdyn force` to predict");
  expect_rejected(
      {"force", with("speed_m_per_min = 200", "speed_m_per_min = 5\nkt_n_per_mm2 = 900"), "--json",
       path("f.json")},
      "give the force coefficients or the material to predict them from, not both");
  // Outside the theory: a slow cut of a thin chip.
  std::string slow = base;
  slow.replace(slow.find("speed_m_per_min = 200"), 21, "speed_m_per_min = 5");
  slow.replace(slow.find("uncut_chip_thickness_mm = 0.15"), 30, "uncut_chip_thickness_mm = 0.01");
  expect_rejected({"force", write("slow.toml", slow), "--json", path("f.json")},
                  "outside the theory's validity");
  expect_rejected({"lobes", path("slow.toml"), "--out", path("l.csv")},
                  "outside the theory's validity");
}

// One test per kind of bad input (a missing key, a wrong type, a value out of range, an
// unknown key, a bad process): exit 2, the key named, no output file.
TEST_F(Cli, RejectsMissingKey) {
  const auto file = variant("kf_n_per_mm2 = 850", "");
  expect_rejected({"lobes", file, "--out", path("o.csv")}, "cutting.kf_n_per_mm2: missing");
}

TEST_F(Cli, RejectsWrongType) {
  const auto file = variant("natural_hz = 228.8", "natural_hz = \"228.8\"");
  expect_rejected({"lobes", file, "--out", path("o.csv")}, "modes[0].natural_hz = \"228.8\"");
}

TEST_F(Cli, RejectsNegativeMass) {
  const auto file = variant("stiffness_n_per_m = 2.26e8", "mass_kg = -0.1");
  expect_rejected({"lobes", file, "--json", path("o.json")}, "modes[0].mass_kg = -0.1");
}

TEST_F(Cli, RejectsDampingOfOneOrMore) {
  const auto file = variant("damping_ratio = 0.01", "damping_ratio = 1.0");
  expect_rejected({"lobes", file, "--out", path("o.csv")}, "modes[0].damping_ratio = 1.0");
}

TEST_F(Cli, RejectsZeroImmersion) {
  // [operation] is a milling table (a turning case refuses it: docs/case-files.md).
  std::string text(*io::example_text("milling-insperger"));
  text.replace(text.find("radial_immersion = 1.0"), 22, "radial_immersion = 0");
  expect_rejected({"lobes", write("case.toml", text), "--out", path("o.csv")},
                  "operation.radial_immersion = 0");
}

TEST_F(Cli, RejectsRpmMinNotBelowRpmMax) {
  const auto file = variant("rpm_min = 500", "rpm_min = 5000");
  expect_rejected({"lobes", file, "--out", path("o.csv")}, "lobes.rpm_max = 5000");
}

TEST_F(Cli, RejectsNan) {
  const auto file = variant("kf_n_per_mm2 = 850", "kf_n_per_mm2 = nan");
  expect_rejected({"lobes", file, "--plot", path("o.png")}, "cutting.kf_n_per_mm2 = nan");
}

TEST_F(Cli, RejectsUnknownKey) {
  const auto file = variant("rpm_steps = 200", "rpm_stepz = 200");
  expect_rejected({"lobes", file, "--out", path("o.csv")},
                  "lobes.rpm_stepz: unknown key (did you mean rpm_steps?)");
}

TEST_F(Cli, RejectsAbsurdGrid) {
  const auto file = variant("rpm_steps = 200", "rpm_steps = 50000000");
  expect_rejected({"lobes", file, "--out", path("o.csv")}, "lobes.rpm_steps = 50000000");
  const auto slow = variant("rpm_min = 500", "rpm_min = 0.01");
  expect_rejected({"lobes", slow, "--out", path("o.csv")},
                  "lobes.rpm_min: spindle speed = 0.01 rpm");
}

TEST_F(Cli, RejectsSyntaxErrorWithLine) {
  const auto file = write("bad.toml", "process = \"turning\"\n[[modes]\n");
  expect_rejected({"lobes", file, "--out", path("o.csv")}, "bad.toml: line 2");
}

TEST_F(Cli, RejectsBadCommandLine) {
  expect_rejected({"lobes", "--method", "fast", "--out", path("o.csv")}, "--method = \"fast\"");
  expect_rejected({"lobes", "--plot", path("o.jpg")}, "unsupported figure format");
  expect_rejected({"lobes", "--out", path("missing/o.csv")}, "does not exist");
  expect_rejected({"check", "--depth-mm", "3"}, "--rpm is required");
  expect_rejected({"check", "--rpm", "-5", "--depth-mm", "3"}, "--rpm = -5");
  expect_rejected({"lobes", path("none.toml")}, "cannot read the file");
  expect_rejected({"example", "nope"}, "available: ");
  expect_rejected({"frobnicate"}, "frobnicate");
}

TEST_F(Cli, RejectsMissingFeedForSimulation) {
  const auto file = variant("uncut_chip_thickness_mm = 0.05", "");
  expect_rejected({"simulate", file, "--out", path("o.csv")},
                  "cutting.uncut_chip_thickness_mm: missing");
}

TEST_F(Cli, RejectsMillingCaseWithoutTool) {
  // A milling case (the turning example's [vibration] and turning keys would be refused).
  std::string text(*io::example_text("milling-insperger"));
  const auto at = text.find("[tool]");
  text.erase(at, text.find("[operation]") - at);
  expect_rejected({"lobes", write("case.toml", text), "--out", path("o.csv")}, "tool: missing");
}

TEST_F(Cli, RealProcessExitCodesAndStreams) {
  const std::string bin = CUTDYN_BINARY;
  const auto file = variant("damping_ratio = 0.01", "damping_ratio = -1");
  const std::string cmd = bin + " lobes " + file + " --out " + path("o.csv") + " 2>" +
                          path("err.txt") + " >" + path("out.txt");
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2);
  std::ifstream err(path("err.txt"));
  std::string line;
  std::getline(err, line);
  EXPECT_EQ(line, "cutdyn: error: " + file +
                      ": modes[0].damping_ratio = -1: must be at least 0 and less than 1");
  EXPECT_FALSE(fs::exists(path("o.csv")));
}

TEST_F(Cli, MillingLobesAndCheck) {
  // The Insperger–Stépán slotting benchmark through the command line, against the library.
  std::string text(*io::example_text("milling-insperger"));
  text.replace(text.find("rpm_steps = 200"), 15, "rpm_steps = 21\nrefine = false");
  const auto file = write("mill.toml", text);
  ASSERT_EQ(cutdyn({"lobes", file, "--out", path("m.csv")}).code, 0);
  const auto lines = csv_lines(path("m.csv"));
  ASSERT_EQ(lines.size(), 22u);
  EXPECT_EQ(lines[0].rfind("spindle_rpm,critical_depth_mm,chatter_hz,lobe,bifurcation", 0), 0u);
  const io::Case c = io::parse_case(text, "mill");
  MillingProcess m;
  m.modal = c.modal;
  m.cutting.kt_pa = *c.cutting.kt_pa;
  m.cutting.kr_pa = *c.cutting.kr_pa;
  m.tool.teeth = 2;
  const DelayedSystem s = milling_system(m, 5000.0);
  FdOptions o;
  o.depth_max_m = 1e-3;
  const CriticalDepth fd = fd_critical_depth_by_radius(s, o, RadiusSolver::kArnoldi, 1e-4, 16);
  EXPECT_NEAR(std::stod(lines[1].substr(lines[1].find(',') + 1)), 1e3 * fd.depth_m,
              2e-3 * 1e3 * fd.depth_m);
  const Result r =
      cutdyn({"check", file, "--rpm", "5000", "--depth-mm", "0.04", "--json", path("c.json")});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(std::ifstream(path("c.json")));
  EXPECT_TRUE(doc["stable"].get<bool>());
  EXPECT_EQ(doc["bifurcation"], "hopf");
  EXPECT_NEAR(doc["critical_depth_mm"].get<double>(), 1e3 * fd.depth_m, 2e-3 * 1e3 * fd.depth_m);
}

TEST_F(Cli, MillingVariablePitchHelicalExample) {
  // The example cutter (4 flutes, 70/110° pitch, 30° helix) through the command line: every
  // speed resolved, the first against the library with the model built by hand, and the pitch
  // echoed in the JSON.
  std::string text(*io::example_text("milling-variable-pitch"));
  text.replace(text.find("rpm_steps = 200"), 15, "rpm_steps = 9\nrefine = false");
  const auto file = write("vp.toml", text);
  const Result r = cutdyn({"lobes", file, "--out", path("vp.csv"), "--json", path("vp.json")});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("4 teeth, helix 30°, pitch 70/110/70/110°"), std::string::npos) << r.out;
  const auto lines = csv_lines(path("vp.csv"));
  ASSERT_EQ(lines.size(), 10u);
  MillingProcess m = testing::insperger_benchmark(0.5);
  m.tool.teeth = 4;
  m.tool.helix_rad = units::deg_to_rad(30.0);
  const double a = units::deg_to_rad(70.0), b = units::deg_to_rad(110.0);
  m.tool.pitch_rad = {a, b, a, b};
  MillingStabilityOptions o;
  o.depth_max_m = 1e-3;
  o.rel_tol = 1e-5;
  const MillingBoundary lib = milling_critical_depth(m, 4000.0, o);
  ASSERT_TRUE(lib.boundary.found);
  EXPECT_NEAR(std::stod(lines[1].substr(lines[1].find(',') + 1)), 1e3 * lib.boundary.depth_m,
              2e-3 * 1e3 * lib.boundary.depth_m);
  const auto doc = nlohmann::json::parse(std::ifstream(path("vp.json")));
  EXPECT_EQ(doc["case"]["tool"]["pitch_deg"], nlohmann::json::parse("[70, 110, 70, 110]"));
  for (const auto& p : doc["points"]) EXPECT_TRUE(p["critical_depth_mm"].is_number());
}

TEST_F(Cli, CaseMayNameABuiltInExampleUnlessAFileHasThatName) {
  const Result r = cutdyn({"check", "milling-insperger", "--rpm", "5000", "--depth-mm", "0.04"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("milling, 2 teeth"), std::string::npos) << r.out;
  // A file of that name comes first (here: a turning case, in the working directory).
  write("milling-insperger", std::string(*io::example_text("turning-conventional")));
  const fs::path cwd = fs::current_path();
  fs::current_path(dir_);
  const Result t = cutdyn({"check", "milling-insperger", "--rpm", "1400", "--depth-mm", "1"});
  fs::current_path(cwd);
  ASSERT_EQ(t.code, 0) << t.err;
  EXPECT_NE(t.out.find("turning"), std::string::npos) << t.out;
  expect_rejected({"check", "no-such-example", "--rpm", "5000", "--depth-mm", "0.04"},
                  "no-such-example: cannot read the file");
}

TEST_F(Cli, MillingSimulationAgreesWithTheLobesAndWritesItsOutputs) {
  // The milling example's [simulate] point (90 % of the predicted critical depth at
  // 10 000 rpm) is stable; at 112 % it chatters. Outputs: traces, summary, figure.
  const Result r = cutdyn({"simulate", "milling-insperger", "--json", path("s.json"), "--out",
                           path("s.csv"), "--plot", path("s.png")});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(std::ifstream(path("s.json")));
  const auto& summary = doc["summary"];
  EXPECT_FALSE(summary["chatter"].get<bool>());
  EXPECT_NEAR(summary["predicted_critical_depth_mm"].get<double>(), 0.0715, 0.001);
  EXPECT_NEAR(summary["mean_teeth_in_cut"].get<double>(), 1.0, 0.01);  // slotting, 2 teeth
  EXPECT_NEAR(summary["force_pulsation"].get<double>(), 1.0, 1e-12);   // chip 0 at 0 and π
  const auto lines = csv_lines(path("s.csv"));
  ASSERT_GT(lines.size(), 1000u);
  EXPECT_EQ(lines[0], "time_s,fx_n,fy_n,force_n,x_um,y_um,teeth_in_cut,cutting_force_n");
  EXPECT_TRUE(fs::exists(path("s.png")));
  const Result chatter = cutdyn({"simulate", "milling-insperger", "--depth-mm", "0.08"});
  ASSERT_EQ(chatter.code, 0) << chatter.err;
  EXPECT_NE(chatter.out.find("CHATTER"), std::string::npos) << chatter.out;
}

TEST_F(Cli, MillingSimulationOfTheS1Preset) {
  // The ermolaev2020 example: the S1 law through the case file, against the library with the
  // preset built by hand (relative units as 1 mm, N).
  const Result r = cutdyn({"simulate", "ermolaev2020", "--json", path("e.json")});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(std::ifstream(path("e.json")));
  MillingCut cut;
  const double k = 1e7, m = 1.0;
  for (Direction d : {Direction::kX, Direction::kY})
    cut.process.modal.modes.push_back(Mode{d, std::sqrt(k / m), 0.1 / (2 * std::sqrt(k * m)), k});
  cut.process.tool.teeth = 5;
  cut.process.tool.diameter_m = 0.02;
  cut.process.tool.helix_rad = units::deg_to_rad(30.0);
  cut.width_m =
      (units::kPi / 6) * cut.process.tool.diameter_m / (2 * std::tan(cut.process.tool.helix_rad));
  cut.process.engagement.entry_rad = units::kPi / 6;
  cut.process.engagement.exit_rad = units::kPi;
  cut.spindle_rad_s = 2 * units::kPi;
  cut.feed_per_tooth_m = 1e-3;
  cut.process.s1_law = ErmolaevForceLaw{25e3, 0.2, 3.0, 0.2e-3, 0.0, units::kPi / 5};
  cut.regenerative = false;
  MillingSimulationOptions o;
  o.revolutions = 6;
  o.summary_revolutions = 1;
  o.steps_per_tooth = 200;
  const MillingSimulationResult lib = simulate_milling(cut, o);
  EXPECT_NEAR(doc["summary"]["force_pulsation"].get<double>(), lib.force_pulsation, 1e-9);
  EXPECT_NEAR(doc["summary"]["mean_force_n"].get<double>(), lib.mean_force_n,
              1e-9 * lib.mean_force_n);
  EXPECT_EQ(doc["force_law"], "s1");
}

TEST_F(Cli, MillingSweepTabulatesTheMetricOverTheRange) {
  // force_law.t2_s = 0, 0.1, ..., 0.3 on the ermolaev2020 preset: each row equals a single run of
  // the case with that value, and the CSV has every metric.
  const Result r =
      cutdyn({"simulate", "ermolaev2020", "--sweep", "force_law.t2_s=0:0.1:0.3", "--json",
              path("w.json"), "--out", path("w.csv"), "--plot", path("w.png")});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(std::ifstream(path("w.json")));
  ASSERT_EQ(doc["points"].size(), 4u);
  EXPECT_EQ(doc["sweep"], "force_law.t2_s");
  std::string text(*io::example_text("ermolaev2020"));
  text.replace(text.find("t2_s = 0.2"), 10, "t2_s = 0.3");
  const Result single = cutdyn({"simulate", write("t03.toml", text), "--json", path("s.json")});
  ASSERT_EQ(single.code, 0) << single.err;
  const auto one = nlohmann::json::parse(std::ifstream(path("s.json")));
  EXPECT_DOUBLE_EQ(doc["points"][3]["value"].get<double>(), 0.3);
  EXPECT_DOUBLE_EQ(doc["points"][3]["force_pulsation"].get<double>(),
                   one["summary"]["force_pulsation"].get<double>());
  const auto lines = csv_lines(path("w.csv"));
  ASSERT_EQ(lines.size(), 5u);
  EXPECT_EQ(lines[0].rfind("force_law.t2_s,force_pulsation,mean_force_n,", 0), 0u);
  EXPECT_TRUE(fs::exists(path("w.png")));
  // Bad sweeps: the syntax, a value the key does not take, an unknown metric; nothing written.
  expect_rejected(
      {"simulate", "ermolaev2020", "--sweep", "force_law.t2_s=0:-1:1", "--out", path("bad.csv")},
      "STEP must be positive");
  expect_rejected(
      {"simulate", "ermolaev2020", "--sweep", "tool.teeth=1:0.5:2", "--out", path("bad.csv")},
      "example ermolaev2020: tool.teeth = 1.5: wrong type: expected an integer");
  expect_rejected({"simulate", "ermolaev2020", "--sweep", "tool.teeth=2:1:3", "--metric", "nope",
                   "--out", path("bad.csv")},
                  "--metric = \"nope\": must be one of force_pulsation");
  expect_rejected({"simulate", "ermolaev2020", "--sweep", "t2_s", "--out", path("bad.csv")},
                  "expected KEY=FROM:STEP:TO");
}

TEST_F(Cli, DriveUnderTheS1PresetLoad) {
  // `cutdyn drive` (default: ermolaev2020, static drives of β = −10000 N·m·s): the x axis
  // follows the feed (5 mm/s over 2 mm/rad: Ω0 = 2.5 rad/s) and carries the resistance of the
  // cut; the y axis stands still (no kδ, no δ). Checked against the closed forms of the static
  // characteristic from the reported torques.
  const Result r = cutdyn({"drive", "--json", path("d.json"), "--out", path("d.csv")});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(std::ifstream(path("d.json")));
  ASSERT_EQ(doc["axes"].size(), 2u);
  const auto& x = doc["axes"][0];
  EXPECT_EQ(x["axis"], "x");
  EXPECT_NEAR(x["commanded_speed_rad_s"].get<double>(), 2.5, 1e-12);
  const double beta = 1e4, mean = x["mean_load_torque_nm"], ripple = x["torque_ripple_nm"];
  EXPECT_NEAR(x["speed_ripple_rad_s"].get<double>(), ripple / beta, 1e-12);
  EXPECT_NEAR(x["static_error"].get<double>(), mean / (2.5 * beta), 1e-12);
  // kδ = 2(Ωmax − Ωmin)/(Ωmax + Ωmin) (eq. 1) = 2·ΔΩ/Ω̄mid, Ω̄mid = Ω0 − (mid-range torque)/β.
  EXPECT_NEAR(x["k_delta"].get<double>(), 2 * (ripple / beta) / 2.5, 1e-9);
  EXPECT_EQ(x["k_delta_verdict"], "acceptable");
  // The summary is of the detected periodic steady state: the static drive follows the force,
  // periodic at the revolution once the cut has settled.
  EXPECT_TRUE(x["steady_state"].get<bool>());
  EXPECT_TRUE(x["warnings"].empty());
  EXPECT_GE(x["steady_revolutions"].get<int>(), 2);
  EXPECT_NEAR(x["mean_speed_rad_s"].get<double>(), 2.5 - mean / beta, 1e-12);
  const auto& y = doc["axes"][1];
  EXPECT_TRUE(y["k_delta"].is_null());
  EXPECT_NEAR(y["commanded_speed_rad_s"].get<double>(), 0.0, 1e-15);
  // ε is the drive's position error plus the cutter's deflection: here the cutter dominates.
  EXPECT_LE(x["epsilon_um"].get<double>(),
            x["drive_error_um"].get<double>() + x["cutter_error_um"].get<double>() + 1e-12);
  EXPECT_GT(x["cutter_error_um"].get<double>(), 100 * x["drive_error_um"].get<double>());
  const auto lines = csv_lines(path("d.csv"));
  EXPECT_EQ(lines[0],
            "axis,time_s,axis_force_n,load_torque_nm,speed_rad_s,position_error_um,epsilon_um");
}

TEST_F(Cli, DriveCurrentsAndSweepAndBadDrives) {
  std::string text(*io::example_text("ermolaev2020"));
  // Both axes have a motor (x: KT = 1.621 N·m/A in the space-vector measure, the default); the
  // currents CSV has the monitor's input columns and its equivalent current is |Te|/KT (the
  // static drive's motor torque is the load torque).
  const auto file = write("drive.toml", text);
  const Result r = cutdyn({"drive", file, "--currents", path("i.csv"), "--out", path("d.csv")});
  ASSERT_EQ(r.code, 0) << r.err;
  auto currents = csv_lines(path("i.csv"));
  ASSERT_GT(currents.size(), 100u);
  // Before the header, one line per axis with the motor the currents were made with.
  EXPECT_EQ(currents[0],
            "# axis = x, measure = space-vector, torque_constant_nm_per_a = 1.621, pole_pairs = 4");
  EXPECT_EQ(currents[1],
            "# axis = y, measure = space-vector, torque_constant_nm_per_a = 1.627, pole_pairs = 4");
  currents.erase(currents.begin(), currents.begin() + 2);
  EXPECT_EQ(currents[0], "time_s,axis,iu_a,iv_a,iw_a,speed_rad_s,rotor_angle_rad");
  const auto traces = csv_lines(path("d.csv"));
  // Row 1 of both: axis x at the first instant.
  const auto fields = [](const std::string& line) {
    std::vector<std::string> out;
    std::stringstream ss(line);
    for (std::string f; std::getline(ss, f, ',');) out.push_back(f);
    return out;
  };
  const auto i1 = fields(currents[1]), d1 = fields(traces[1]);
  const double id = equivalent_current(std::stod(i1[2]), std::stod(i1[3]), std::stod(i1[4]),
                                       CurrentMeasure::kSpaceVector);
  EXPECT_NEAR(id, std::abs(std::stod(d1[3])) / 1.621, 1e-9);
  // The rotor's electrical angle θe: iu = −Î·sin θe, Î = Te/KT (space vector, no noise).
  EXPECT_NEAR(std::stod(i1[2]), -std::stod(d1[3]) / 1.621 * std::sin(std::stod(i1[6])), 1e-9);
  // Ten rows later the angle has advanced by p·∫Ω dt (4 pole pairs, trapezoidal).
  const auto i11 = fields(currents[11]);
  double turned = 0.0;
  for (int k = 1; k <= 10; ++k) {
    const auto a = fields(currents[static_cast<std::size_t>(k)]),
               b = fields(currents[static_cast<std::size_t>(k + 1)]);
    turned += 4 * 0.5 * (std::stod(a[5]) + std::stod(b[5])) * (std::stod(b[0]) - std::stod(a[0]));
  }
  EXPECT_NEAR(std::fmod(std::stod(i1[6]) + turned, 2 * units::kPi), std::stod(i11[6]), 1e-6);
  // The monitor reads the recorded measure: against the zheng2012 calibration (the source's RMS
  // measure) the space-vector log is refused, naming the line and both measures; an RMS motor in
  // the case records rms and passes that check.
  const Result mismatch = cutdyn(
      {"monitor", "estimate", "--calib", "zheng2012", path("i.csv"), "--out", path("e.csv")});
  EXPECT_EQ(mismatch.code, 2) << mismatch.err;
  EXPECT_NE(mismatch.err.find("line 1: axis x: the currents were logged with measure = "
                              "space-vector, the calibration's measure is rms"),
            std::string::npos)
      << mismatch.err;
  std::string rms = text;
  rms.insert(rms.find("pole_pairs = 4"), "current_measure = \"rms\"\n");
  ASSERT_EQ(cutdyn({"drive", write("rms.toml", rms), "--currents", path("r.csv")}).code, 0);
  EXPECT_EQ(csv_lines(path("r.csv"))[0],
            "# axis = x, measure = rms, torque_constant_nm_per_a = 1.621, pole_pairs = 4");
  // A sweep of the spindle speed tabulates ε per axis.
  const Result sweep =
      cutdyn({"drive", file, "--sweep", "simulate.rpm=60:60:180", "--json", path("s.json")});
  ASSERT_EQ(sweep.code, 0) << sweep.err;
  const auto doc = nlohmann::json::parse(std::ifstream(path("s.json")));
  ASSERT_EQ(doc["points"].size(), 3u);
  EXPECT_EQ(doc["points"][2]["axes"][1]["axis"], "y");
  EXPECT_GT(doc["points"][0]["axes"][0]["epsilon_um"].get<double>(), 0.0);
  // Bad drives: no [[drives]]; a lever without its diameter; currents without a motor.
  expect_rejected({"drive", "milling-insperger", "--out", path("x.csv")}, "drives: missing");
  std::string lever = text;
  lever.replace(lever.find("output_diameter_mm = 40"), 23, "");
  expect_rejected({"drive", write("lever.toml", lever), "--out", path("x.csv")},
                  "drives[0].output_diameter_mm: missing");
  std::string no_motor = text;
  no_motor.replace(no_motor.find("torque_constant_nm_per_a = 1.627"), 32, "");
  no_motor.replace(no_motor.rfind("pole_pairs = 4"), 14, "");
  expect_rejected({"drive", write("nomotor.toml", no_motor), "--currents", path("x.csv")},
                  "drives (axis y): the motor phase currents need the motor");
}

TEST_F(Cli, DriveSummariesAreOfTheSteadyStateAndSayWhenItIsNotReached) {
  // The x axis as a dynamic P-only loop (the case that once reported a static error of 0: the mean
  // speed far below the commanded one). Steady state of J·dΩ/dt = Kp·(Ω0 − Ω) − Mc − b·Ω:
  // Ω̄ = (Kp·Ω0 − Mc̄)/(Kp + b), so δ = (Ω0 − Ω̄)/Ω0 from the reported mean load torque
  // (Ω0 = 2.5 rad/s).
  std::string text(*io::example_text("ermolaev2020"));
  const std::string stat = "model = \"static\"\nstiffness_nm_s_per_rad = -10000  # beta\n";
  ASSERT_NE(text.find(stat), std::string::npos);
  text.replace(text.find(stat), stat.size(),
               "model = \"dynamic\"\ninertia_kg_m2 = 2e-4\nkp_nm_s_per_rad = 0.2\n"
               "ki_nm_per_rad = 0\nviscous_nm_s_per_rad = 0.01\n");
  const Result r = cutdyn({"drive", write("ponly.toml", text), "--json", path("p.json")});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(std::ifstream(path("p.json")));
  const auto& x = doc["axes"][0];
  const double mc = x["mean_load_torque_nm"], mean = (0.2 * 2.5 - mc) / 0.21;
  EXPECT_TRUE(x["steady_state"].get<bool>()) << x.dump();
  EXPECT_NEAR(x["mean_speed_rad_s"].get<double>(), mean, 1e-3 * mean);
  EXPECT_NEAR(x["static_error"].get<double>(), 1.0 - mean / 2.5, 1e-3);
  EXPECT_GT(x["static_error"].get<double>(), 0.1);
  EXPECT_FALSE(x["static_error_ok"].get<bool>());
  EXPECT_NE(r.out.find("ABOVE 10 %"), std::string::npos) << r.out;
  // Two revolutions cannot show a steady state: a warning on stderr, in the text and the JSON.
  text.replace(text.find("revolutions = 6"), 15, "revolutions = 2");
  const Result two = cutdyn({"drive", write("two.toml", text), "--json", path("t.json")});
  ASSERT_EQ(two.code, 0) << two.err;
  const auto t = nlohmann::json::parse(std::ifstream(path("t.json")));
  EXPECT_FALSE(t["axes"][0]["steady_state"].get<bool>());
  ASSERT_FALSE(t["axes"][0]["warnings"].empty());
  EXPECT_NE(two.err.find("cutdyn: warning: " + path("two.toml") +
                         ": axis x: no periodic steady "
                         "state within the run"),
            std::string::npos)
      << two.err;
  EXPECT_NE(two.out.find("warning: no periodic steady state"), std::string::npos) << two.out;
}

TEST_F(Cli, DriveCurrentNoiseSeed) {
  // Noise on both axes: --seed reproduces a run and another seed changes it; the case's
  // [[drives]] seed is the same as --seed; the two axes' noise differs.
  std::string text(*io::example_text("ermolaev2020"));
  const std::string noise = "current_noise_a = 0.05\n";
  for (std::size_t at = text.find("pole_pairs = 4"); at != std::string::npos;
       at = text.find("pole_pairs = 4", at + noise.size() + 1))
    text.insert(at, noise);
  const auto file = write("noisy.toml", text);
  const auto run = [&](std::vector<std::string> extra, const std::string& out) {
    std::vector<std::string> args{"drive", file, "--currents", path(out)};
    args.insert(args.end(), extra.begin(), extra.end());
    const Result r = cutdyn(args);
    EXPECT_EQ(r.code, 0) << r.err;
    return csv_lines(path(out));
  };
  const auto a = run({"--seed", "5"}, "a.csv"), b = run({"--seed", "5"}, "b.csv"),
             c = run({"--seed", "6"}, "c.csv");
  ASSERT_GT(a.size(), 100u);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  std::string seeded = text;
  seeded.insert(seeded.find("pole_pairs = 4"), "seed = 5\n");
  seeded.insert(seeded.rfind("pole_pairs = 4"), "seed = 5\n");
  const auto d = [&] {
    const Result r = cutdyn({"drive", write("seeded.toml", seeded), "--currents", path("d.csv")});
    EXPECT_EQ(r.code, 0) << r.err;
    return csv_lines(path("d.csv"));
  }();
  EXPECT_EQ(d, a);
  // Within a run, the noise of x and y is uncorrelated: the difference of the runs with seeds 5
  // and 6 is pure noise (variance 2σ²) on each axis.
  std::vector<double> dx, dy;
  ASSERT_EQ(a[2].rfind("time_s,", 0), 0u);  // two comment lines, then the header
  for (std::size_t i = 3; i < a.size(); ++i) {
    std::stringstream sa(a[i]), sc(c[i]);
    std::string fa, fc, axis;
    std::vector<std::string> va, vc;
    while (std::getline(sa, fa, ',')) va.push_back(fa);
    while (std::getline(sc, fc, ',')) vc.push_back(fc);
    (va[1] == "x" ? dx : dy).push_back(std::stod(va[2]) - std::stod(vc[2]));
  }
  ASSERT_EQ(dx.size(), dy.size());
  double sxy = 0, sxx = 0, syy = 0;
  for (std::size_t i = 0; i < dx.size(); ++i) {
    sxy += dx[i] * dy[i];
    sxx += dx[i] * dx[i];
    syy += dy[i] * dy[i];
  }
  const double rho = sxy / std::sqrt(sxx * syy);
  EXPECT_LT(std::abs(rho), 4.0 / std::sqrt(static_cast<double>(dx.size()))) << rho;
  EXPECT_NEAR(std::sqrt(sxx / static_cast<double>(dx.size())), 0.05 * std::sqrt(2.0), 0.01);
  expect_rejected({"drive", file, "--seed", "-1", "--currents", path("x.csv")}, "--seed");
}

TEST_F(Cli, PlanReportsTheBoreMillingQuantities) {
  // The example bore-plan without [limits] (no optimisation) against the library; the JSON has
  // the keys of docs/models/bore-milling.md.
  std::string plain(*io::example_text("bore-plan"));
  plain.erase(plain.find("[limits]"));
  const Result r = cutdyn({"plan", write("plain.toml", plain), "--json", path("p.json")});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(std::ifstream(path("p.json")));
  const io::Case c = io::parse_case(plain, "plain");
  const BoreMillingResult lib = bore_milling(*c.bore);
  EXPECT_DOUBLE_EQ(doc["max_axial_feed_mm"].get<double>(), 1e3 * lib.max_axial_feed_m);
  EXPECT_DOUBLE_EQ(doc["max_axial_feed_closed_form_mm"].get<double>(),
                   1e3 * lib.max_axial_feed_closed_form_m);
  EXPECT_DOUBLE_EQ(doc["q_mm"].get<double>(), 1e3 * lib.q_m);
  EXPECT_DOUBLE_EQ(doc["main_time_min"].get<double>(), lib.main_time_s / 60.0);
  EXPECT_NEAR(doc["straightness_error_mm"].get<double>(), 0.05 * 5.0, 1e-9);  // Δ1 = k·t
  EXPECT_DOUBLE_EQ(doc["cutter_rpm"].get<double>(), 60.0 * lib.cutter_rev_per_s);
  EXPECT_DOUBLE_EQ(doc["workpiece_rpm"].get<double>(), 60.0 * lib.workpiece_rev_per_s);
  for (const char* key : {"faceting_mm", "milling_width_mm"})
    EXPECT_TRUE(doc[key].is_number()) << key;
  // A given feed; feeds at or above q leave uncut ridges; an impossible offset; not a plan.
  EXPECT_FALSE(doc["optimised"].get<bool>());
  // The example itself has [limits]: the plan is optimised, within every limit, and no slower
  // than the example's own h = h* with the same limits.
  const Result opt = cutdyn({"plan", "--json", path("o.json"), "--plot", path("o.png")});
  ASSERT_EQ(opt.code, 0) << opt.err;
  const auto o = nlohmann::json::parse(std::ifstream(path("o.json")));
  EXPECT_TRUE(o["optimised"].get<bool>());
  EXPECT_FALSE(o["binding_constraints"].empty());
  EXPECT_LE(o["straightness_error_mm"].get<double>(), 0.25 * (1 + 1e-9));
  EXPECT_LE(o["faceting_mm"].get<double>(), 0.01 * (1 + 1e-9));
  EXPECT_LE(o["max_chip_thickness_mm"].get<double>(), 1.5 * (1 + 1e-9));
  EXPECT_LE(o["workpiece_rpm"].get<double>(), 5.0 * (1 + 1e-9));
  EXPECT_LE(o["cutting_speed_m_per_min"].get<double>(), 150.0 * (1 + 1e-9));
  const io::Case with_limits = io::load_example("bore-plan");
  EXPECT_LE(o["main_time_min"].get<double>() * 60.0,
            bore_milling_main_time(*with_limits.bore, *with_limits.bore_limits,
                                   with_limits.bore->offset_m, max_axial_feed(*with_limits.bore)) *
                (1 + 1e-9));
  EXPECT_TRUE(fs::exists(path("o.png")));
  const Result given = cutdyn({"plan", "--axial-feed-mm", "10", "--json", path("g.json")});
  ASSERT_EQ(given.code, 0) << given.err;
  EXPECT_DOUBLE_EQ(
      nlohmann::json::parse(std::ifstream(path("g.json")))["axial_feed_mm"].get<double>(), 10.0);
  expect_rejected({"plan", "--axial-feed-mm", "250", "--json", path("x.json")},
                  "uncut ridges (S0 < q)");
  std::string text = plain;
  text.replace(text.find("offset_mm = 3.109375"), 20, "offset_mm = -160");
  expect_rejected({"plan", write("bad.toml", text), "--json", path("x.json")},
                  "the cutter does not fit: D/2 + |h| must be less than d/2");
  expect_rejected({"plan", "milling-insperger", "--json", path("x.json")},
                  "`cutdyn plan` takes a bore-milling case");
}

TEST_F(Cli, MillingSimulationRejectsIncompleteCases) {
  std::string text(*io::example_text("milling-insperger"));
  const auto without = [&](const std::string& line) {
    std::string t = text;
    return t.replace(t.find(line), line.size(), "");
  };
  expect_rejected({"simulate", write("nofeed.toml", without("feed_per_tooth_mm = 0.05")), "--out",
                   path("x.csv")},
                  "operation.feed_per_tooth_mm: missing");
  std::string window = text;
  window.replace(window.find("direction = \"down\""), 18, "entry_deg = 30");
  expect_rejected({"simulate", write("window.toml", window), "--out", path("x.csv")},
                  "operation.entry_deg = 30: give entry_deg and exit_deg together");
  expect_rejected({"simulate", "milling-insperger", "--rpm", "-5", "--out", path("x.csv")},
                  "command line: --rpm = -5: must be positive");
  expect_rejected({"simulate", "milling-insperger", "--depth-mm", "0", "--out", path("x.csv")},
                  "--depth-mm = 0 mm: must be greater than 0 and at most 10000 mm");
  std::string law = text + "\n[force_law]\nt2_s = -1\n";
  expect_rejected({"simulate", write("law.toml", law), "--out", path("x.csv")},
                  "force_law.c_n_per_mm: missing");
  expect_rejected({"simulate", write("law2.toml", law), "--out", path("x.csv")},
                  "force_law.t2_s = -1: must be at least 0");
}

TEST_F(Cli, MillingLowImmersionReportsFlipLobes) {
  std::string text(*io::example_text("milling-insperger"));
  text.replace(text.find("radial_immersion = 1.0"), 22, "radial_immersion = 0.05");
  text.replace(text.find("rpm_steps = 200"), 15, "rpm_steps = 41");
  text.replace(text.find("depth_max_mm = 1"), 16, "depth_max_mm = 10");
  const auto file = write("low.toml", text);
  const Result r = cutdyn({"lobes", file, "--json", path("low.json")});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(std::ifstream(path("low.json")));
  int flips = 0, hopfs = 0;
  for (const auto& p : doc["points"]) {
    flips += p["bifurcation"] == "flip";
    hopfs += p["bifurcation"] == "hopf";
  }
  EXPECT_GT(flips, 3);
  EXPECT_GT(hopfs, 3);
}

TEST_F(Cli, MillingRejectsPitchAnglesThatAreNotOneRevolution) {
  const std::string text(*io::example_text("milling-insperger"));
  const auto with_tool = [&](const std::string& line) {
    std::string t = text;
    return t.replace(t.find("[tool]"), 6, "[tool]\n" + line);
  };
  expect_rejected(
      {"lobes", write("sum.toml", with_tool("pitch_deg = [170, 170]")), "--out", path("p.csv")},
      "tool.pitch_deg = [170, 170]: the angles must add up to 360, they add up to 340");
  expect_rejected({"lobes", write("count.toml", with_tool("pitch_deg = [120, 120, 120]")), "--out",
                   path("p.csv")},
                  "must give one angle per tooth (teeth = 2), got 3");
  expect_rejected(
      {"lobes", write("neg.toml", with_tool("pitch_deg = [-10, 370]")), "--out", path("p.csv")},
      "tool.pitch_deg[0] = -10: must be greater than 0");
  expect_rejected(
      {"lobes", write("type.toml", with_tool("pitch_deg = 360")), "--out", path("p.csv")},
      "tool.pitch_deg = 360: wrong type: expected a non-empty array of numbers, got");
  expect_rejected(
      {"lobes", write("nan.toml", with_tool("pitch_deg = [nan, 180]")), "--out", path("p.csv")},
      "tool.pitch_deg[0] = nan: must be a finite number");
}

TEST_F(Cli, TargetDepthListsTheStableSpeedRanges) {
  std::string text(*io::example_text("milling-insperger"));
  text.replace(text.find("rpm_steps = 200"), 15, "rpm_steps = 41");
  const auto file = write("mill.toml", text);
  const Result r = cutdyn({"lobes", file, "--target-depth-mm", "0.2", "--json", path("t.json")});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("recommended:"), std::string::npos);
  const auto doc = nlohmann::json::parse(std::ifstream(path("t.json")));
  ASSERT_FALSE(doc["stable_ranges"].empty());
  // Every speed inside a range is stable at 0.2 mm, every one outside is not, and the
  // recommended speed keeps the margin it reports: every speed within ±ε of it is stable at
  // 0.2·(1 + ε) mm; the deepest speed, which was recommended before, keeps less (even read off
  // the points alone).
  double deepest = 0.0, deepest_rpm = 0.0;
  for (const auto& p : doc["points"]) {
    const double rpm = p["spindle_rpm"], depth = p["critical_depth_mm"];
    bool inside = false;
    for (const auto& range : doc["stable_ranges"])
      inside = inside ||
               (rpm >= range["rpm_from"].get<double>() && rpm <= range["rpm_to"].get<double>());
    EXPECT_EQ(inside, depth > 0.2) << "rpm " << rpm;
    if (depth > deepest) {
      deepest = depth;
      deepest_rpm = rpm;
    }
  }
  const double n = doc["recommended_rpm"], eps = doc["recommended_margin"];
  EXPECT_GT(eps, 0.0);
  const auto margin_at = [&](double at) {  // the definition, by brute force
    double e = 1.0;
    for (const auto& p : doc["points"]) {
      const double delta = std::abs(p["spindle_rpm"].get<double>() - at) / at;
      const double head = p["critical_depth_mm"].get<double>() / 0.2 - 1.0;
      e = std::min(e, std::max(delta, head));
    }
    const auto& pts = doc["points"];
    const double lo = pts.front()["spindle_rpm"], hi = pts.back()["spindle_rpm"];
    return std::min({e, (at - lo) / at, (hi - at) / at});
  };
  // The margin is found between the traced speeds too (docs "Advice"): at most what the points
  // alone give, and every traced speed within ±ε keeps 0.2·(1 + ε) mm.
  EXPECT_LE(eps, margin_at(n) + 1e-4);
  for (const auto& p : doc["points"])
    if (std::abs(p["spindle_rpm"].get<double>() - n) <= eps * n) {
      EXPECT_GE(p["critical_depth_mm"].get<double>(), 0.2 * (1.0 + eps) * (1.0 - 1e-9));
    }
  EXPECT_LE(margin_at(deepest_rpm), eps);
  expect_rejected({"lobes", file, "--target-depth-mm", "0", "--out", path("x.csv")},
                  "--target-depth-mm = 0");
}

// ---- No silent wrong answers: keys a process does not use; the bore planner's accuracy ----

// kc_n_per_mm2 in a milling case ran with Kr = 0: now exit 2 naming the file, key, value and
// the keys milling takes, and no output file.
TEST_F(Cli, KeyTheProcessDoesNotUseIsRejected) {
  std::string text(*io::example_text("milling-insperger"));
  text.replace(text.find("kr_n_per_mm2 = 200"), 18, "kc_n_per_mm2 = 200");
  const std::string file = write("kc.toml", text);
  for (const char* command : {"lobes", "simulate"}) {
    SCOPED_TRACE(command);
    expect_rejected({command, file, "--out", path("x.csv")},
                    "cutdyn: error: " + file +
                        ": cutting.kc_n_per_mm2 = 200: not used in a milling case (milling takes "
                        "kt_n_per_mm2, kr_n_per_mm2, kte_n_per_mm, kre_n_per_mm)");
  }
}

// `cutdyn plan --axial-feed-mm` beyond the accuracy: computed (exit 0), with a warning in the
// text, on stderr and in the JSON naming Δ1, k·t and the largest feed that keeps Δ1 <= k·t; k
// outside 0.005 … 0.1 is refused.
TEST_F(Cli, PlanWarnsWhenTheFeedBreaksTheAccuracy) {
  std::string plain(*io::example_text("bore-plan"));
  plain.erase(plain.find("[limits]"));
  const std::string file = write("plain.toml", plain);
  const BoreMillingCase b = *io::parse_case(plain, "plain").bore;
  const double s_max_mm = 1e3 * max_axial_feed(b);
  const int s0_mm = static_cast<int>(1.2 * s_max_mm + 0.5);  // above the largest, below q
  const Result r =
      cutdyn({"plan", file, "--axial-feed-mm", std::to_string(s0_mm), "--json", path("w.json")});
  ASSERT_EQ(r.code, 0) << r.err;
  char s_max_text[32];
  std::snprintf(s_max_text, sizeof s_max_text, "%.4g", s_max_mm);
  const std::string largest =
      std::string("the largest axial feed with Δ1 <= k·t is ") + s_max_text + " mm";
  EXPECT_NE(r.out.find("  warning: the straightness error Δ1 = "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(largest), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("cutdyn: warning: command line: "), std::string::npos) << r.err;
  const auto doc = nlohmann::json::parse(std::ifstream(path("w.json")));
  EXPECT_FALSE(doc["accuracy_met"].get<bool>());
  ASSERT_EQ(doc["warnings"].size(), 1u);
  EXPECT_NE(doc["warnings"][0].get<std::string>().find("k·t = 0.25 mm"), std::string::npos);
  EXPECT_GT(doc["straightness_error_mm"].get<double>(), 0.25);
  // At the largest feed: no warning.
  const Result ok = cutdyn({"plan", file, "--json", path("ok.json")});
  ASSERT_EQ(ok.code, 0) << ok.err;
  EXPECT_EQ(ok.out.find("warning"), std::string::npos) << ok.out;
  EXPECT_TRUE(nlohmann::json::parse(std::ifstream(path("ok.json")))["accuracy_met"].get<bool>());
  // k outside the source's range.
  std::string k = plain;
  k.replace(k.find("accuracy_coefficient = 0.05"), 27, "accuracy_coefficient = 0.3");
  expect_rejected({"plan", write("k.toml", k), "--json", path("k.json")},
                  "process.accuracy_coefficient = 0.3: must be from 0.005 (finishing) to 0.1 "
                  "(roughing)");
  // An error prints millimetres (4 significant digits), not metres.
  expect_rejected({"plan", file, "--axial-feed-mm", "250", "--json", path("x.json")},
                  "axial feed S0 = 250 mm: must be less than q = 69.43 mm");
}

// A fixed axial feed with [limits]: the optimiser does not run, and the plan says so.
TEST_F(Cli, PlanSaysWhenItsLimitsAreNotUsed) {
  const Result r = cutdyn({"plan", "--axial-feed-mm", "10", "--json", path("g.json")});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("warning: [limits] not used to optimise: the axial feed is given "
                       "(--axial-feed-mm)"),
            std::string::npos)
      << r.out;
  const auto doc = nlohmann::json::parse(std::ifstream(path("g.json")));
  EXPECT_FALSE(doc["optimised"].get<bool>());
  EXPECT_TRUE(doc["accuracy_met"].get<bool>());  // 10 mm is below the largest feed
  ASSERT_EQ(doc["warnings"].size(), 1u);
}

// Runaway growth is chatter, said so, with only finite numbers written: milling-insperger at
// 1 mm (4.9e47 µm and "stable" before) and 1000 mm (exit 1, "CsvWriter: … non-finite"
// before), turning at 10 000 mm, the deepest a request may ask (1e6 mm gave −1e306 µm before).
// Exit 0 each time.
TEST_F(Cli, SimulateStopsARunawayAndSaysChatter) {
  const auto finite_numbers = [](const std::string& file) {
    std::ifstream in(file);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::string lower = text;
    for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    return !text.empty() && lower.find("nan") == std::string::npos &&
           lower.find("inf") == std::string::npos;
  };
  for (const char* depth : {"1", "1000"}) {
    const Result r = cutdyn({"simulate", "milling-insperger", "--depth-mm", depth, "--out",
                             path("r.csv"), "--json", path("r.json")});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("→ CHATTER (runaway growth, stopped at t = "), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("stable"), std::string::npos) << r.out;
    EXPECT_TRUE(finite_numbers(path("r.csv"))) << depth;
    EXPECT_TRUE(finite_numbers(path("r.json"))) << depth;
    const auto summary = nlohmann::json::parse(std::ifstream(path("r.json")))["summary"];
    EXPECT_EQ(summary["status"], "runaway");
    EXPECT_TRUE(summary["chatter"].get<bool>());
    EXPECT_LT(summary["stop_time_s"].get<double>(), 100 * 60.0 / 10000.0);  // of 100 revs
    // The prediction stays the lobes' 0.0715 mm whatever the simulated depth.
    EXPECT_NEAR(summary["predicted_critical_depth_mm"].get<double>(), 0.0715, 0.001) << depth;
  }
  const Result t = cutdyn({"simulate", "--depth-mm", "10000", "--duration-s", "1", "--out",
                           path("t.csv"), "--json", path("t.json")});
  ASSERT_EQ(t.code, 0) << t.err;
  EXPECT_NE(t.out.find("CHATTER (runaway growth, stopped at t = "), std::string::npos) << t.out;
  EXPECT_TRUE(finite_numbers(path("t.csv")));
  EXPECT_TRUE(finite_numbers(path("t.json")));
  // (The document is kept: a range over a member of a temporary would outlive it.)
  const nlohmann::json report = nlohmann::json::parse(std::ifstream(path("t.json")));
  for (const auto& run : report["results"]) {
    EXPECT_EQ(run["status"], "runaway");
    EXPECT_TRUE(run["chatter"].get<bool>());
  }
  // The initial displacement is the disturbance whose growth decides: zero is refused.
  std::string text(*io::example_text("turning-ultrasonic"));
  ASSERT_NE(text.find("[simulate]"), std::string::npos);
  text.replace(text.find("[simulate]"), 10, "[simulate]\ninitial_displacement_um = 0");
  const Result zero = cutdyn({"simulate", write("z.toml", text)});
  EXPECT_EQ(zero.code, 2) << zero.out;
  EXPECT_NE(zero.err.find("simulate.initial_displacement_um = 0: must be positive"),
            std::string::npos)
      << zero.err;
}

}  // namespace
}  // namespace cutdyn::cli
