// Golden outputs: every command on the built-in examples, its text and the files it writes,
// against the outputs kept in tests/golden/. A restructuring of the command line or the job
// layer must leave them unchanged (or change them on purpose: rerun with
// CUTDYN_UPDATE_GOLDEN=1 and review the diff). Numbers are compared to 1e-9 relative (plus
// 1e-12 absolute), everything else exactly; wall-clock times are masked.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "monitor/synthetic_logs.hpp"
#include "support/cli_runner.hpp"
#include "support/temp_dir.hpp"

namespace cutdyn::cli {
namespace {

namespace fs = std::filesystem;

struct Golden {
  std::string name;
  std::vector<std::string> args;  // "{dir}" is replaced by the test's temporary folder
  std::vector<std::string> files;  // written by the command, compared too
};

const std::vector<Golden>& goldens() {
  static const std::vector<Golden> all = {
      {"lobes-turning-ultrasonic", {"lobes", "--out", "{dir}/l.csv", "--json", "{dir}/l.json"},
       {"l.csv", "l.json"}},
      {"lobes-turning-conventional-target",
       {"lobes", "turning-conventional", "--target-depth-mm", "10", "--json", "{dir}/l.json"},
       {"l.json"}},
      {"lobes-turning-ultrasonic-speed", {"lobes", "turning-ultrasonic-speed"}, {}},
      {"lobes-milling-insperger", {"lobes", "milling-insperger", "--out", "{dir}/l.csv"}, {"l.csv"}},
      {"lobes-milling-variable-pitch", {"lobes", "milling-variable-pitch"}, {}},
      {"lobes-oxley", {"lobes", "oxley-aisi1045"}, {}},
      {"check-turning", {"check", "turning-ultrasonic", "--rpm", "1400", "--depth-mm", "10",
                         "--json", "{dir}/c.json"}, {"c.json"}},
      {"check-milling", {"check", "milling-insperger", "--rpm", "10000", "--depth-mm", "0.05"}, {}},
      {"simulate-turning", {"simulate", "turning-ultrasonic", "--duration-s", "0.5", "--json",
                            "{dir}/s.json"}, {"s.json"}},
      {"simulate-milling", {"simulate", "milling-insperger", "--json", "{dir}/s.json"}, {"s.json"}},
      {"simulate-ermolaev", {"simulate", "ermolaev2020"}, {}},
      {"plan", {"plan", "--json", "{dir}/p.json"}, {"p.json"}},
      {"force-ultrasonic", {"force", "ultrasonic-force"}, {}},
      {"force-aa5083", {"force", "ultrasonic-force-aa5083"}, {}},
      {"force-oxley", {"force", "oxley-aisi1045"}, {}},
      {"drive-ermolaev", {"drive", "ermolaev2020", "--json", "{dir}/d.json"}, {"d.json"}},
  };
  return all;
}

// Text with the folder replaced and wall-clock times masked ("0.24 s" in a lobes header,
// "seconds": … in JSON).
std::string normalise(std::string text, const std::string& dir) {
  std::string replaced;
  for (std::size_t from = 0;;) {
    const std::size_t at = text.find(dir, from);
    replaced.append(text, from, at == std::string::npos ? std::string::npos : at - from);
    if (at == std::string::npos) break;
    replaced += "{dir}";
    from = at + dir.size();
  }
  text = replaced;
  text = std::regex_replace(text, std::regex(R"(, [0-9.]+ s\n)"), ", <time> s\n");
  text = std::regex_replace(text, std::regex(R"("seconds": [0-9.eE+-]+)"), "\"seconds\": <time>");
  return text;
}

// Splits into numbers and the text between them.
std::vector<std::string> tokens(const std::string& text) {
  static const std::regex number(R"([-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?)");
  std::vector<std::string> out;
  std::size_t last = 0;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), number); it != std::sregex_iterator();
       ++it) {
    out.push_back(text.substr(last, static_cast<std::size_t>(it->position()) - last));
    std::string token(1, '#');
    token += it->str();
    out.push_back(std::move(token));
    last = static_cast<std::size_t>(it->position() + it->length());
  }
  out.push_back(text.substr(last));
  return out;
}

// "" when equal within the tolerance, else where they first differ.
std::string compare(const std::string& expected, const std::string& actual) {
  const auto a = tokens(expected), b = tokens(actual);
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    if (a[i] == b[i]) continue;
    if (a[i][0] == '#' && b[i][0] == '#') {
      const double x = std::strtod(a[i].c_str() + 1, nullptr), y = std::strtod(b[i].c_str() + 1, nullptr);
      if (std::abs(x - y) <= 1e-9 * std::max(std::abs(x), std::abs(y)) + 1e-12) continue;
    }
    std::string context;
    for (std::size_t j = i >= 3 ? i - 3 : 0; j < std::min(a.size(), i + 4); ++j) context += a[j];
    return "token " + std::to_string(i) + ": expected \"" + a[i] + "\", got \"" + b[i] +
           "\" near: " + context;
  }
  return a.size() == b.size() ? "" : "different lengths";
}

using testing::read_file;

class GoldenOutputs : public ::testing::TestWithParam<Golden> {};

// Compares (or with CUTDYN_UPDATE_GOLDEN=1 rewrites) each (golden file, output) pair.
void expect_golden(const std::vector<std::pair<std::string, std::string>>& outputs,
                   const std::string& dir) {
  const fs::path golden_dir = fs::path(CUTDYN_SOURCE_DIR) / "tests" / "golden";
  const bool update = std::getenv("CUTDYN_UPDATE_GOLDEN") != nullptr;
  for (const auto& [file, content] : outputs) {
    const std::string actual = normalise(content, dir);
    if (update) {
      std::ofstream(golden_dir / file, std::ios::binary) << actual;
      continue;
    }
    ASSERT_TRUE(fs::exists(golden_dir / file)) << file << ": no golden output (CUTDYN_UPDATE_GOLDEN=1)";
    EXPECT_EQ(compare(read_file(golden_dir / file), actual), "") << file;
  }
}

// A fresh folder for one golden case.
fs::path golden_folder(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() /
                       ("cutdyn-golden-" + std::to_string(::getpid()) + "-" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// The arguments with "{dir}" replaced by `dir`.
std::vector<std::string> in_folder(const std::vector<std::string>& args, const std::string& dir) {
  std::vector<std::string> out;
  for (std::string a : args) {
    if (const auto at = a.find("{dir}"); at != std::string::npos) a.replace(at, 5, dir);
    out.push_back(a);
  }
  return out;
}

TEST_P(GoldenOutputs, AreUnchanged) {
  const Golden& g = GetParam();
  const fs::path dir_ = golden_folder(g.name);
  const std::string dir = dir_.string();
  const auto r = testing::run_cutdyn(in_folder(g.args, dir));
  ASSERT_EQ(r.code, 0) << r.err;
  std::vector<std::pair<std::string, std::string>> outputs = {{g.name + ".txt", r.out}};
  for (const std::string& f : g.files) outputs.push_back({g.name + "." + f, read_file(dir_ / f)});
  expect_golden(outputs, dir);
  fs::remove_all(dir_);
}

INSTANTIATE_TEST_SUITE_P(Examples, GoldenOutputs, ::testing::ValuesIn(goldens()),
                         [](const ::testing::TestParamInfo<Golden>& param_info) {
                           std::string n = param_info.param.name;
                           for (char& ch : n)
                             if (ch == '-') ch = '_';
                           return n;
                         });

// ---- monitor: the commands read current logs ------------------------------------------
// Each case first writes the same logs into its folder (synthetic logs of the preset's axes
// x and y with noise on the currents and the speed, tests/monitor/synthetic_logs.hpp; fixed
// seeds), runs its `setup` commands (e.g. the calibration an estimate reads), then the
// command; its standard error (the estimate's summary, warnings, alarms) is compared too.
struct MonitorGolden {
  std::string name;
  std::vector<std::vector<std::string>> setup;
  std::vector<std::string> args;
  std::vector<std::string> files;
};

void write_monitor_logs(const fs::path& dir) {
  using testing::synthetic_run;
  const testing::LogNoise noise{0.05, 0.02};
  const AxisModel x = zheng2012_axis('x'), y = zheng2012_axis('y');
  const auto csv = [](const AxisRun& run, const std::string& axis, bool force = false) {
    return testing::to_csv(run, axis, force);
  };
  const auto body = [](const std::string& text) { return text.substr(text.find('\n') + 1); };
  const auto put = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name, std::ios::binary) << text;
  };
  put("idle.csv", csv(synthetic_run(x, testing::idle_profile(0.3), 1e-3, noise, 1), "x") +
                      body(csv(synthetic_run(y, testing::idle_profile(0.3), 1e-3, noise, 2), "y")));
  put("loaded_x.csv", csv(synthetic_run(x, testing::loaded_profile(0.2), 1e-3, noise, 3), "x", true));
  put("loaded_y.csv", csv(synthetic_run(y, testing::loaded_profile(0.2), 1e-3, noise, 4), "y", true));
  // Reference runs of axis x: 0.4 s at 60 rad/s and 2000 N; the cut: 2000 N, then an
  // overload of 3000 N from 0.25 s; axis y (no band) at -40 rad/s and 800 N.
  put("ref1.csv", csv(synthetic_run(x, {{60.0, 0.4, 2000.0}}, 1e-3, noise, 5, true), "x"));
  put("ref2.csv", csv(synthetic_run(x, {{60.0, 0.4, 2000.0}}, 1e-3, noise, 6, true), "x"));
  const std::string cut =
      csv(synthetic_run(x, {{60.0, 0.25, 2000.0}, {60.0, 0.15, 3000.0, 0.0}}, 1e-3, noise, 7,
                        true),
          "x") +
      body(csv(synthetic_run(y, {{-40.0, 0.1, 800.0}}, 1e-3, noise, 8, true), "y"));
  put("cut.csv", cut);
  // The cut with three bad lines (text, NaN, time going back) after its 11th data line.
  std::string bad = cut;
  std::size_t at = 0;
  for (int k = 0; k < 12; ++k) at = bad.find('\n', at) + 1;
  bad.insert(at, "0.0105,x,ten,-5,-5,60\n0.0106,x,20,-10,-10,NaN\n0.002,x,20,-10,-10,60\n");
  put("bad.csv", bad);
}

const std::vector<std::string> kCalibrate = {
    "monitor", "calibrate", "--idle", "{dir}/idle.csv", "--loaded", "{dir}/loaded_x.csv",
    "{dir}/loaded_y.csv", "--base", "zheng2012", "--out", "{dir}/calib.json"};
const std::vector<std::string> kTeach = {
    "monitor", "teach", "--calib", "{dir}/calib.json", "{dir}/ref1.csv", "{dir}/ref2.csv",
    "--out", "{dir}/band.json", "--rpm", "600", "--teeth", "4"};

const std::vector<MonitorGolden>& monitor_goldens() {
  static const std::vector<MonitorGolden> all = {
      {"monitor-calibrate", {}, kCalibrate, {"calib.json"}},
      {"monitor-calibrate-idle-kt",
       {},
       {"monitor", "calibrate", "--idle", "{dir}/idle.csv", "--kt", "0.1596", "--kt", "x=0.159",
        "--inertia", "x=1.667e-3", "--inertia", "y=1.383e-3", "--measure", "rms", "--base",
        "zheng2012",
        "--window-s", "0.04", "--out", "{dir}/calib.json"},
       {"calib.json"}},
      {"monitor-estimate",
       {kCalibrate},
       {"monitor", "estimate", "--calib", "{dir}/calib.json", "{dir}/cut.csv",
        "--tooth-frequency-hz", "40", "--json", "{dir}/e.json"},
       {"e.json"}},
      {"monitor-estimate-preset-skip",
       {},
       {"monitor", "estimate", "--calib", "zheng2012", "{dir}/bad.csv", "--on-bad-line", "skip",
        "--bandwidth-hz", "80", "--out", "{dir}/e.csv"},
       {"e.csv"}},
      {"monitor-estimate-band",
       {kCalibrate, kTeach},
       {"monitor", "estimate", "--calib", "{dir}/calib.json", "{dir}/cut.csv", "--band",
        "{dir}/band.json", "--alarms", "{dir}/alarms.csv", "--out", "{dir}/e.csv", "--json",
        "{dir}/e.json", "--persist-s", "0.004"},
       {"e.csv", "alarms.csv", "e.json"}},
      {"monitor-teach", {kCalibrate}, kTeach, {"band.json"}},
      // The currents of `cutdyn drive` (space-vector motors, with the rotor angle) against the
      // preset's constants in their measure.
      {"monitor-estimate-drive-currents",
       {{"drive", "ermolaev2020", "--currents", "{dir}/currents.csv", "--seed", "3"},
        {"monitor", "calibrate", "--base", "zheng2012", "--measure", "space-vector", "--out",
         "{dir}/sv.json"}},
       {"monitor", "estimate", "--calib", "{dir}/sv.json", "{dir}/currents.csv", "--out",
        "{dir}/e.csv", "--json", "{dir}/e.json"},
       {"sv.json", "e.csv", "e.json"}},
      {"monitor-teach-plain",
       {},
       {"monitor", "teach", "--calib", "zheng2012", "{dir}/ref1.csv", "--out", "{dir}/band.json",
        "--bin-s", "0.02", "--k-sigma", "4"},
       {"band.json"}},
  };
  return all;
}

class MonitorGoldenOutputs : public ::testing::TestWithParam<MonitorGolden> {};

TEST_P(MonitorGoldenOutputs, AreUnchanged) {
  const MonitorGolden& g = GetParam();
  const fs::path dir_ = golden_folder(g.name);
  const std::string dir = dir_.string();
  write_monitor_logs(dir_);
  for (const auto& command : g.setup) {
    const auto s = testing::run_cutdyn(in_folder(command, dir));
    ASSERT_EQ(s.code, 0) << s.err;
  }
  const auto r = testing::run_cutdyn(in_folder(g.args, dir));
  ASSERT_EQ(r.code, 0) << r.err;
  std::vector<std::pair<std::string, std::string>> outputs = {{g.name + ".txt", r.out},
                                                              {g.name + ".err.txt", r.err}};
  for (const std::string& f : g.files) outputs.push_back({g.name + "." + f, read_file(dir_ / f)});
  expect_golden(outputs, dir);
  fs::remove_all(dir_);
}

INSTANTIATE_TEST_SUITE_P(Monitor, MonitorGoldenOutputs, ::testing::ValuesIn(monitor_goldens()),
                         [](const ::testing::TestParamInfo<MonitorGolden>& param_info) {
                           std::string n = param_info.param.name;
                           for (char& ch : n)
                             if (ch == '-') ch = '_';
                           return n;
                         });

// ---- identify: the example force file, copied into the folder (its path is in the output) --

TEST(IdentifyGoldenOutputs, AreUnchanged) {
  const std::string name = "identify-milling-insperger";
  const fs::path dir_ = golden_folder(name);
  const std::string dir = dir_.string();
  fs::copy_file(
      fs::path(CUTDYN_SOURCE_DIR) / "examples" / "forces" / "milling-insperger-mean-forces.csv",
      dir_ / "forces.csv");
  const auto r = testing::run_cutdyn(in_folder({"identify", "milling-insperger", "{dir}/forces.csv",
                                                "--out", "{dir}/c.toml", "--json", "{dir}/i.json"},
                                               dir));
  ASSERT_EQ(r.code, 0) << r.err;
  expect_golden({{name + ".txt", r.out},
                 {name + ".c.toml", read_file(dir_ / "c.toml")},
                 {name + ".i.json", read_file(dir_ / "i.json")}},
                dir);
  fs::remove_all(dir_);
}

TEST(GoldenCompare, NumbersWithinTheToleranceAndTextExactly) {
  EXPECT_EQ(compare("depth 1.0000000000 mm", "depth 1.0000000001 mm"), "");
  EXPECT_NE(compare("depth 1.00000 mm", "depth 1.00001 mm"), "");
  EXPECT_NE(compare("depth 1 mm STABLE", "depth 1 mm UNSTABLE"), "");
  EXPECT_NE(compare("a 1 b", "a 1 b 2"), "");
  EXPECT_EQ(normalise("x, 0.24 s\n\"seconds\": 1.5e-3,", "/t"), "x, <time> s\n\"seconds\": <time>,");
}

}  // namespace
}  // namespace cutdyn::cli
