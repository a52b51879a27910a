// The drive job from C++ (cutdyn/app/drive.hpp): the case's axes under its cut, the current
// log the monitor reads, and a sweep that is its single runs.
#include "cutdyn/app/drive.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "cutdyn/app/case_models.hpp"
#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/monitor/current_csv.hpp"

namespace cutdyn::app {
namespace {

// The cut of the case as `cutdyn drive` builds it (its speed and depth, [simulate]).
DriveCut cut_of(const io::Case& c) { return milling_setup(c, SimulateRequest{}); }

TEST(DriveJob, AxesTakeTheirShareOfTheFeedAndLogTheirCurrents) {
  const io::Case c = load_case("", "ermolaev2020");
  const DriveReport r = run_drive(c, cut_of(c), {7});
  ASSERT_EQ(r.axes.size(), c.drives.size());
  const double feed = r.cut.cut.feed_per_tooth_m * r.cut.cut.process.tool.teeth * r.cut.rpm / 60.0;
  for (const DriveAxisReport& a : r.axes) {
    EXPECT_GE(a.axis.direction[0], 0.0);  // turned along the feed
    EXPECT_DOUBLE_EQ(a.feed_speed_m_per_s, feed * a.axis.direction[0]);
    ASSERT_TRUE(a.axis.motor);
    EXPECT_EQ(a.axis.motor->seed, 7u);  // the options' seed for every axis
    EXPECT_EQ(a.cutter_m.size(), a.drive.time_s.size());
    EXPECT_GT(a.epsilon_pp_m, 0.0);
    EXPECT_EQ(drive_metrics(a).at(0), units::m_to_um(a.epsilon_pp_m));
  }
  // The current log: the monitor's parser reads every row and each axis' recorded measure.
  std::ostringstream log;
  write_current_log(log, r, c.source);
  CurrentCsvParser parser("log");
  std::vector<CurrentRow> rows;
  std::vector<CsvLineError> errors;
  parser.feed(log.str(), rows, errors, true);
  parser.finish(rows, errors, true);
  EXPECT_TRUE(errors.empty());
  std::size_t expected = 0;
  for (const DriveAxisReport& a : r.axes) {
    expected += axis_currents(a, r.traces_from_s).time_s.size();
    const auto m = parser.recorded_measure(a.axis.name);
    ASSERT_TRUE(m);
    EXPECT_EQ(m->first, a.axis.motor->measure);
  }
  EXPECT_EQ(rows.size(), expected);
  EXPECT_TRUE(parser.has_rotor_angle());
}

// The metrics of two runs are the same, NaN (a quantity the drive does not have) included.
void expect_same_metrics(const DriveAxisReport& a, const DriveAxisReport& b) {
  const std::vector<double> x = drive_metrics(a), y = drive_metrics(b);
  ASSERT_EQ(x.size(), y.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (std::isnan(x[i]))
      EXPECT_TRUE(std::isnan(y[i])) << drive_metric_names()[i];
    else
      EXPECT_EQ(x[i], y[i]) << drive_metric_names()[i];
  }
}

TEST(DriveJob, ASweepIsItsSingleRuns) {
  const io::Case c = load_case("", "ermolaev2020");
  const double rpm = *c.simulate.rpm;
  const DriveSweepReport sweep =
      run_drive_sweep(c, "simulate.rpm", {rpm, 1.5 * rpm}, cut_of, {}, 1);
  ASSERT_EQ(sweep.runs.size(), 2u);
  const io::Case faster = io::with_value(c, "simulate.rpm", 1.5 * rpm);
  const DriveReport single = run_drive(faster, cut_of(faster));
  // The overloads on the case's own cut give the same.
  expect_same_metrics(run_drive(faster, SimulateRequest{}).axes[0], single.axes[0]);
  const DriveSweepReport own =
      run_drive_sweep(c, Sweep{"simulate.rpm", {1.5 * rpm}}, SimulateRequest{}, {}, 1);
  expect_same_metrics(own.runs[0].axes[0], single.axes[0]);
  ASSERT_EQ(sweep.runs[1].axes.size(), single.axes.size());
  for (std::size_t k = 0; k < single.axes.size(); ++k)
    expect_same_metrics(sweep.runs[1].axes[k], single.axes[k]);
  EXPECT_DOUBLE_EQ(sweep.runs[0].cut.rpm, rpm);
  // A case without drives is refused before anything runs.
  EXPECT_THROW(
      run_drive_sweep(load_case("", "milling-insperger"), "simulate.rpm", {1000.0}, cut_of),
      InvalidInput);
}

TEST(DriveJob, ABeatingCutterModeDoesNotHideTheSteadyState) {
  // ermolaev2020 at 1200 rpm: the cutter's 503 Hz mode is almost undamped (ζ ≈ 2e-5), so the
  // static drives' speed still beats by about 1e-8 rad/s from one revolution to the next —
  // far less than moves the axis by 1 nm in a revolution. Both axes are steady, without a
  // warning (each warned before the 1 nm floor).
  const io::Case c = load_case("", "ermolaev2020");
  SimulateRequest r;
  r.rpm = 1200.0;
  const DriveReport report = run_drive(c, r);
  for (const DriveAxisReport& a : report.axes) {
    EXPECT_TRUE(a.drive.steady) << a.axis.name;
    EXPECT_TRUE(a.drive.warnings.empty()) << a.axis.name << ": " << a.drive.warnings.front();
  }
}

}  // namespace
}  // namespace cutdyn::app
