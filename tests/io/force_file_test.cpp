// The force files of the identification (io/force_file.hpp), and the example mean-force file
// examples/forces/milling-insperger-mean-forces.csv (CUTDYN_UPDATE_EXAMPLES=1 rewrites it).
#include "cutdyn/io/force_file.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn::io {
namespace {

std::string joined(const std::vector<std::string>& lines) {
  std::string s;
  for (const std::string& l : lines) s += "\n  " + l;
  return s;
}

namespace fs = std::filesystem;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

std::vector<std::string> problems(const std::string& text, const std::string& source = "f.csv") {
  try {
    parse_force_file(text, source);
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where(), source);
    return e.problems();
  }
  ADD_FAILURE() << "accepted:\n" << text;
  return {};
}

TEST(ForceFile, ReadsMeanForcesByColumnName) {
  // Columns in another order, comments, blank lines, CRLF, blanks around fields.
  const std::string text =
      "# test cuts\r\n"
      "\r\n"
      "fy_n, feed_per_tooth_mm ,fx_n,depth_mm\r\n"
      "120.5,0.05,-40,2\r\n"
      "# a comment between rows\r\n"
      "+240, 0.1 , -80.25 ,1.5\r\n";
  EXPECT_EQ(force_file_kind(text, "m.csv"), ForceFileKind::kMeanForces);
  const std::vector<MeanForce> m = parse_mean_force_csv(text, "m.csv");
  ASSERT_EQ(m.size(), 2u);
  EXPECT_DOUBLE_EQ(m[0].feed_per_tooth_m, 0.05e-3);
  EXPECT_DOUBLE_EQ(m[0].depth_m, 2e-3);
  EXPECT_EQ(m[0].fx_n, -40.0);
  EXPECT_EQ(m[0].fy_n, 120.5);
  EXPECT_FALSE(m[0].fz_n.has_value());
  EXPECT_EQ(m[0].label, "m.csv:4");
  EXPECT_EQ(m[1].label, "m.csv:6");
  EXPECT_EQ(m[1].fx_n, -80.25);
  EXPECT_DOUBLE_EQ(m[1].depth_m, 1.5e-3);
  // The optional axial column.
  const std::vector<MeanForce> z =
      parse_force_file("feed_per_tooth_mm,depth_mm,fx_n,fy_n,fz_n\n0.1,2,1,2,3", "z.csv");
  ASSERT_EQ(z.size(), 1u);
  EXPECT_EQ(z[0].fz_n, 3.0);
}

TEST(ForceFile, MeanForceErrorsNameLineAndColumn) {
  const std::string header = "feed_per_tooth_mm,depth_mm,fx_n,fy_n\n";
  EXPECT_THAT(
      problems(header + "0.1,2,abc,4\n0.2,2,1\n0.3,-1,1,2\n0.1,2,,4\n0.1,2,nan,1\n"),
      ElementsAre("line 2, column fx_n: \"abc\" is not a number",
                  "line 3: 3 fields, the header (line 1) has 4",
                  "line 4, column depth_mm: -1 must be positive", "line 5, column fx_n: is empty",
                  "line 6, column fx_n: \"nan\" must be a finite number"));
  EXPECT_THAT(problems("feed_per_tooth_mm,depth_mm,fx_n,fy_n,fz_N\n0.1,2,1,2,3\n"),
              ElementsAre(HasSubstr("line 1, column 5: unknown column \"fz_N\" (the columns are "
                                    "feed_per_tooth_mm,depth_mm,fx_n,fy_n,fz_n (optional))")));
  EXPECT_THAT(problems("# x\nfeed_per_tooth_mm,fx_n,fy_n,fx_n\n0.1,2,1,2\n"),
              ElementsAre("line 2, column 4: column fx_n appears twice",
                          HasSubstr("line 2: missing column depth_mm")));
  EXPECT_THAT(problems("# only comments\n\n"), ElementsAre(HasSubstr("no header line")));
  EXPECT_THAT(problems(""), ElementsAre(HasSubstr("no header line")));
  EXPECT_THAT(problems(header), ElementsAre("line 1: no data after the header"));
  EXPECT_THAT(problems("a,b\n1,2\n"), ElementsAre(HasSubstr("line 1: the header \"a,b\" names "
                                                            "neither")));
  // Many bad lines: the first 20 and a count.
  std::string many = header;
  for (int i = 0; i < 25; ++i) many += "x,2,1,1\n";
  const std::vector<std::string> p = problems(many);
  ASSERT_EQ(p.size(), 21u);
  EXPECT_EQ(p.back(), "… and 5 more problem(s)");
}

const char* kRecord =
    "# rig test 3\n"
    "# feed_per_tooth_mm = 0.05, depth_mm = 2\n"
    "# rpm = 3000\n"
    "time_s,fx_n,fy_n\n"
    "0,1,10\n"
    "0.005,3,10\n"
    "0.01,1,10\n"
    "0.015,3,10\n"
    "0.02,1,10\n"
    "0.025,5,12\n";

TEST(ForceFile, ReadsAForceRecordAndItsCut) {
  EXPECT_EQ(force_file_kind(kRecord, "r.csv"), ForceFileKind::kTimeSeries);
  const ForceSeries s = parse_force_series_csv(kRecord, "r.csv");
  EXPECT_DOUBLE_EQ(s.feed_per_tooth_m, 0.05e-3);
  EXPECT_DOUBLE_EQ(s.depth_m, 2e-3);
  EXPECT_EQ(s.rpm, 3000.0);
  EXPECT_EQ(s.time_s.size(), 6u);
  EXPECT_TRUE(s.fz_n.empty());
  EXPECT_EQ(s.label, "r.csv");
  // As a sample: one revolution (0.02 s), the last one, 0.005–0.025 s: trapezoids of x give
  // (2 + 2 + 2 + 3)·0.005 / 0.02 = 2.25 N, of y (10·3 + 11)·0.005 / 0.02 = 10.25 N.
  const std::vector<MeanForce> m = parse_force_file(kRecord, "r.csv");
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].revolutions, 1);
  EXPECT_NEAR(m[0].fx_n, 2.25, 1e-12);
  EXPECT_NEAR(m[0].fy_n, 10.25, 1e-12);
  EXPECT_EQ(m[0].label, "r.csv");
}

// The same record as `cutdyn monitor estimate` writes it: one row per axis and instant, the
// force resisting each axis (−F on the cutter), its other columns beside.
TEST(ForceFile, ReadsTheMonitorsEstimateAsTheSameRecord) {
  std::istringstream in(kRecord);
  std::string line, text;
  while (std::getline(in, line) && line.rfind('#', 0) == 0) text += line + "\n";
  text += "time_s,axis,force_n,force_sigma_n,speed_rad_s,accel_rad_s2\n";
  while (std::getline(in, line)) {
    double t = 0, fx = 0, fy = 0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf", &t, &fx, &fy), 3);
    char row[160];
    std::snprintf(row, sizeof row, "%.17g,x,%.17g,0.5,60,0\n%.17g,y,%.17g,,60,0\n", t, -fx, t, -fy);
    text += row;
  }
  EXPECT_EQ(force_file_kind(text, "m.csv"), ForceFileKind::kMonitorEstimate);
  const std::vector<MeanForce> a = parse_force_file(kRecord, "r.csv");
  const std::vector<MeanForce> b = parse_force_file(text, "m.csv");
  ASSERT_EQ(b.size(), 1u);
  EXPECT_EQ(b[0].fx_n, a[0].fx_n);
  EXPECT_EQ(b[0].fy_n, a[0].fy_n);
  EXPECT_EQ(b[0].feed_per_tooth_m, a[0].feed_per_tooth_m);
  // An instant without y, an unknown axis, an axis twice: named by line.
  const std::string head =
      "# feed_per_tooth_mm = 0.05, depth_mm = 2, rpm = 3000\ntime_s,axis,force_n\n";
  EXPECT_THAT(problems(head + "0,x,1\n0,y,2\n0.01,x,1\n0.02,x,1\n0.02,y,1\n"),
              ElementsAre(HasSubstr("line 5: at 0.01 s the file gives no axis y")));
  EXPECT_THAT(
      problems(head + "0,x,1\n0,w,2\n"),
      ElementsAre(HasSubstr("line 4: axis \"w\" is not x, y or z"), HasSubstr("no axis y")));
  EXPECT_THAT(problems(head + "0,x,1\n0,x,2\n0,y,1\n"),
              ElementsAre(HasSubstr("line 4: axis x twice at 0 s")));
}

TEST(ForceFile, ForceRecordErrorsNameLineAndKey) {
  EXPECT_THAT(problems("# feed_per_tooth_mm = 0.05\n# depth_mm=2\ntime_s,fx_n,fy_n\n0,1,1\n"),
              ElementsAre(HasSubstr("missing rpm: a force record states its cut in comment lines "
                                    "before the header (line 3)")));
  EXPECT_THAT(
      problems("# feed_per_tooth_mm = 0.05, depth_mm = x, rpm = -3\n# rpm = 2\ntime_s,fx_n,fy_n\n"
               "0,1,1\n0.01,1,1\n0.01,1,1\n"),
      ElementsAre("line 1, depth_mm: \"x\" is not a number", "line 1, rpm: -3 must be positive",
                  "line 2, rpm: given twice (first on line 1)",
                  "line 6, column time_s: 0.01 s does not increase over line 5 (0.01 s)"));
  // Short record: the library's check, where = the file.
  EXPECT_THAT(problems("# feed_per_tooth_mm = 0.05\n# depth_mm = 2\n# rpm = 3000\n"
                       "time_s,fx_n,fy_n\n0,1,1\n0.01,1,1\n",
                       "short.csv"),
              ElementsAre(HasSubstr("time_s spans 0.01 s, less than one revolution")));
}

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "cutdyn-force-file-test";
  fs::create_directories(dir);
  return dir / name;
}

TEST(ForceFile, ReadsSeveralFiles) {
  const fs::path a = scratch("a.csv"), b = scratch("b.csv");
  std::ofstream(a) << "feed_per_tooth_mm,depth_mm,fx_n,fy_n\n0.05,2,1,2\n0.1,2,3,4\n";
  std::ofstream(b) << kRecord;
  const std::vector<MeanForce> m = read_force_files({a, b});
  ASSERT_EQ(m.size(), 3u);
  EXPECT_EQ(m[0].label, a.string() + ":2");
  EXPECT_EQ(m[2].label, b.string());
  EXPECT_NEAR(m[2].fx_n, 2.25, 1e-12);
  try {
    read_force_files({a, scratch("missing.csv")});
    ADD_FAILURE() << "accepted";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where(), scratch("missing.csv").string());
    EXPECT_THAT(e.problems(), ElementsAre(HasSubstr("cannot read the file")));
  }
  fs::remove(a);
  fs::remove(b);
}

// ---- the example file ------------------------------------------------------------------

const fs::path kExample =
    fs::path(CUTDYN_EXAMPLES_DIR) / "forces" / "milling-insperger-mean-forces.csv";

// The example's recipe: the tool of examples/milling-insperger.toml (2 teeth, slotting, down),
// Kt 600, Kr 200 N/mm², Kte 20, Kre 25 N/mm, depth 2 mm, six feeds, normal noise of 1 % of
// the resultant mean force per component (Box–Muller on mt19937_64, seed 2024).
CuttingCoefficients example_coefficients() {
  CuttingCoefficients k;
  k.kt_pa = 600e6;
  k.kr_pa = 200e6;
  k.kte_n_per_m = 20e3;
  k.kre_n_per_m = 25e3;
  return k;
}
const IdentifyCut kExampleCut{2, 0.0, units::kPi};

std::string example_text() {
  std::mt19937_64 engine(2024);
  const auto uniform = [&] { return (static_cast<double>(engine() >> 11) + 0.5) * 0x1.0p-53; };
  const auto normal = [&] {
    const double u1 = uniform(), u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(units::kTwoPi * u2);
  };
  std::string text =
      "# Mean forces of six test cuts with the tool of examples/milling-insperger.toml: 2 "
      "straight\n"
      "# teeth, D 20 mm, slotting, down-milling. Synthetic: the closed-form mean forces of\n"
      "# Kt 600, Kr 200 N/mm², Kte 20, Kre 25 N/mm at 2 mm depth, plus normal noise of 1 % of the\n"
      "# resultant force (seed 2024; tests/io/force_file_test.cpp, CUTDYN_UPDATE_EXAMPLES=1).\n"
      "# Forces on the cutter, N; x is the feed direction.\n"
      "feed_per_tooth_mm,depth_mm,fx_n,fy_n\n";
  for (double feed_mm : {0.025, 0.05, 0.075, 0.1, 0.125, 0.15}) {
    const Eigen::Vector3d f =
        mean_milling_force(kExampleCut, example_coefficients(), units::mm_to_m(feed_mm), 2e-3);
    const double sigma = 0.01 * f.head<2>().norm();
    const double fx = f.x() + sigma * normal(), fy = f.y() + sigma * normal();
    char line[96];
    std::snprintf(line, sizeof line, "%.3f,2,%.3f,%.3f\n", feed_mm, fx, fy);
    text += line;
  }
  return text;
}

TEST(ForceFileExample, IsTheRecipesAndGivesBackItsCoefficients) {
  const std::string expected = example_text();
  if (std::getenv("CUTDYN_UPDATE_EXAMPLES") != nullptr) {
    std::ofstream(kExample, std::ios::binary) << expected;
    GTEST_SKIP() << "rewrote " << kExample;
  }
  std::ifstream in(kExample, std::ios::binary);
  ASSERT_TRUE(in) << kExample << " is missing (CUTDYN_UPDATE_EXAMPLES=1 writes it)";
  std::ostringstream content;
  content << in.rdbuf();
  // The numbers of the file are the recipe's (to their printed 3 decimals).
  const std::vector<MeanForce> file = parse_mean_force_csv(content.str(), "example");
  const std::vector<MeanForce> recipe = parse_mean_force_csv(expected, "recipe");
  ASSERT_EQ(file.size(), recipe.size());
  for (std::size_t i = 0; i < file.size(); ++i) {
    EXPECT_EQ(file[i].feed_per_tooth_m, recipe[i].feed_per_tooth_m);
    EXPECT_NEAR(file[i].fx_n, recipe[i].fx_n, 2e-3) << file[i].label;
    EXPECT_NEAR(file[i].fy_n, recipe[i].fy_n, 2e-3) << file[i].label;
  }
  // The fit: each coefficient's 95 % interval holds the recipe's value; no warnings.
  const CoefficientFit f = identify_coefficients(kExampleCut, file);
  const CuttingCoefficients k = example_coefficients();
  for (const auto& [c, truth] :
       {std::pair{f.kt, k.kt_pa}, std::pair{f.kr, k.kr_pa}, std::pair{f.kte, k.kte_n_per_m},
        std::pair{f.kre, k.kre_n_per_m}}) {
    EXPECT_LE(c.ci95_low, truth);
    EXPECT_GE(c.ci95_high, truth);
  }
  EXPECT_TRUE(f.warnings.empty()) << joined(f.warnings);
  if (std::getenv("CUTDYN_IDENTIFY_VERBOSE"))
    std::printf("Kt %.2f ± %.2f, Kr %.2f ± %.2f N/mm², Kte %.3f ± %.3f, Kre %.3f ± %.3f N/mm\n",
                f.kt.value / 1e6, f.kt.ci95_high / 1e6 - f.kt.value / 1e6, f.kr.value / 1e6,
                f.kr.ci95_high / 1e6 - f.kr.value / 1e6, f.kte.value / 1e3,
                (f.kte.ci95_high - f.kte.value) / 1e3, f.kre.value / 1e3,
                (f.kre.ci95_high - f.kre.value) / 1e3);
}

}  // namespace
}  // namespace cutdyn::io
