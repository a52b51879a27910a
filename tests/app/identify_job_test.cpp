// The identify job (app/identify.hpp): the cut from the case, the force files, the fit, the
// report in the case's units and the [cutting] table it writes back.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cutdyn/app/case_models.hpp"
#include "cutdyn/app/identify.hpp"
#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/io/case_file.hpp"
#include "cutdyn/io/force_file.hpp"
#include "cutdyn/io/output.hpp"
#include "cutdyn/simulate/milling_simulation.hpp"
#include "support/temp_dir.hpp"

namespace cutdyn::app {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const fs::path kExampleForces =
    fs::path(CUTDYN_SOURCE_DIR) / "examples" / "forces" / "milling-insperger-mean-forces.csv";

IdentifyRequest request_of(const std::vector<fs::path>& files) {
  IdentifyRequest r;
  r.force_files = files;
  return r;
}

// The problems of a refused job (and its where()).
std::vector<std::string> refusal(const io::Case& c, const IdentifyRequest& r,
                                 const std::string& where) {
  try {
    run_identify(c, r);
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where(), where);
    return e.problems();
  }
  ADD_FAILURE() << "accepted";
  return {};
}

std::string all(const std::vector<std::string>& lines) {
  std::string s;
  for (const std::string& l : lines) s += l + "\n";
  return s;
}

// A case file's text with its [cutting] table (up to the next table) replaced by `table`.
std::string with_cutting(std::string text, const std::string& table) {
  const auto at = text.find("\n[cutting]");
  EXPECT_NE(at, std::string::npos);
  const auto end = text.find("\n[", at + 1);
  text.replace(at + 1, end - at, table + "\n");
  return text;
}

const IdentifiedValue& value(const IdentifyJobReport& r, const std::string& name) {
  for (const IdentifiedValue& v : r.values)
    if (v.name == name) return v;
  throw std::logic_error("no " + name);
}

TEST(IdentifyJob, RecoversTheExampleCoefficientsWithinTheReportedIntervals) {
  // examples/forces/README.md: the file was made from Kt 600, Kr 200 N/mm², Kte 20, Kre 25
  // N/mm with 1 % noise, for the tool and slotting of milling-insperger.
  const io::Case c = load_case("", "milling-insperger");
  const IdentifyJobReport r = run_identify(c, request_of({kExampleForces}));
  EXPECT_EQ(r.cut.teeth, 2);
  EXPECT_EQ(r.cut.entry_rad, 0.0);
  EXPECT_NEAR(r.cut.exit_rad, units::kPi, 1e-15);
  ASSERT_EQ(r.values.size(), 4u);  // no fz: no axial pair
  const struct {
    const char* name;
    double truth, case_value;
  } expected[] = {{"Kt", 600, 600}, {"Kr", 200, 200}, {"Kte", 20, NAN}, {"Kre", 25, NAN}};
  for (const auto& e : expected) {
    const IdentifiedValue& v = value(r, e.name);
    EXPECT_TRUE(v.value.uncertainty_known) << e.name;
    EXPECT_LE(v.value.ci95_low, e.truth) << e.name;
    EXPECT_GE(v.value.ci95_high, e.truth) << e.name;
    EXPECT_TRUE(v.value.determined()) << e.name;
    EXPECT_EQ(v.case_value.has_value(), !std::isnan(e.case_value)) << e.name;
    if (v.case_value) {
      EXPECT_EQ(*v.case_value, e.case_value) << e.name;
    }
  }
  // The library's fit of the same samples, in N/mm² and N/mm.
  const CoefficientFit f = identify_coefficients(r.cut, io::read_force_files({kExampleForces}));
  EXPECT_NEAR(value(r, "Kt").value.value, f.kt.value / 1e6, 1e-12 * 600);
  EXPECT_NEAR(value(r, "Kr").value.ci95_high, f.kr.ci95_high / 1e6, 1e-12 * 200);
  EXPECT_NEAR(value(r, "Kte").value.std_error, f.kte.std_error / 1e3, 1e-12 * 20);
  EXPECT_NEAR(value(r, "Kre").value.ci95_low, f.kre.ci95_low / 1e3, 1e-12 * 25);
  EXPECT_EQ(value(r, "Kt").unit, "N/mm²");
  EXPECT_EQ(value(r, "Kre").unit, "N/mm");
  EXPECT_TRUE(r.warnings.empty()) << all(r.warnings);
  EXPECT_TRUE(r.notes.empty()) << all(r.notes);
  // The fitted forces by a second route: the closed-form mean force of the identified
  // coefficients; the residual is measured − fitted.
  ASSERT_EQ(r.samples.size(), 6u);
  for (const IdentifiedSample& s : r.samples) {
    const auto closed = mean_milling_force(r.cut, r.fit.coefficients(), s.measured.feed_per_tooth_m,
                                           s.measured.depth_m);
    EXPECT_NEAR(s.fitted_fx_n, closed.x(), 1e-9 * closed.norm()) << s.measured.label;
    EXPECT_NEAR(s.fitted_fy_n, closed.y(), 1e-9 * closed.norm()) << s.measured.label;
    EXPECT_NEAR(s.residual.fx_n, s.measured.fx_n - s.fitted_fx_n, 1e-12 * closed.norm());
    EXPECT_THAT(s.measured.label, HasSubstr("milling-insperger-mean-forces.csv:"));
  }
  EXPECT_THAT(r.samples.front().measured.label, HasSubstr(".csv:7"));  // the first data line
}

constexpr const char* kBareMilling =
    "process = \"milling\"\n"
    "[tool]\nteeth = 3\ndiameter_mm = 16\n"
    "[operation]\nradial_immersion = 0.5\ndirection = \"up\"\n";

TEST(IdentifyJob, NeedsToolAndOperationButNeitherModesNorCoefficients) {
  // No [[modes]], no [cutting]: the window is up-milling at a_e/D = 0.5, [0, π/2].
  const io::Case bare = io::parse_case(kBareMilling, "bare.toml");
  const IdentifyJobReport r = run_identify(bare, request_of({kExampleForces}));
  EXPECT_EQ(r.cut.teeth, 3);
  EXPECT_EQ(r.cut.entry_rad, 0.0);
  EXPECT_NEAR(r.cut.exit_rad, units::kPi / 2, 1e-12);
  EXPECT_FALSE(value(r, "Kt").case_value.has_value());

  const io::Case no_tool =
      io::parse_case("process = \"milling\"\n[operation]\nradial_immersion = 1\n", "no-tool.toml");
  EXPECT_THAT(all(refusal(no_tool, request_of({kExampleForces}), "no-tool.toml")),
              HasSubstr("tool: missing (required by `cutdyn identify`"));
  const io::Case neither = io::parse_case("process = \"milling\"\n", "neither.toml");
  const std::vector<std::string> both =
      refusal(neither, request_of({kExampleForces}), "neither.toml");
  ASSERT_EQ(both.size(), 2u) << all(both);
  EXPECT_THAT(both[1], HasSubstr("operation: missing (required by `cutdyn identify`"));
  const io::Case turning = load_case("", "turning-ultrasonic");
  EXPECT_THAT(all(refusal(turning, request_of({kExampleForces}), turning.source)),
              HasSubstr("process = \"turning\": `cutdyn identify` identifies the coefficients "
                        "of milling"));
  IdentifyRequest none;
  none.names.where = "command line";
  EXPECT_THAT(all(refusal(bare, none, "command line")), HasSubstr("no force files"));
  EXPECT_THAT(all(refusal(bare, request_of({"/nonexistent/f.csv"}), "/nonexistent/f.csv")),
              HasSubstr("cannot read the file"));
}

class IdentifyFiles : public testing::TempDirTest {
 protected:
  fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(dir_ / name, std::ios::binary) << text;
    return dir_ / name;
  }
  // A mean-force file of the closed-form forces of `k` (fz with the axial pair).
  fs::path mean_force_file(const IdentifyCut& cut, const CuttingCoefficients& k, bool axial) {
    std::string text = axial ? "feed_per_tooth_mm,depth_mm,fx_n,fy_n,fz_n\n"
                             : "feed_per_tooth_mm,depth_mm,fx_n,fy_n\n";
    for (double feed_mm : {0.03, 0.06, 0.09, 0.12}) {
      const auto f = mean_milling_force(cut, k, units::mm_to_m(feed_mm), 2e-3);
      text += io::format_number(feed_mm) + ",2," + io::format_number(f.x()) + "," +
              io::format_number(f.y());
      text += (axial ? "," + io::format_number(f.z()) : std::string()) + "\n";
    }
    return write("forces.csv", text);
  }
};

TEST_F(IdentifyFiles, SimulatedForceRecordsGiveBackTheSimulationsCoefficients) {
  // A 3-tooth cutter with uneven pitch and a 30° helix, down-milling at a_e/D = 0.5; force
  // records of the rigid simulation (chip from the feed alone) at five feeds, written as
  // force-record files (time_s,fx_n,fy_n with the cut in comments), identified back. The
  // simulation's mean force misses at most half an angle step of force at each window edge
  // (tests/forces/identify_test.cpp measured below 0.2 % at 2048 steps per tooth): 1 %.
  const io::Case c = io::parse_case(
      "process = \"milling\"\n"
      "[tool]\nteeth = 3\ndiameter_mm = 16\nhelix_deg = 30\npitch_deg = [110, 120, 130]\n"
      "[operation]\nradial_immersion = 0.5\ndirection = \"down\"\n"
      "[cutting]\nkt_n_per_mm2 = 700\nkr_n_per_mm2 = 210\nkte_n_per_mm = 25\n"
      "kre_n_per_mm = 30\n",
      "simulated.toml");
  MillingSimulationOptions o;
  o.steps_per_tooth = 2048;
  o.revolutions = 3;
  o.summary_revolutions = 2;
  o.max_recorded_samples = 1 << 20;
  std::vector<fs::path> files;
  std::vector<MeanForce> in_memory;
  for (double feed_mm : {0.04, 0.07, 0.1, 0.13, 0.16}) {
    MillingCut cut;
    cut.process = milling_process_as_given(c);
    cut.spindle_rad_s = units::rpm_to_rad_per_s(3000.0);
    cut.feed_per_tooth_m = units::mm_to_m(feed_mm);
    cut.width_m = 3e-3;
    cut.regenerative = false;
    const MillingSimulationResult s = simulate_milling(cut, o);
    std::string csv = "# simulated\n# feed_per_tooth_mm = " + io::format_number(feed_mm) +
                      ", depth_mm = 3\n# rpm = 3000\ntime_s,fx_n,fy_n\n";
    for (std::size_t i = 0; i < s.time_s.size(); ++i)
      csv += io::format_number(s.time_s[i]) + "," + io::format_number(s.fx_n[i]) + "," +
             io::format_number(s.fy_n[i]) + "\n";
    files.push_back(write("sim-" + io::format_number(feed_mm) + ".csv", csv));
    in_memory.push_back(mean_over_revolutions(
        {s.time_s, s.fx_n, s.fy_n, {}, 3000.0, cut.feed_per_tooth_m, 3e-3, "memory"}));
  }
  const IdentifyJobReport r = run_identify(c, request_of(files));
  ASSERT_EQ(r.samples.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) {  // the files hold the traces exactly
    EXPECT_EQ(r.samples[i].measured.fx_n, in_memory[i].fx_n);
    EXPECT_EQ(r.samples[i].measured.fy_n, in_memory[i].fy_n);
    EXPECT_EQ(r.samples[i].measured.revolutions, in_memory[i].revolutions);
    EXPECT_GE(r.samples[i].measured.revolutions, 2);
  }
  for (const auto& [name, truth] :
       {std::pair<const char*, double>{"Kt", 700}, {"Kr", 210}, {"Kte", 25}, {"Kre", 30}}) {
    const IdentifiedValue& v = value(r, name);
    EXPECT_NEAR(v.value.value, truth, 0.01 * truth) << name;
    EXPECT_EQ(v.case_value, truth) << name;
    if (std::getenv("CUTDYN_IDENTIFY_VERBOSE"))
      std::printf("%s: %.6g (error %.3g %%)\n", name, v.value.value,
                  100 * (v.value.value - truth) / truth);
  }
  ASSERT_EQ(r.notes.size(), 2u) << all(r.notes);
  EXPECT_THAT(r.notes[0], HasSubstr("tool.pitch_deg (uneven pitch) is not used"));
  EXPECT_THAT(r.notes[1], HasSubstr("tool.helix_deg = 30 is not used"));
}

TEST_F(IdentifyFiles, CuttingTableReadsBackIntoTheCase) {
  const io::Case c = load_case("", "milling-insperger");
  const IdentifyJobReport r = run_identify(c, request_of({kExampleForces}));
  const std::string table = cutting_table_toml(c, r);
  const io::Case back = io::parse_case(with_cutting(std::string(c.text), table), "identified.toml");
  EXPECT_NEAR(*back.cutting.kt_pa, r.fit.kt.value, 1e-12 * r.fit.kt.value);
  EXPECT_NEAR(*back.cutting.kr_pa, r.fit.kr.value, 1e-12 * r.fit.kr.value);
  EXPECT_NEAR(*back.cutting.kte_n_per_m, r.fit.kte.value, 1e-12 * r.fit.kte.value);
  EXPECT_NEAR(*back.cutting.kre_n_per_m, r.fit.kre.value, 1e-12 * r.fit.kre.value);
  EXPECT_EQ(back.modal.modes.size(), c.modal.modes.size());  // the rest of the case kept
  EXPECT_THAT(table, HasSubstr("kt_n_per_mm2 = "));
  EXPECT_THAT(table, HasSubstr("# 95 %: "));
}

TEST_F(IdentifyFiles, CuttingTableLeavesOutWhatTheCaseFileRefuses) {
  // Exact mean forces (fz too) of a negative Kre and an axial pair, slotting with 2 teeth.
  const IdentifyCut slot{2, 0.0, units::kPi};
  const CuttingCoefficients k{650e6, 220e6, 150e6, 22e3, -5e3, 8e3};
  const fs::path forces = mean_force_file(slot, k, true);
  const io::Case c = load_case("", "milling-insperger");
  const IdentifyJobReport r = run_identify(c, request_of({forces}));
  ASSERT_EQ(r.values.size(), 6u);
  EXPECT_NEAR(value(r, "Kre").value.value, -5.0, 1e-9);
  EXPECT_NEAR(value(r, "Ka").value.value, 150.0, 1e-9);
  EXPECT_FALSE(value(r, "Ka").case_key);
  EXPECT_THAT(all(r.warnings), HasSubstr("Kre"));
  const std::string table = cutting_table_toml(c, r);
  EXPECT_THAT(table, HasSubstr("# kre_n_per_mm = -"));
  EXPECT_THAT(table, HasSubstr("not set: the case file takes kre_n_per_mm ≥ 0 only"));
  EXPECT_THAT(table, HasSubstr("# ka_n_per_mm2 = "));
  EXPECT_THAT(table, HasSubstr("# kae_n_per_mm = "));
  const io::Case back = io::parse_case(with_cutting(std::string(c.text), table), "back.toml");
  EXPECT_NEAR(*back.cutting.kte_n_per_m, 22e3, 1e-6);
  EXPECT_FALSE(back.cutting.kre_n_per_m.has_value());

  // With a [force_law] the case file takes no edge coefficients: both are comments, and a
  // note says why.
  std::string s1_text(c.text);
  s1_text += "\n[force_law]\nc_n_per_mm = 1000\n";
  const io::Case s1 = io::parse_case(s1_text, "s1.toml");
  const IdentifyJobReport rs = run_identify(s1, request_of({kExampleForces}));
  const std::string s1_table = cutting_table_toml(s1, rs);
  EXPECT_THAT(s1_table, HasSubstr("# kte_n_per_mm = "));
  EXPECT_THAT(s1_table, HasSubstr("only without [force_law]"));
  EXPECT_THAT(all(rs.notes), HasSubstr("[force_law]"));
  const io::Case s1_back = io::parse_case(with_cutting(s1_text, s1_table), "s1-back.toml");
  EXPECT_NEAR(*s1_back.cutting.kt_pa, rs.fit.kt.value, 1e-12 * rs.fit.kt.value);
  EXPECT_FALSE(s1_back.cutting.kte_n_per_m.has_value());
}

TEST_F(IdentifyFiles, TwoFeedsGiveExactValuesWithoutIntervals) {
  const IdentifyCut slot{2, 0.0, units::kPi};
  const CuttingCoefficients k{650e6, 220e6, 0.0, 22e3, 18e3, 0.0};
  const fs::path forces = write(
      "two.csv", "feed_per_tooth_mm,depth_mm,fx_n,fy_n\n" + [&] {
        std::string rows;
        for (double feed_mm : {0.05, 0.1}) {
          const auto f = mean_milling_force(slot, k, units::mm_to_m(feed_mm), 2e-3);
          rows += io::format_number(feed_mm) + ",2," + io::format_number(f.x()) + "," +
                  io::format_number(f.y()) + "\n";
        }
        return rows;
      }());
  const io::Case c = load_case("", "milling-insperger");
  const IdentifyJobReport r = run_identify(c, request_of({forces}));
  EXPECT_NEAR(value(r, "Kt").value.value, 650.0, 1e-9);
  EXPECT_FALSE(value(r, "Kt").value.uncertainty_known);
  EXPECT_THAT(all(r.warnings), HasSubstr("degrees of freedom"));
  EXPECT_THAT(cutting_table_toml(c, r), HasSubstr("no interval: no residual degrees of freedom"));
}

TEST_F(IdentifyFiles, RefusalsOfTheFitNameTheFiles) {
  // One feed only: the fit refuses, naming the samples; the job says which files.
  const fs::path one = write("one.csv", "feed_per_tooth_mm,depth_mm,fx_n,fy_n\n0.1,2,-50,90\n");
  const io::Case c = load_case("", "milling-insperger");
  EXPECT_THAT(all(refusal(c, request_of({one}), one.string())),
              HasSubstr("need at least 2 distinct feeds"));
  const fs::path bad = write("bad.csv", "feed_per_tooth_mm,depth_mm,fx_n,fy_n\n0.1,2,-50,abc\n");
  EXPECT_THAT(all(refusal(c, request_of({bad}), bad.string())),
              HasSubstr("line 2, column fy_n: \"abc\" is not a number"));
}

}  // namespace
}  // namespace cutdyn::app
