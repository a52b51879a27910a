// `cutdyn monitor calibrate | estimate | teach`, in-process through cli::run, and once as a
// real process reading a pipe line by line.
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli/app.hpp"
#include "cutdyn/monitor/force_estimator.hpp"
#include "monitor/drive_chain.hpp"
#include "monitor/synthetic_logs.hpp"
#include "support/cli_runner.hpp"
#include "support/temp_dir.hpp"

namespace cutdyn::cli {
namespace {

using testing::synthetic_run;

using Result = testing::CliResult;

Result cutdyn(const std::vector<std::string>& args) { return testing::run_cutdyn(args); }

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

class MonitorCli : public testing::TempDirTest {
 protected:
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name)) << text;
    return path(name);
  }
  // Idle and loaded logs of axes x and y (the preset), and their calibration.
  std::string calibrate() {
    const AxisModel x = zheng2012_axis('x'), y = zheng2012_axis('y');
    const std::string idle_x = testing::to_csv(synthetic_run(x, testing::idle_profile(0.3)), "x");
    const std::string idle_y = testing::to_csv(synthetic_run(y, testing::idle_profile(0.3)), "y");
    write("idle.csv", idle_x + idle_y.substr(idle_y.find('\n') + 1));
    write("loaded_x.csv",
          testing::to_csv(synthetic_run(x, testing::loaded_profile(0.2)), "x", true));
    write("loaded_y.csv",
          testing::to_csv(synthetic_run(y, testing::loaded_profile(0.2)), "y", true));
    const Result r = cutdyn({"monitor", "calibrate", "--idle", path("idle.csv"), "--loaded",
                             path("loaded_x.csv"), path("loaded_y.csv"), "--base", "zheng2012",
                             "--out", path("calib.json")});
    EXPECT_EQ(r.code, 0) << r.err;
    return path("calib.json");
  }
  // A run must fail with exit 2, say `needle` on stderr and leave no output file.
  void expect_rejected(std::vector<std::string> args, const std::string& needle) {
    const auto before = testing::listing(dir_);
    const Result r = cutdyn(args);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << "stderr: " << r.err;
    EXPECT_EQ(r.err.rfind("cutdyn: error: ", 0), 0u) << r.err;
    EXPECT_EQ(testing::listing(dir_), before) << "a rejected run wrote files";
  }
};

TEST_F(MonitorCli, CalibrateWritesTheDocumentedFile) {
  const std::string calib = calibrate();
  const auto doc = nlohmann::json::parse(std::ifstream(calib));
  EXPECT_EQ(doc["format"], "cutdyn monitor calibration");
  for (char a : {'x', 'y'}) {
    const AxisModel truth = zheng2012_axis(a);
    const auto& j = doc["axes"][std::string(1, a)];
    EXPECT_NEAR(j["friction_nm"].get<double>(), truth.friction_nm, 1e-6 * truth.friction_nm);
    EXPECT_NEAR(j["viscous_nm_s_per_rad"].get<double>(), truth.viscous_nm_s_per_rad,
                1e-6 * truth.viscous_nm_s_per_rad);
    EXPECT_NEAR(j["force_gain_m"].get<double>(), truth.force_gain_m, 1e-6 * truth.force_gain_m);
    EXPECT_EQ(j["measure"], "rms");
    EXPECT_EQ(j["idle_fit"]["distinct_speeds"], 5);
  }
  // KT and J are needed: without --base or --kt/--inertia the run is refused.
  expect_rejected({"monitor", "calibrate", "--idle", path("idle.csv"), "--out", path("c2.json")},
                  "the torque constant is unknown");
  // A current near the range of a double (a finite number, so the reader takes it) makes the
  // fit overflow: refused with what went wrong, not a calibration of NaN.
  std::istringstream idle(testing::read_file(path("idle.csv")));
  std::string line, huge;
  for (int i = 0; std::getline(idle, line); ++i) {
    if (i > 0 && i % 97 == 0) {  // iu_a, the third field, of every 97th line
      const std::size_t from = line.find(',', line.find(',') + 1) + 1;
      line.replace(from, line.find(',', from) - from, "1e300");
    }
    huge += line + "\n";
  }
  write("huge.csv", huge);
  expect_rejected({"monitor", "calibrate", "--idle", path("huge.csv"), "--base", "zheng2012",
                   "--out", path("c3.json")},
                  "step 1: the fit is not finite");
}

TEST_F(MonitorCli, EstimateStreamsTheForce) {
  const std::string calib = calibrate();
  const AxisModel x = zheng2012_axis('x');
  write("cut.csv",
        testing::to_csv(synthetic_run(x, {{60.0, 0.3, 2500.0}}, 1e-3, {}, 1, true), "x"));
  const Result r = cutdyn({"monitor", "estimate", "--calib", calib, path("cut.csv")});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto lines = lines_of(r.out);
  ASSERT_EQ(lines.size(), 301u);
  EXPECT_EQ(lines[0], "time_s,axis,force_n,force_sigma_n,speed_rad_s,accel_rad_s2");
  EXPECT_EQ(lines[200].rfind("0.199,x,2500,", 0), 0u) << lines[200];  // exact to 7 digits
  EXPECT_NE(r.err.find("300 samples"), std::string::npos) << r.err;
  // --out: the same to a file, the summary on stdout.
  const Result f =
      cutdyn({"monitor", "estimate", "--calib", calib, path("cut.csv"), "--out", path("est.csv")});
  ASSERT_EQ(f.code, 0) << f.err;
  EXPECT_EQ(testing::read_file(path("est.csv")), r.out);
}

TEST_F(MonitorCli, EstimateStatesItsFilter) {
  // The summary and --json state the filter (docs/models/monitor.md §4.1) for the log's step
  // (1 ms) and f_b = 50 Hz: −3 dB at 32.27 Hz, at the 40 Hz tooth frequency the closed form
  // of EstimateFilter, and what force_sigma_n covers.
  const AxisModel x = zheng2012_axis('x');
  write("cut.csv",
        testing::to_csv(synthetic_run(x, {{60.0, 0.3, 2500.0}}, 1e-3, {}, 1, true), "x"));
  const Result r = cutdyn({"monitor", "estimate", "--calib", "zheng2012", path("cut.csv"), "--out",
                           path("est.csv"), "--tooth-frequency-hz", "40", "--json",
                           path("est.json")});
  ASSERT_EQ(r.code, 0) << r.err;
  const EstimateFilter h{50.0, 1e-3};
  EXPECT_NE(r.out.find("−3 dB at " + std::to_string(h.minus_3db_hz()).substr(0, 4)),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("at the tooth frequency 40 Hz: gain"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("estimate of the filtered force"), std::string::npos) << r.out;
  const auto j = nlohmann::json::parse(testing::read_file(path("est.json")));
  const auto& f = j["axes"]["x"]["filter"];
  EXPECT_NEAR(f["minus_3db_hz"].get<double>(), h.minus_3db_hz(), 1e-9);
  EXPECT_NEAR(f["minus_3db_hz"].get<double>(), 32.27, 0.01);
  EXPECT_NEAR(f["step_s"].get<double>(), 1e-3, 1e-12);
  EXPECT_NEAR(f["gain_at_tooth_frequency"].get<double>(), h.gain(40.0), 1e-12);
  EXPECT_NEAR(f["lag_deg_at_tooth_frequency"].get<double>(), h.lag_deg(40.0), 1e-9);
  // At 1 kHz the discrete filter is not yet its continuous limit (−3 dB at 0.644·f_b = 32.2
  // Hz, lag 77.3° at 40 Hz): measured 32.27 Hz and 70.9°.
  EXPECT_NEAR(f["lag_deg_at_tooth_frequency"].get<double>(), 70.87, 0.01);
  EXPECT_EQ(j["samples"].get<int>(), 300);
  EXPECT_NE(j["force_sigma_n_covers"].get<std::string>().find("filtered force"), std::string::npos);
  // A negative tooth frequency is refused before anything is written.
  expect_rejected({"monitor", "estimate", "--calib", "zheng2012", path("cut.csv"), "--out",
                   path("est2.csv"), "--tooth-frequency-hz", "-4"},
                  "--tooth-frequency-hz = -4: must be a finite number >= 0");
}

// A current log of one axis "x" as CSV, with the rotor angle column or without it.
std::string log_csv(const AxisRun& run, bool with_angle) {
  std::string text = "time_s,axis,iu_a,iv_a,iw_a,speed_rad_s";
  text += with_angle ? ",rotor_angle_rad\n" : "\n";
  char line[256];
  for (const AxisSample& s : run) {
    std::snprintf(line, sizeof line, "%.17g,x,%.17g,%.17g,%.17g,%.17g", s.time_s, s.iu_a, s.iv_a,
                  s.iw_a, s.speed_rad_s);
    text += line;
    if (with_angle) {
      std::snprintf(line, sizeof line, ",%.17g", s.rotor_angle_rad);
      text += line;
    }
    text += "\n";
  }
  return text;
}

std::string calibration_json(const AxisModel& m) {
  nlohmann::json j{{"format", "cutdyn monitor calibration"}, {"version", 1}};
  j["axes"]["x"] = {{"measure", std::string(to_string(m.measure))},
                    {"inertia_kg_m2", m.inertia_kg_m2},
                    {"torque_constant_nm_per_a", m.torque_constant_nm_per_a},
                    {"viscous_nm_s_per_rad", m.viscous_nm_s_per_rad},
                    {"friction_nm", m.friction_nm},
                    {"force_gain_m", m.force_gain_m}};
  return j.dump();
}

// The mean of force_n in an estimate CSV from `from_s` on.
double mean_force(const std::string& csv, double from_s) {
  double sum = 0;
  int n = 0;
  const auto lines = lines_of(csv);
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const double t = std::stod(lines[i]);
    if (t < from_s) continue;
    const auto a = lines[i].find(',', lines[i].find(',') + 1);
    sum += std::stod(lines[i].substr(a + 1));
    ++n;
  }
  return n ? sum / n : 0.0;
}

TEST_F(MonitorCli, AidingLoadWarnsWithoutTheAngle) {
  // Down-milling pulls the table along the feed (docs/models/monitor.md §4.5): with
  // rotor_angle_rad the estimate has the right sign and no warning; without it, a warning on
  // stderr and in --json, never silence.
  testing::DriveAxisParameters p;
  p.friction_nm = 0.5;
  p.viscous = 0.01;
  p.noise_a = 0.025;
  double feed = 0;
  const auto sim = testing::milling_cut(600.0, true, 12, feed);
  const AxisRun run = testing::drive_log(p, sim, feed);
  double truth = 0;
  int n = 0;
  for (const AxisSample& s : run)
    if (s.time_s >= 0.4) truth += s.force_n, ++n;
  truth /= n;
  ASSERT_LT(truth, -200.0);
  write("calib.json", calibration_json(testing::drive_axis_model(p)));
  write("angle.csv", log_csv(run, true));
  write("plain.csv", log_csv(run, false));
  const Result a = cutdyn({"monitor", "estimate", "--calib", path("calib.json"), path("angle.csv"),
                           "--bandwidth-hz", "100", "--out", path("a.csv"), "--json",
                           path("a.json")});
  ASSERT_EQ(a.code, 0) << a.err;
  EXPECT_EQ(a.err.find("against the motion"), std::string::npos) << a.err;
  EXPECT_NEAR(mean_force(testing::read_file(path("a.csv")), 0.4), truth, 0.01 * std::abs(truth));
  const auto ja = nlohmann::json::parse(testing::read_file(path("a.json")));
  EXPECT_TRUE(ja["axes"]["x"]["warnings"].empty());
  EXPECT_EQ(ja["axes"]["x"]["torque_current"].get<std::string>().rfind("signed", 0), 0u);

  const Result b = cutdyn({"monitor", "estimate", "--calib", path("calib.json"), path("plain.csv"),
                           "--bandwidth-hz", "100", "--out", path("b.csv"), "--json",
                           path("b.json")});
  ASSERT_EQ(b.code, 0) << b.err;
  EXPECT_NE(b.err.find("cutdyn: warning: " + path("plain.csv") + ": line "), std::string::npos)
      << b.err;
  EXPECT_NE(b.err.find("the motor torque may be against the motion"), std::string::npos) << b.err;
  const auto jb = nlohmann::json::parse(testing::read_file(path("b.json")));
  ASSERT_EQ(jb["axes"]["x"]["warnings"].size(), 1u);
  EXPECT_EQ(jb["axes"]["x"]["warnings"][0]["kind"], "torque-sign");
  EXPECT_GT(jb["axes"]["x"]["warnings"][0]["samples"].get<int>(), 40);
  EXPECT_GT(std::abs(mean_force(testing::read_file(path("b.csv")), 0.4) - truth),
            0.3 * std::abs(truth));
}

TEST_F(MonitorCli, RecordedMeasureMustMatchTheCalibration) {
  // One default measure (space-vector, docs/models/monitor.md §1): a log that records another
  // measure for an axis is refused by calibrate and estimate (exit 2, naming the file, the
  // line, the axis and both measures); a matching one is accepted.
  AxisModel x = zheng2012_axis('x');
  x.measure = CurrentMeasure::kSpaceVector;
  x.torque_constant_nm_per_a /= std::sqrt(2.0);
  const std::string idle = testing::to_csv(synthetic_run(x, testing::idle_profile(0.3)), "x");
  const std::string loaded =
      testing::to_csv(synthetic_run(x, testing::loaded_profile(0.2)), "x", true);
  const std::string sv = "# axis = x, measure = space-vector, pole_pairs = 4\n";
  const std::string rms = "# axis = x, measure = rms, torque_constant_nm_per_a = 1.621\n";
  write("idle_sv.csv", sv + idle);
  write("loaded_sv.csv", sv + loaded);
  write("idle_rms.csv", rms + idle);
  const std::string kt = "x=" + std::to_string(x.torque_constant_nm_per_a);
  const std::string j = "x=" + std::to_string(x.inertia_kg_m2);
  // No --measure, no --base: space-vector, and the files agree.
  const Result ok = cutdyn({"monitor", "calibrate", "--idle", path("idle_sv.csv"), "--loaded",
                            path("loaded_sv.csv"), "--kt", kt, "--inertia", j, "--out",
                            path("calib.json")});
  ASSERT_EQ(ok.code, 0) << ok.err;
  const auto doc = nlohmann::json::parse(testing::read_file(path("calib.json")));
  EXPECT_EQ(doc["axes"]["x"]["measure"], "space-vector");
  expect_rejected({"monitor", "calibrate", "--idle", path("idle_rms.csv"), "--loaded",
                   path("loaded_sv.csv"), "--kt", kt, "--inertia", j, "--out", path("c2.json")},
                  "idle_rms.csv: line 1: axis x: the currents were logged with measure = rms, "
                  "the calibration's measure is space-vector");
  // estimate: the calibration is space-vector; the rms log is refused before any output.
  write("cut_rms.csv", rms + testing::to_csv(synthetic_run(x, {{60.0, 0.1, 500.0}}, 1e-3, {}, 1,
                                                           true),
                                             "x"));
  expect_rejected({"monitor", "estimate", "--calib", path("calib.json"), path("cut_rms.csv"),
                   "--out", path("est.csv")},
                  "cut_rms.csv: line 1: axis x: the currents were logged with measure = rms, "
                  "the calibration's measure is space-vector");
  // The preset keeps the source's rms: a space-vector log is refused against it.
  expect_rejected({"monitor", "estimate", "--calib", "zheng2012", path("idle_sv.csv"), "--out",
                   path("est.csv")},
                  "the currents were logged with measure = space-vector, the calibration's "
                  "measure is rms");
}

TEST_F(MonitorCli, MalformedInputStopsWithTheLine) {
  const std::string h = "time_s,axis,iu_a,iv_a,iw_a,speed_rad_s\n";
  const std::string ok = "0,x,20,-10,-10,50\n0.001,x,20,-10,-10,50\n";
  // A fitted calibration: with the literature one (zheng2012) the lines before a bad line
  // would also raise the warning that its uncertainty is unknown, before the error.
  const std::string calib = calibrate();
  const auto args = [&](const std::string& file) {
    return std::vector<std::string>{"monitor",  "estimate", "--calib",      calib,
                                    path(file), "--out",    path("est.csv")};
  };
  write("missing.csv", "time_s,axis,iu_a,iv_a,iw_a\n0,x,1,1,1\n");
  expect_rejected(args("missing.csv"), "missing.csv: line 1: missing column speed_rad_s");
  write("text.csv", h + ok + "0.002,x,ten,-5,-5,50\n");
  expect_rejected(args("text.csv"), "text.csv: line 4: iu_a = \"ten\": not a number");
  write("nan.csv", h + ok + "0.002,x,20,-10,-10,NaN\n");
  expect_rejected(args("nan.csv"), "nan.csv: line 4: speed_rad_s = \"NaN\": must be a finite");
  write("back.csv", h + ok + "0,x,20,-10,-10,50\n");
  expect_rejected(args("back.csv"), "back.csv: line 4: time_s = 0 s on axis x goes backwards");
  write("empty.csv", "");
  expect_rejected(args("empty.csv"), "empty.csv: line 1: empty input");
  write("short.csv", h + ok + "0.002,x,10,-5\n");
  expect_rejected(args("short.csv"), "short.csv: line 4: missing column iw_a, speed_rad_s");
  write("axis.csv", h + ok + "0.002,q,20,-10,-10,50\n");
  expect_rejected(args("axis.csv"), "line 4: axis \"q\" is not in the calibration");
  expect_rejected(
      {"monitor", "estimate", "--calib", "zheng2012", path("text.csv"), "--on-bad-line", "maybe"},
      "--on-bad-line = \"maybe\": must be stop or skip");
}

TEST_F(MonitorCli, SkipBadLinesReportsTheCount) {
  write("bad.csv",
        "time_s,axis,iu_a,iv_a,iw_a,speed_rad_s\n0,x,20,-10,-10,50\n0.001,x,ten,-5,-5,50\n"
        "0.002,x,20,-10,-10,nan\n0.003,x,20,-10,-10,50\n0.001,x,20,-10,-10,50\n");
  const Result r = cutdyn({"monitor", "estimate", "--calib", "zheng2012", path("bad.csv"),
                           "--on-bad-line", "skip", "--json", path("bad.json")});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(lines_of(r.out).size(), 3u);  // header + lines 2 and 5
  EXPECT_NE(r.err.find("bad.csv: skipped 3 bad lines"), std::string::npos) << r.err;
  // The JSON summary counts them too, beside the samples estimated.
  const auto j = nlohmann::json::parse(testing::read_file(path("bad.json")));
  EXPECT_EQ(j["skipped_lines"].get<int>(), 3);
  EXPECT_EQ(j["samples"].get<int>(), 2);
  EXPECT_NE(r.err.find("line 3: iu_a = \"ten\": not a number (skipped)"), std::string::npos);
  // All lines bad: nothing to estimate, exit 2.
  write("allbad.csv", "time_s,axis,iu_a,iv_a,iw_a,speed_rad_s\n0,x,a,b,c,d\n");
  const Result none = cutdyn(
      {"monitor", "estimate", "--calib", "zheng2012", path("allbad.csv"), "--on-bad-line", "skip"});
  EXPECT_EQ(none.code, 2);
  EXPECT_NE(none.err.find("no valid data line (1 skipped)"), std::string::npos) << none.err;
}

TEST_F(MonitorCli, TeachWithTheCutsSpeedAndTeethAveragesOverTheToothPeriod) {
  // --rpm 600 --teeth 4: the band file records the tooth period (25 ms) as the averaging
  // window, 0.12 of it as the smoothing, one revolution as the phase tolerance; an explicit
  // --smoothing-s wins; --rpm alone is refused.
  const AxisModel x = zheng2012_axis('x');
  write("ref.csv",
        testing::to_csv(synthetic_run(x, {{60.0, 0.5, 2000.0}}, 1e-3, {}, 1, true), "x"));
  const Result t = cutdyn({"monitor", "teach", "--calib", "zheng2012", path("ref.csv"), "--out",
                           path("band.json"), "--rpm", "600", "--teeth", "4"});
  ASSERT_EQ(t.code, 0) << t.err;
  EXPECT_EQ(t.err.find("warning"), std::string::npos) << t.err;
  const auto band = nlohmann::json::parse(std::ifstream(path("band.json")));
  EXPECT_DOUBLE_EQ(band.at("average_s").get<double>(), 0.025);
  EXPECT_DOUBLE_EQ(band.at("smoothing_s").get<double>(), 0.003);
  EXPECT_DOUBLE_EQ(band.at("phase_tolerance_s").get<double>(), 0.1);
  const Result u = cutdyn({"monitor", "teach", "--calib", "zheng2012", path("ref.csv"), "--out",
                           path("band2.json"), "--rpm", "600", "--teeth", "4", "--smoothing-s",
                           "0.005"});
  ASSERT_EQ(u.code, 0) << u.err;
  EXPECT_DOUBLE_EQ(
      nlohmann::json::parse(std::ifstream(path("band2.json"))).at("smoothing_s").get<double>(),
      0.005);
  expect_rejected({"monitor", "teach", "--calib", "zheng2012", path("ref.csv"), "--out",
                   path("band3.json"), "--rpm", "600"},
                  "--rpm needs --teeth");
  expect_rejected({"monitor", "teach", "--calib", "zheng2012", path("ref.csv"), "--out",
                   path("band3.json"), "--rpm", "-600", "--teeth", "4"},
                  "rpm");
}

TEST_F(MonitorCli, TeachThenEstimateFlagsOverload) {
  // Reference: 0.5 s at 60 rad/s and 2000 N. Monitored: the force rises to 3000 N at 0.3 s.
  const AxisModel x = zheng2012_axis('x');
  write("ref.csv",
        testing::to_csv(synthetic_run(x, {{60.0, 0.5, 2000.0}}, 1e-3, {}, 1, true), "x"));
  write("cut.csv", testing::to_csv(synthetic_run(x, {{60.0, 0.3, 2000.0}, {60.0, 0.2, 3000.0, 0.0}},
                                                 1e-3, {}, 1, true),
                                   "x"));
  const Result t = cutdyn(
      {"monitor", "teach", "--calib", "zheng2012", path("ref.csv"), "--out", path("band.json")});
  ASSERT_EQ(t.code, 0) << t.err;
  EXPECT_NE(t.err.find("no --rpm and --teeth: the monitored level keeps the tooth pattern"),
            std::string::npos)
      << t.err;
  const Result r =
      cutdyn({"monitor", "estimate", "--calib", "zheng2012", path("cut.csv"), "--band",
              path("band.json"), "--alarms", path("alarms.csv"), "--out", path("est.csv")});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("cutdyn: alarm: overload on axis x at 0.30"), std::string::npos) << r.err;
  const auto alarms = lines_of(testing::read_file(path("alarms.csv")));
  ASSERT_GE(alarms.size(), 2u);
  EXPECT_EQ(alarms[0], "time_s,axis,alarm,detected_s,level,limit");
  // Band 2000 ± (10 % + 5 %): the estimate is the step through the stated filter (the step
  // mean, then two first-order stages at q = exp(−2π·50 Hz·1 ms), docs/models/monitor.md §4.1),
  // and the level is its first-order low-pass (τ 10 ms, gain 1 − exp(−Δt/τ)): the alarm begins
  // at the first sample where that chain, run here on the ideal step, passes 2300 N (0.3105 s).
  const double q = std::exp(-2.0 * M_PI * 50.0 * 1e-3), g = 1.0 - std::exp(-1e-3 / 0.01);
  double y1 = 0, y2 = 0, level = 0, expected = 0;
  for (int k = 0; k < 200 && expected == 0; ++k) {  // the sample at 0.3 s + k ms
    const double mean = k == 0 ? 0.5 : 1.0;  // the step at 0.3 s: half of the first step
    y1 += (1 - q) * (mean - y1);
    y2 += (1 - q) * (y1 - y2);
    level += g * (y2 - level);
    if (2000.0 + 1000.0 * level > 2300.0) expected = 0.3 + k * 1e-3;
  }
  ASSERT_GT(expected, 0.305);
  EXPECT_NEAR(std::stod(alarms[1].substr(0, alarms[1].find(','))), expected, 1.5e-3);
  const auto est = lines_of(testing::read_file(path("est.csv")));
  EXPECT_EQ(est[0],
            "time_s,axis,force_n,force_sigma_n,speed_rad_s,accel_rad_s2,level_n,upper_n,"
            "lower_n,alarm");
  EXPECT_EQ(est.back().substr(est.back().rfind(',') + 1).rfind("overload", 0), 0u) << est.back();
  EXPECT_EQ(est[100].substr(est[100].rfind(',') + 1), "");
}

// The literature coefficients (--calib zheng2012) have no known uncertainty for any machine:
// force_sigma_n is left empty (not 0, not NaN) and a warning says why; a calibration fitted
// from idle and loaded logs gives a number; one that keeps the base's KBlf stays unknown.
TEST_F(MonitorCli, LiteratureCoefficientsHaveNoClaimedUncertainty) {
  const AxisModel x = zheng2012_axis('x');
  write("cut.csv",
        testing::to_csv(synthetic_run(x, {{60.0, 0.1, 2500.0}}, 1e-3, {}, 1, true), "x"));
  const Result lit = cutdyn({"monitor", "estimate", "--calib", "zheng2012", path("cut.csv")});
  ASSERT_EQ(lit.code, 0) << lit.err;
  EXPECT_NE(lit.err.find("uncertainty unknown for the literature coefficients"), std::string::npos)
      << lit.err;
  const auto rows = lines_of(lit.out);
  ASSERT_EQ(rows.size(), 101u);
  for (std::size_t i = 1; i < rows.size(); ++i) {
    // time,axis,force,<empty σ>,speed,accel; the force itself is still exact (2500 N).
    EXPECT_NE(rows[i].find(",x,2500,,"), std::string::npos) << rows[i];
    EXPECT_EQ(rows[i].find("nan"), std::string::npos) << rows[i];
  }
  // Fitted from logs: σ is a number (noise-free logs: the small fit uncertainties only).
  const Result fitted = cutdyn({"monitor", "estimate", "--calib", calibrate(), path("cut.csv")});
  ASSERT_EQ(fitted.code, 0) << fitted.err;
  EXPECT_EQ(fitted.err.find("uncertainty unknown"), std::string::npos) << fitted.err;
  const auto f = lines_of(fitted.out);
  const std::string sigma = f[50].substr(f[50].find(",x,") + 3);
  EXPECT_GE(std::stod(sigma.substr(sigma.find(',') + 1)), 0.0) << f[50];
  EXPECT_EQ(f[50].find(",,"), std::string::npos) << f[50];
  // Only the idle step on top of the base: KBlf is the paper's, the uncertainty unknown.
  const Result idle_only = cutdyn({"monitor", "calibrate", "--idle", path("idle.csv"), "--base",
                                   "zheng2012", "--out", path("idle_only.json")});
  ASSERT_EQ(idle_only.code, 0) << idle_only.err;
  const auto doc = nlohmann::json::parse(std::ifstream(path("idle_only.json")));
  EXPECT_FALSE(doc["axes"]["x"]["uncertainty_known"].get<bool>());
  const Result est =
      cutdyn({"monitor", "estimate", "--calib", path("idle_only.json"), path("cut.csv")});
  ASSERT_EQ(est.code, 0) << est.err;
  EXPECT_NE(lines_of(est.out)[50].find(",x,2500,,"), std::string::npos) << est.out;
}

// --bandwidth-hz must be positive and below the Nyquist frequency of the log (1 kHz samples:
// 500 Hz); otherwise exit 2 naming the value and the limit, and no output file.
TEST_F(MonitorCli, BandwidthAboveNyquistIsRejected) {
  const AxisModel x = zheng2012_axis('x');
  write("cut.csv",
        testing::to_csv(synthetic_run(x, {{60.0, 0.05, 2500.0}}, 1e-3, {}, 1, true), "x"));
  const std::string calib = calibrate();
  const auto args = [&](const std::string& bw) {
    return std::vector<std::string>{"monitor", "estimate",      "--calib",
                                    calib,     path("cut.csv"), "--bandwidth-hz",
                                    bw,        "--out",         path("est.csv")};
  };
  expect_rejected(args("600"), "bandwidth_hz = 600 Hz: must be below the Nyquist frequency");
  expect_rejected(args("500"), "of the samples, 500 Hz");
  expect_rejected(args("0"), "bandwidth_hz");
  expect_rejected(args("-5"), "bandwidth_hz");
  const Result ok = cutdyn(args("499"));
  EXPECT_EQ(ok.code, 0) << ok.err;
  // teach reads its runs through the same estimator.
  expect_rejected({"monitor", "teach", "--calib", calib, path("cut.csv"), "--bandwidth-hz", "1000",
                   "--out", path("band.json")},
                  "must be below the Nyquist frequency");
}

TEST_F(MonitorCli, StandardInputIsAnsweredLineByLine) {
  // A real process on a pipe: each line written gets its estimate before the next is sent
  // (the pipe stays open), so the estimate is usable live.
  int to_child[2], from_child[2];
  ASSERT_EQ(pipe(to_child), 0);
  ASSERT_EQ(pipe(from_child), 0);
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    dup2(to_child[0], 0);
    dup2(from_child[1], 1);
    close(to_child[1]);
    close(from_child[0]);
    execl(CUTDYN_BINARY, "cutdyn", "monitor", "estimate", "--calib", "zheng2012", "-",
          static_cast<char*>(nullptr));
    _exit(127);
  }
  close(to_child[0]);
  close(from_child[1]);
  std::string received;
  const auto read_until_lines = [&](std::size_t want) {
    char buf[4096];
    while (lines_of(received).size() < want) {
      pollfd p{from_child[0], POLLIN, 0};
      if (poll(&p, 1, 5000) <= 0) return false;
      const ssize_t n = read(from_child[0], buf, sizeof buf);
      if (n <= 0) return false;
      received.append(buf, static_cast<std::size_t>(n));
    }
    return true;
  };
  const std::string lines[] = {"time_s,axis,iu_a,iv_a,iw_a,speed_rad_s\n0,x,20,-10,-10,50\n",
                               "0.001,x,20,-10,-10,50\n", "0.002,x,20,-10,-10,50\n"};
  for (std::size_t k = 0; k < 3; ++k) {
    ASSERT_EQ(::write(to_child[1], lines[k].data(), lines[k].size()),
              static_cast<ssize_t>(lines[k].size()));
    EXPECT_TRUE(read_until_lines(k + 2)) << "no answer to line " << k + 2 << ": " << received;
  }
  close(to_child[1]);
  int status = 0;
  waitpid(pid, &status, 0);
  close(from_child[0]);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  EXPECT_EQ(lines_of(received).at(3).rfind("0.002,x,", 0), 0u) << received;
}

}  // namespace
}  // namespace cutdyn::cli
