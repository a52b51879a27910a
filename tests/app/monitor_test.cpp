// The monitor jobs from C++ (cutdyn/app/monitor.hpp): calibrate, estimate fed chunk by chunk,
// teach, and the calibration and band files read back as they were written.
#include "cutdyn/app/monitor.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "cutdyn/core/error.hpp"
#include "cutdyn/io/output.hpp"
#include "monitor/synthetic_logs.hpp"
#include "support/temp_dir.hpp"

namespace cutdyn::app {
namespace {

using testing::synthetic_run;

// Every value of two calibrations, compared exactly.
void expect_same(const Calibration& a, const Calibration& b) {
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [axis, x] : a) {
    const AxisCalibration& y = b.at(axis);
    const auto values = [](const AxisCalibration& c) {
      const AxisModel& m = c.model;
      const AxisUncertainty& s = c.sigma;
      return std::vector<double>{m.inertia_kg_m2,
                                 m.torque_constant_nm_per_a,
                                 m.viscous_nm_s_per_rad,
                                 m.friction_nm,
                                 m.force_gain_m,
                                 s.inertia_kg_m2,
                                 s.torque_constant_nm_per_a,
                                 s.viscous_nm_s_per_rad,
                                 s.friction_nm,
                                 s.friction_viscous_covariance,
                                 s.force_gain_m,
                                 c.current_noise_a,
                                 c.speed_noise_rad_s};
    };
    EXPECT_EQ(values(x), values(y)) << "axis " << axis;
    EXPECT_EQ(x.model.measure, y.model.measure) << "axis " << axis;
    EXPECT_EQ(x.uncertainty_known, y.uncertainty_known) << "axis " << axis;
  }
}

class MonitorJobs : public testing::TempDirTest {
 protected:
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream((dir_ / name).string(), std::ios::binary) << text;
    return (dir_ / name).string();
  }
  // Noisy idle and loaded logs of the preset's axis x, calibrated on the preset's KT and J.
  CalibrateReport calibrate_x() {
    const AxisModel x = zheng2012_axis('x');
    const testing::LogNoise noise{0.05, 0.02};
    CalibrateOptions o;
    o.idle = {
        write("idle.csv",
              testing::to_csv(synthetic_run(x, testing::idle_profile(0.3), 1e-3, noise, 1), "x"))};
    o.loaded = {write("loaded.csv", testing::to_csv(synthetic_run(x, testing::loaded_profile(0.2),
                                                                  1e-3, noise, 2),
                                                    "x", true))};
    o.base = "zheng2012";
    return calibrate(o);
  }
};

TEST_F(MonitorJobs, CalibrationFileReadsBackAsTheCalibrationInMemory) {
  const CalibrateReport report = calibrate_x();
  ASSERT_EQ(report.axes.size(), 1u);
  const CalibratedAxis& x = report.axes.at("x");
  ASSERT_TRUE(x.idle && x.load);
  EXPECT_TRUE(x.calibration.uncertainty_known);
  // The fit finds the preset's constants the logs were made with (noise: within 2 %).
  const AxisModel truth = zheng2012_axis('x');
  EXPECT_NEAR(x.calibration.model.friction_nm, truth.friction_nm, 0.02 * truth.friction_nm);
  EXPECT_NEAR(x.calibration.model.force_gain_m, truth.force_gain_m, 0.02 * truth.force_gain_m);
  EXPECT_GT(x.calibration.sigma.force_gain_m, 0.0);
  // Written as the command writes it, read back: every value the same, to the last bit.
  {
    std::ofstream file(dir_ / "calib.json");
    io::write_json(file, calibration_json(report.axes));
  }
  const Calibration back = read_calibration((dir_ / "calib.json").string());
  expect_same(back, report.calibration());
  // The preset too, through its document.
  expect_same(calibration_from_json(calibration_json(zheng2012_preset()), "preset"),
              zheng2012_preset());
}

// Found by fuzz_calibration and fuzz_band (docs/fuzzing.md): a number that no double holds
// made the JSON reader throw out_of_range, which escaped the readers' InvalidInput.
TEST_F(MonitorJobs, FuzzANumberNoDoubleHoldsIsNotJson) {
  std::ofstream(dir_ / "calib.json")
      << R"({"format": "cutdyn monitor calibration", "axes": {"x": {"friction_nm": 1e400}}})";
  std::ofstream(dir_ / "band.json") << R"({"format": "cutdyn monitor band", "bin_s": 1e400})";
  for (const char* name : {"calib.json", "band.json"}) {
    const std::string path = (dir_ / name).string();
    try {
      if (std::string(name) == "calib.json")
        read_calibration(path);
      else
        read_band(path);
      ADD_FAILURE() << name << " was read";
    } catch (const InvalidInput& e) {
      EXPECT_EQ(e.where(), path);
      ASSERT_EQ(e.problems().size(), 1u);
      EXPECT_EQ(e.problems()[0].rfind("not valid JSON: ", 0), 0u) << e.problems()[0];
    }
  }
}

// Found by fuzz_calibration and fuzz_band: a value of the wrong type where the files have a
// string (format, measure) threw json::type_error past the readers; a band's run count that no
// int holds was converted to int regardless (undefined; -2147483648 on x86-64).
TEST_F(MonitorJobs, FuzzWrongTypesAndHugeCountsAreRefusedByName) {
  const auto problem = [&](const std::string& text, bool band) -> std::string {
    std::ofstream(dir_ / "file.json") << text;
    try {
      if (band)
        read_band((dir_ / "file.json").string());
      else
        read_calibration((dir_ / "file.json").string());
    } catch (const InvalidInput& e) {
      return e.problems().at(0);
    }
    return "(read)";
  };
  const std::string axis =
      R"("inertia_kg_m2": 0.001, "torque_constant_nm_per_a": 1.2, "viscous_nm_s_per_rad": 0.01,
         "friction_nm": 1.5, "force_gain_m": 0.0006)";
  EXPECT_EQ(problem(R"({"format": 7, "axes": {}})", false),
            "format: must be \"cutdyn monitor calibration\"");
  EXPECT_EQ(problem(R"({"format": "cutdyn monitor calibration", "axes": {"x": {"measure": 0, )" +
                        axis + "}}}",
                    false),
            "axes.x.measure = \"0\": must be rms or space-vector");
  EXPECT_EQ(
      problem(R"({"format": "cutdyn monitor calibration", "axes": {"x": {"measure": "rms", )" +
                  axis + "}}}",
              false),
      "(read)");
  EXPECT_EQ(problem(R"({"format": ["cutdyn monitor band"], "axes": {}})", true),
            "format: must be \"cutdyn monitor band\"");
  const std::string band = R"({"format": "cutdyn monitor band", "bin_s": 0.01, "smoothing_s": 0.01,
      "axes": {"x": {"cycle_s": 0.02, "mean_n": [1, 2], "sigma_n": [0, 0], "upper_n": [2, 3],
                     "lower_n": [0, 1], "cutting": [1, 1], "runs": RUNS}}})";
  const auto with_runs = [&](const std::string& runs) {
    std::string text = band;
    return text.replace(text.find("RUNS"), 4, runs);
  };
  EXPECT_EQ(problem(with_runs("3"), true), "(read)");
  EXPECT_EQ(problem(with_runs("1e300"), true), "axes.x.runs = 1e+300: must be a whole number >= 0");
  EXPECT_EQ(problem(with_runs("-1"), true), "axes.x.runs = -1: must be a whole number >= 0");
  EXPECT_EQ(problem(with_runs("2.5"), true), "axes.x.runs = 2.5: must be a whole number >= 0");
}

// Logs held in memory (LogTexts) are read as the same logs in files: the same calibration and
// band to the last bit, and messages name them by their names.
TEST_F(MonitorJobs, LogsInMemoryAreReadAsFiles) {
  const AxisModel x = zheng2012_axis('x');
  const testing::LogNoise noise{0.05, 0.02};
  const std::string idle =
      testing::to_csv(synthetic_run(x, testing::idle_profile(0.3), 1e-3, noise, 1), "x");
  const std::string loaded =
      testing::to_csv(synthetic_run(x, testing::loaded_profile(0.2), 1e-3, noise, 2), "x", true);
  CalibrateOptions files, memory;
  files.idle = {write("idle.csv", idle)};
  files.loaded = {write("loaded.csv", loaded)};
  memory.idle = {"idle[0]"};
  memory.loaded = {"loaded[0]"};
  memory.texts = {{"idle[0]", idle}, {"loaded[0]", loaded}};
  files.base = memory.base = "zheng2012";
  const CalibrateReport from_files = calibrate(files);
  expect_same(calibrate(memory).calibration(), from_files.calibration());

  TeachOptions teach_files, teach_memory;
  teach_files.references = {files.loaded.front()};
  teach_files.calibration = "zheng2012";
  teach_memory.references = {"run"};
  teach_memory.texts = {{"run", loaded}};
  teach_memory.calibration = "given";
  teach_memory.calibration_given = zheng2012_preset();
  const TeachReport a = teach(teach_files), b = teach(teach_memory);
  EXPECT_EQ(band_json(a.band)["axes"], band_json(b.band)["axes"]);

  // A bad line of a log in memory is named by the log's name and line.
  memory.texts["idle[0]"] = idle.substr(0, idle.find('\n') + 1) + "0,x,1,2,three,4\n";
  try {
    calibrate(memory);
    FAIL() << "accepted a bad line";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where(), "idle[0]");
    EXPECT_NE(e.problems().at(0).find("line 2"), std::string::npos) << e.problems().at(0);
  }
  // One read gives all of the text, the next the end.
  LogInput in("log", "a,b\n1,2\n");
  EXPECT_EQ(in.read(), "a,b\n1,2\n");
  EXPECT_EQ(in.read(), "");
  EXPECT_EQ(in.name(), "log");
}

TEST_F(MonitorJobs, CalibrationFileErrorsNameTheKey) {
  nlohmann::json doc = calibration_json(zheng2012_preset());
  doc["axes"]["y"]["friction_nm"] = "much";
  try {
    calibration_from_json(doc, "c.json");
    FAIL() << "accepted a friction that is not a number";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where(), "c.json");
    EXPECT_EQ(e.problems().at(0), "axes.y.friction_nm = \"much\": must be a number");
  }
}

TEST_F(MonitorJobs, EstimateFedInAnyChunksGivesTheSameRows) {
  // 0.3 s at 60 rad/s under 2500 N on axis x: fed whole and fed 7 bytes at a time, the same
  // CSV; the row callback sees every sample, and the force after the filter's start is the
  // force the log was made with.
  const AxisModel x = zheng2012_axis('x');
  const std::string log =
      testing::to_csv(synthetic_run(x, {{60.0, 0.3, 2500.0}}, 1e-3, {}, 1, true), "x");
  const auto run = [&](std::size_t chunk, std::vector<double>* forces) {
    std::string csv;
    EstimateJob::Sinks sinks{[&](std::string_view rows) { csv += rows; },
                             [&](const EstimatedRow& r) {
                               if (forces) forces->push_back(r.estimate.force_n);
                             }};
    EstimateJob job(zheng2012_preset(), "zheng2012", {}, std::nullopt, {}, "log", sinks);
    for (std::size_t at = 0; at < log.size(); at += chunk)
      job.feed(std::string_view(log).substr(at, chunk));
    const EstimateReport report = job.finish();
    EXPECT_EQ(report.samples, 300u);
    EXPECT_EQ(report.axes.size(), 1u);
    EXPECT_FALSE(report.axes.at(0).sigma_known);  // the literature coefficients
    return csv;
  };
  std::vector<double> forces;
  const std::string whole = run(log.size(), &forces);
  EXPECT_EQ(run(7, nullptr), whole);
  EXPECT_EQ(whole.substr(0, whole.find('\n')), kEstimateHeader);
  ASSERT_EQ(forces.size(), 300u);
  EXPECT_NEAR(forces.back(), 2500.0, 1e-6 * 2500.0);
}

TEST_F(MonitorJobs, TeachThenEstimateRaisesTheOverload) {
  const AxisModel x = zheng2012_axis('x');
  TeachOptions t;
  t.references = {write(
      "ref.csv", testing::to_csv(synthetic_run(x, {{60.0, 0.5, 2000.0}}, 1e-3, {}, 1, true), "x"))};
  t.calibration = "zheng2012";
  t.rpm = 600.0;
  t.teeth = 4;
  const TeachReport taught = teach(t);
  EXPECT_TRUE(taught.warnings.empty());
  EXPECT_DOUBLE_EQ(taught.band.options.average_s, 0.025);  // the tooth period
  // The band file reads back as taught.
  const BandFile back = band_from_json(band_json(taught.band), "band.json");
  ASSERT_EQ(back.axes.size(), 1u);
  EXPECT_EQ(back.axes.at("x").upper_n, taught.band.axes.at("x").upper_n);
  EXPECT_EQ(back.axes.at("x").cutting, taught.band.axes.at("x").cutting);
  EXPECT_EQ(back.bandwidth_hz, 50.0);
  // The cut: 3000 N from 0.3 s. An overload alarm, reported as it is confirmed.
  const std::string cut = write(
      "cut.csv", testing::to_csv(synthetic_run(x, {{60.0, 0.3, 2000.0}, {60.0, 0.2, 3000.0, 0.0}},
                                               1e-3, {}, 1, true),
                                 "x"));
  std::vector<AlarmEvent> live;
  MonitorListener listener;
  listener.alarm = [&](const std::string&, const AlarmEvent& a) { live.push_back(a); };
  write("band.json", band_json(taught.band).dump());
  const EstimateReport r =
      estimate(cut, "zheng2012", {}, (dir_ / "band.json").string(), {}, listener);
  ASSERT_FALSE(r.alarms.empty());
  EXPECT_EQ(r.alarms.front().second.kind, AlarmKind::kOverload);
  // Caught within one tooth period (25 ms) of the step: the level is averaged over it.
  EXPECT_GT(r.alarms.front().second.time_s, 0.3);
  EXPECT_LT(r.alarms.front().second.time_s, 0.325);
  EXPECT_EQ(live.size(), r.alarms.size());
}

TEST_F(MonitorJobs, BadLinesAreSkippedAndCountedOrStop) {
  const std::string log =
      "time_s,axis,iu_a,iv_a,iw_a,speed_rad_s\n0,x,20,-10,-10,50\n0.001,x,ten,-5,-5,50\n"
      "0.002,x,20,-10,-10,50\n";
  EstimateOptions skip;
  skip.stop_at_bad_line = false;
  EstimateJob job(zheng2012_preset(), "zheng2012", skip);
  job.feed(log);
  const EstimateReport r = job.finish();
  EXPECT_EQ(r.samples, 2u);
  EXPECT_EQ(r.bad_lines, 1u);
  EstimateJob strict(zheng2012_preset(), "zheng2012", {}, std::nullopt, {}, "log");
  EXPECT_THROW(strict.feed(log), InvalidInput);
}

}  // namespace
}  // namespace cutdyn::app
