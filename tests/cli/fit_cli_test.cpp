// `cutdyn fit`: the modes of the example FRFs (known modes plus 1 % noise) recovered, the
// [[modes]] tables of --out read back by the case loader and giving the lobes of the case
// made from the same FRF, --json equal to the text, bad input refused with nothing written.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <complex>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cutdyn/app/case_models.hpp"
#include "cutdyn/app/stability.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/io/case_file.hpp"
#include "support/cli_runner.hpp"
#include "support/temp_dir.hpp"

namespace cutdyn::cli {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using Result = testing::CliResult;

const fs::path kFrf = fs::path(CUTDYN_SOURCE_DIR) / "examples" / "frf";

Result cutdyn(const std::vector<std::string>& args) { return testing::run_cutdyn(args); }

class FitCli : public testing::TempDirTest {
 protected:
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  void expect_rejected(const std::vector<std::string>& args, const std::string& needle) {
    const auto before = testing::listing(dir_);
    const Result r = cutdyn(args);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_THAT(r.err, HasSubstr(needle));
    EXPECT_EQ(testing::listing(dir_), before) << "a rejected run wrote files";
  }
};

// examples/frf/README.md: x 520 Hz ζ 0.035 k 1.8e7, 1380 Hz ζ 0.020 k 4.5e7; y 610 Hz ζ 0.030
// k 2.2e7, 1450 Hz ζ 0.025 k 6.0e7. The fit's stated accuracy at 1 % noise: frequency 0.5 %,
// damping 5 %, stiffness 3 % (docs/models/modal-fitting.md).
TEST_F(FitCli, RecoversTheExampleModesInEveryFormatAndWritesThemForACase) {
  struct Truth {
    double hz, zeta, k;
  };
  const std::vector<std::pair<std::string, std::vector<Truth>>> cases{
      {"x", {{520.0, 0.035, 1.8e7}, {1380.0, 0.020, 4.5e7}}},
      {"y", {{610.0, 0.030, 2.2e7}, {1450.0, 0.025, 6.0e7}}}};
  for (const auto& [direction, truth] : cases) {
    for (const char* ext : {".frf", ".csv", ".uff"}) {
      const std::string file = (kFrf / ("tool_" + direction + ext)).string();
      const std::string out = path("modes_" + direction + ".toml");
      const Result r =
          cutdyn({"fit", file, "--direction", direction, "--out", out, "--json", path("fit.json")});
      ASSERT_EQ(r.code, 0) << r.err;
      EXPECT_THAT(r.out, HasSubstr("2 modes in " + direction + " (chosen from the stabilisation"));
      std::ifstream in(out);
      std::stringstream text;
      text << in.rdbuf();
      const io::Case c = io::parse_case("process = \"milling\"\n" + text.str(), out);
      ASSERT_EQ(c.modal.modes.size(), 2u) << file;
      const auto doc = nlohmann::json::parse(std::ifstream(path("fit.json")));
      EXPECT_EQ(doc["command"], "fit");
      for (std::size_t i = 0; i < 2; ++i) {
        const Mode& m = c.modal.modes[i];
        EXPECT_EQ(to_string(m.direction), direction);
        EXPECT_NEAR(units::rad_per_s_to_hz(m.natural_rad_s) / truth[i].hz, 1.0, 5e-3) << file;
        EXPECT_NEAR(m.damping_ratio / truth[i].zeta, 1.0, 0.05) << file;
        EXPECT_NEAR(m.stiffness_n_per_m / truth[i].k, 1.0, 0.03) << file;
        // The file holds the JSON's numbers (to the digits written).
        EXPECT_NEAR(doc["modes"][i]["stiffness_n_per_m"].get<double>(), m.stiffness_n_per_m,
                    1e-9 * m.stiffness_n_per_m);
      }
    }
  }
}

TEST_F(FitCli, SpuriousPolesDroppedByTheAutomaticChoiceAreNotesNotWarnings) {
  // tool_y's noise makes a pole near 1021 Hz that the automatic choice drops: said on stdout
  // as a note, with no warning on stderr.
  const Result r = cutdyn({"fit", (kFrf / "tool_y.csv").string(), "--direction", "y"});
  ASSERT_EQ(r.code, 0);
  EXPECT_THAT(r.out, HasSubstr("note: pole at 1020"));
  EXPECT_EQ(r.err, "");
  // Asked for 3 modes where the table holds 2: refused with the reason, not 2 without a word.
  expect_rejected({"fit", (kFrf / "tool_y.csv").string(), "--modes", "3", "--out", path("o.toml")},
                  "modes = 3: the band 50…3000 Hz holds 2 distinct physical mode(s)");
}

TEST_F(FitCli, TheDirectionIsTheUffFilesResponseDirectionUnlessGiven) {
  // tool_y.uff names its response +Y (record 6); a CSV names none: x unless --direction.
  EXPECT_THAT(cutdyn({"fit", (kFrf / "tool_y.uff").string()}).out, HasSubstr("2 modes in y"));
  EXPECT_THAT(cutdyn({"fit", (kFrf / "tool_y.csv").string()}).out, HasSubstr("2 modes in x"));
  EXPECT_THAT(cutdyn({"fit", (kFrf / "tool_y.uff").string(), "--direction", "x"}).out,
              HasSubstr("2 modes in x"));
}

TEST_F(FitCli, FittedModesGiveTheLobesOfTheMeasuredCase) {
  // The example case with [[frf]] and the same case with the [[modes]] `fit` wrote: the full
  // discretization of the one uses the modes fitted by the other's loader, the same fit.
  const io::Case measured = io::load_case_file(kFrf / "milling-measured.toml");
  std::string modes;
  for (const char* d : {"x", "y"}) {
    const std::string out = path(std::string("m") + d + ".toml");
    ASSERT_EQ(cutdyn({"fit", (kFrf / (std::string("tool_") + d + ".csv")).string(), "--direction",
                      d, "--out", out})
                  .code,
              0);
    std::ifstream in(out);
    std::stringstream text;
    text << in.rdbuf();
    modes += text.str() + "\n";
  }
  std::string with_modes = measured.text;
  const auto cut = with_modes.find("[[frf]]"), end = with_modes.find("[cutting]");
  with_modes.replace(cut, end - cut, modes);
  const io::Case fitted = io::parse_case(with_modes, "fitted");
  for (double rpm : {6000.0, 12000.0}) {
    app::CheckRequest r;
    r.rpm = rpm;
    r.depth_m = 0.5e-3;
    r.method = "full-discretization";
    const double a = app::run_check(measured, r).boundary.depth_m;
    const double b = app::run_check(fitted, r).boundary.depth_m;
    EXPECT_NEAR(a / b, 1.0, 1e-6) << rpm;
  }
}

TEST_F(FitCli, BadInputIsRefusedWithNothingWritten) {
  const std::string x = (kFrf / "tool_x.csv").string();
  expect_rejected({"fit", x, "--band", "2500:200", "--out", path("o.toml")}, "--band");
  expect_rejected({"fit", x, "--modes", "two", "--out", path("o.toml")}, "--modes");
  expect_rejected({"fit", x, "--band", "5000:6000", "--out", path("o.toml")}, "band");
  expect_rejected({"fit", path("missing.csv"), "--out", path("o.toml")}, "missing.csv");
  std::ofstream(path("bad.frf")) << "10 1e-8 0\n20 1e-8 0\n15 1e-8 0\n";
  const auto before = testing::listing(dir_);
  const Result r = cutdyn({"fit", path("bad.frf"), "--out", path("o.toml")});
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("line 3"));
  EXPECT_EQ(testing::listing(dir_), before);
  // The same file named by a case's [[frf]]: every command that loads the case refuses it.
  std::ofstream(path("case.toml"))
      << "process = \"milling\"\n[[frf]]\ndirection = \"x\"\nfile = \"bad.frf\"\n"
         "[cutting]\nkt_n_per_mm2 = 600\n[tool]\nteeth = 2\ndiameter_mm = 20\n";
  expect_rejected({"lobes", path("case.toml"), "--out", path("l.csv")},
                  "frf[0].file = \"bad.frf\": line 3");
  expect_rejected(
      {"check", path("case.toml"), "--rpm", "9000", "--depth-mm", "1", "--json", path("c.json")},
      "line 3");
  // An output that names an input is refused before anything is read or written (every
  // command: the check is the command line's).
  expect_rejected({"fit", path("bad.frf"), "--out", path("bad.frf")}, "is an input");
  expect_rejected({"lobes", path("case.toml"), "--out", path("case.toml")}, "is an input");
}

// The example x table (1 % noise) rewritten: as a mobility in receptance columns, and with a
// header in units cutdyn does not read.
TEST_F(FitCli, UnitsAndQuantitiesAreNotTakenOnFaith) {
  std::ifstream in(kFrf / "tool_x.frf");
  std::ostringstream mobility, feet, stiffness;
  mobility << "Frequency Real Imaginary\n";
  feet << "Freq[Hz] re[ft/N] im[ft/N]\n";
  stiffness << "Freq[Hz] re[N/m] im[N/m]\n";
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '%') continue;
    std::istringstream fields(line);
    double f = 0, re = 0, im = 0;
    fields >> f >> re >> im;
    const std::complex<double> y = std::complex<double>(0, 2 * 3.141592653589793 * f) *
                                   std::complex<double>(re, im);
    mobility << f << ' ' << y.real() << ' ' << y.imag() << '\n';
    feet << f << ' ' << re / 0.3048 << ' ' << im / 0.3048 << '\n';
    stiffness << f << ' ' << re << ' ' << im << '\n';
  }
  std::ofstream(path("mobility.frf")) << mobility.str();
  std::ofstream(path("feet.frf")) << feet.str();
  std::ofstream(path("stiffness.frf")) << stiffness.str();
  // A mobility stored as receptance: refused with the evidence, nothing written, also through
  // a case's [[frf]].
  expect_rejected({"fit", path("mobility.frf"), "--out", path("o.toml")},
                  "behave like a mobility (velocity per force) stored as a receptance");
  std::ofstream(path("case.toml"))
      << "process = \"milling\"\n[[frf]]\ndirection = \"x\"\nfile = \"mobility.frf\"\n"
         "[cutting]\nkt_n_per_mm2 = 600\n[tool]\nteeth = 2\ndiameter_mm = 20\n";
  expect_rejected({"lobes", path("case.toml"), "--out", path("l.csv")},
                  "frf[0].file = \"mobility.frf\": as a direct receptance");
  // Unknown or wrong unit words: refused naming the line, unless the units are given.
  expect_rejected({"fit", path("feet.frf"), "--out", path("o.toml")},
                  "line 1: \"ft/N\" is not a unit cutdyn knows");
  expect_rejected({"fit", path("stiffness.frf"), "--out", path("o.toml")},
                  "line 1: \"N/m\" is a dynamic stiffness");
  expect_rejected({"fit", path("feet.frf"), "--units", "Hz, furlongs/N", "--out", path("o.toml")},
                  "units = \"Hz, furlongs/N\"");
  // Given as (m/s)/N, the mobility is read as what it is; feet given in mm/N is just a scale.
  const Result y = cutdyn({"fit", path("mobility.frf"), "--units", "(m/s)/N", "--json",
                           path("y.json")});
  ASSERT_EQ(y.code, 0) << y.err;
  const Result ref = cutdyn({"fit", (kFrf / "tool_x.frf").string(), "--json", path("ref.json")});
  ASSERT_EQ(ref.code, 0) << ref.err;
  const auto read_json = [&](const std::string& name) {
    std::ifstream f(path(name));
    return nlohmann::json::parse(f);
  };
  const auto jy = read_json("y.json"), jr = read_json("ref.json");
  ASSERT_EQ(jy["modes"].size(), jr["modes"].size());
  for (std::size_t i = 0; i < jr["modes"].size(); ++i) {
    EXPECT_NEAR(jy["modes"][i]["natural_hz"].get<double>(),
                jr["modes"][i]["natural_hz"].get<double>(),
                1e-6 * jr["modes"][i]["natural_hz"].get<double>());
    EXPECT_NEAR(jy["modes"][i]["stiffness_n_per_m"].get<double>(),
                jr["modes"][i]["stiffness_n_per_m"].get<double>(),
                1e-4 * jr["modes"][i]["stiffness_n_per_m"].get<double>());
  }
  EXPECT_EQ(jy["quantity"], "mobility");
  const Result mm = cutdyn({"fit", path("feet.frf"), "--units", "Hz, mm/N", "--json",
                            path("mm.json")});
  ASSERT_EQ(mm.code, 0) << mm.err;
  const auto jm = read_json("mm.json");
  // ft → mm: the values were divided by 0.3048 m; read as mm they are 1e-3/0.3048 of the truth,
  // so the stiffness comes out 0.3048e3 times as large.
  EXPECT_NEAR(jm["modes"][0]["stiffness_n_per_m"].get<double>() /
                  jr["modes"][0]["stiffness_n_per_m"].get<double>(),
              304.8, 304.8 * 1e-4);
}

// A coherence column is read and used: the text and the JSON say the fit weighed by it, the
// modes are the example's; a coherence of 95 (a percentage) is refused naming the line.
TEST_F(FitCli, ACoherenceColumnWeighsTheFitAndABadOneIsRefused) {
  std::ifstream in(kFrf / "tool_x.csv");
  std::ostringstream with, percent;
  with << "frequency_hz,real_m_per_n,imag_m_per_n,coherence\n";
  percent << "frequency_hz,real_m_per_n,imag_m_per_n,coherence\n";
  int n = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#' || line[0] == 'f') continue;
    // Lower coherence on every fifth line: an uneven noise the weights can tell.
    with << line << "," << (n % 5 == 0 ? "0.9" : "0.995") << "\n";
    percent << line << "," << (n == 7 ? "95" : "0.99") << "\n";
    ++n;
  }
  std::ofstream(path("coh.csv")) << with.str();
  std::ofstream(path("percent.csv")) << percent.str();
  const Result r = cutdyn({"fit", path("coh.csv"), "--json", path("coh.json")});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("(the fit weighted by the coherence)"));
  EXPECT_THAT(r.out, HasSubstr("weighted by the table's coherence (lowest γ² 0.900"));
  std::ifstream j(path("coh.json"));
  const auto json = nlohmann::json::parse(j);
  EXPECT_EQ(json["noise"]["coherence_weighted"], true);
  ASSERT_EQ(json["modes"].size(), 2u);
  EXPECT_NEAR(json["modes"][0]["natural_hz"].get<double>(), 520.0, 0.005 * 520.0);
  EXPECT_NEAR(json["modes"][1]["stiffness_n_per_m"].get<double>(), 4.5e7, 0.03 * 4.5e7);
  expect_rejected({"fit", path("percent.csv"), "--out", path("o.toml")},
                  "line 9: coherence 95 is not 0 to 1 (the ordinary coherence γ², not a "
                  "percentage or dB)");
}

}  // namespace
}  // namespace cutdyn::cli
