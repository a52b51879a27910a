// The monitor's CSV reader: good input in pieces, and each kind of malformed input.
#include "cutdyn/monitor/current_csv.hpp"

#include <gtest/gtest.h>

#include "cutdyn/core/error.hpp"

namespace cutdyn {
namespace {

struct Parsed {
  std::vector<CurrentRow> rows;
  std::vector<CsvLineError> errors;
  std::vector<std::string> axes;
};

// Whole text at once, or `piece` bytes at a time.
Parsed parse(const std::string& text, bool stop, std::size_t piece = 0,
             const std::string& extra = {}) {
  CurrentCsvParser p("log.csv", extra);
  Parsed r;
  if (piece == 0) piece = text.size() + 1;
  bool ok = true;
  for (std::size_t at = 0; ok && at < text.size(); at += piece)
    ok = p.feed(std::string_view(text).substr(at, piece), r.rows, r.errors, stop);
  if (ok) p.finish(r.rows, r.errors, stop);
  r.axes = p.axes();
  return r;
}

std::string problem_of(const std::string& text) {
  try {
    parse(text, true);
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where(), "log.csv");
    return e.problems().at(0);
  }
  return "(no error)";
}

const std::string kGood =
    "speed_rad_s,time_s,note,axis,iu_a,iv_a,iw_a\r\n"
    "10,0.000,a,x,1,-0.5,-0.5\r\n"
    "\n"
    "-20, 0.000 ,b, y ,+2,-1,-1e0\r\n"
    "11,0.001,c,x,1.5,-0.75,-0.75";  // no final line end

TEST(MonitorCsv, ParsesColumnsInAnyOrderInAnyPieces) {
  for (std::size_t piece : {0, 1, 3, 7}) {
    const Parsed r = parse(kGood, true, piece);
    ASSERT_EQ(r.rows.size(), 3u) << piece;
    EXPECT_TRUE(r.errors.empty());
    EXPECT_EQ(r.axes, (std::vector<std::string>{"x", "y"}));
    EXPECT_EQ(r.rows[1].line, 4u);
    EXPECT_EQ(r.rows[1].axis, 1);
    EXPECT_DOUBLE_EQ(r.rows[1].speed_rad_s, -20.0);
    EXPECT_DOUBLE_EQ(r.rows[1].iu_a, 2.0);
    EXPECT_DOUBLE_EQ(r.rows[2].time_s, 0.001);
    EXPECT_DOUBLE_EQ(r.rows[2].iw_a, -0.75);
  }
}

const std::string kHeader = "time_s,axis,iu_a,iv_a,iw_a,speed_rad_s\n";

TEST(MonitorCsv, MissingColumnInTheHeader) {
  EXPECT_EQ(problem_of("time_s,axis,iu_a,iv_a,speed_rad_s\n0,x,1,1,1\n"),
            "line 1: missing column iw_a (the header is \"time_s,axis,iu_a,iv_a,speed_rad_s\"; "
            "required: time_s,axis,iu_a,iv_a,iw_a,speed_rad_s)");
}

TEST(MonitorCsv, MissingColumnInALine) {
  const Parsed r = parse(kHeader + "0,x,1,1,1,5\n0.001,x,1,1\n0.002,x,1,1,1,5\n", false);
  ASSERT_EQ(r.errors.size(), 1u);
  EXPECT_EQ(r.errors[0].text(),
            "line 3: missing column iw_a, speed_rad_s (the line has 4 fields, the header 6)");
  EXPECT_EQ(r.rows.size(), 2u);  // skip: the others are kept
}

TEST(MonitorCsv, TextInANumber) {
  const Parsed r = parse(kHeader + "0,x,1,1,1,5\n0.001,x,1,abc,1,5\n0.002,x,1,1,1,5\n", true);
  ASSERT_EQ(r.errors.size(), 1u);
  EXPECT_EQ(r.errors[0].text(), "line 3: iv_a = \"abc\": not a number");
  EXPECT_EQ(r.rows.size(), 1u);  // stop: nothing after the bad line
  EXPECT_EQ(parse(kHeader + "0,x,1,1,1,5 rad/s\n", false).errors.at(0).text(),
            "line 2: speed_rad_s = \"5 rad/s\": not a number");
  EXPECT_EQ(parse(kHeader + "0,x,1,,1,5\n", false).errors.at(0).text(), "line 2: iv_a is empty");
}

TEST(MonitorCsv, NanAndInfinity) {
  const Parsed r = parse(kHeader + "0,x,1,1,1,nan\n0.001,x,inf,1,1,5\n0.002,x,1,1,1,5\n", false);
  ASSERT_EQ(r.errors.size(), 2u);
  EXPECT_EQ(r.errors[0].text(), "line 2: speed_rad_s = \"nan\": must be a finite number");
  EXPECT_EQ(r.errors[1].text(), "line 3: iu_a = \"inf\": must be a finite number");
  EXPECT_EQ(r.rows.size(), 1u);
}

TEST(MonitorCsv, TimeGoingBackwardsPerAxis) {
  // y may start earlier than x's last sample; x may not go back, nor repeat.
  const Parsed r = parse(kHeader +
                             "0.002,x,1,1,1,5\n0.000,y,1,1,1,5\n0.001,x,1,1,1,5\n"
                             "0.002,x,1,1,1,5\n0.003,x,1,1,1,5\n",
                         false);
  ASSERT_EQ(r.errors.size(), 2u);
  EXPECT_EQ(r.errors[0].text(),
            "line 4: time_s = 0.001 s on axis x goes backwards from line 2 (0.002 s): time must "
            "increase on each axis");
  EXPECT_EQ(r.errors[1].text(),
            "line 5: time_s = 0.002 s on axis x repeats line 2 (0.002 s): time must increase on "
            "each axis");
  EXPECT_EQ(r.rows.size(), 3u);
}

TEST(MonitorCsv, EmptyInput) {
  EXPECT_EQ(problem_of(""),
            "line 1: empty input: expected a header line with the columns "
            "time_s,axis,iu_a,iv_a,iw_a,speed_rad_s");
  EXPECT_EQ(problem_of("\n \n"), problem_of(""));
  EXPECT_EQ(problem_of(kHeader), "line 2: no data after the header (the input ends at line 1)");
}

TEST(MonitorCsv, ExtraColumnIsRequiredWhenAsked) {
  const Parsed r = parse("time_s,axis,iu_a,iv_a,iw_a,speed_rad_s,force_n\n0,x,1,1,1,5,250\n", true,
                         0, "force_n");
  ASSERT_EQ(r.rows.size(), 1u);
  EXPECT_DOUBLE_EQ(r.rows[0].extra, 250.0);
  EXPECT_THROW(parse(kHeader + "0,x,1,1,1,5\n", true, 0, "force_n"), InvalidInput);
}

TEST(MonitorCsv, WritesEstimateRows) {
  std::string out;
  append_estimate_row(out, 0.001, "x", ForceEstimate{1234.56789012, 12.5, 80.0, -3.25, false});
  EXPECT_EQ(out, "0.001,x,1234.568,12.5,80,-3.25");
  // An unknown uncertainty (the literature coefficients) leaves the field empty, never NaN
  // or a made-up number.
  out.clear();
  append_estimate_row(out, 0.002, "y", ForceEstimate{-10.0, 0.0, -5.0, 0.0, false, false});
  EXPECT_EQ(out, "0.002,y,-10,,-5,0");
}

}  // namespace
}  // namespace cutdyn

namespace cutdyn {
namespace {

TEST(MonitorCsvAngle, OptionalRotorAngleColumn) {
  // Where the header has rotor_angle_rad every line gives it; without it, rows carry 0 and
  // has_rotor_angle() is false.
  CurrentCsvParser with("a.csv");
  std::vector<CurrentRow> rows;
  std::vector<CsvLineError> errors;
  with.feed("time_s,axis,rotor_angle_rad,iu_a,iv_a,iw_a,speed_rad_s\n0,x,1.25,1,-0.5,-0.5,3\n"
            "0.001,x,,1,-0.5,-0.5,3\n0.002,x,-7.5,1,-0.5,-0.5,3\n",
            rows, errors, false);
  with.finish(rows, errors, false);
  EXPECT_TRUE(with.has_rotor_angle());
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].rotor_angle_rad, 1.25);
  EXPECT_EQ(rows[1].rotor_angle_rad, -7.5);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].text(), "line 3: rotor_angle_rad is empty");
  CurrentCsvParser without("b.csv");
  rows.clear();
  without.feed("time_s,axis,iu_a,iv_a,iw_a,speed_rad_s\n0,x,1,-0.5,-0.5,3\n", rows, errors, false);
  without.finish(rows, errors, false);
  EXPECT_FALSE(without.has_rotor_angle());
  // A line too short for the angle names it.
  CurrentCsvParser shortline("c.csv");
  errors.clear();
  rows.clear();
  shortline.feed("time_s,axis,iu_a,iv_a,iw_a,speed_rad_s,rotor_angle_rad\n0,x,1,-0.5,-0.5,3\n",
                 rows, errors, false);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].text(), "line 2: missing column rotor_angle_rad (the line has 6 fields, "
                              "the header 7)");
}

}  // namespace
}  // namespace cutdyn

namespace cutdyn {
namespace {

TEST(MonitorCsvComments, LeadingKeyValueCommentsAreReadAndExposed) {
  // `cutdyn drive --currents` writes one line per axis before the header; unknown keys are
  // kept (and ignored by the monitor), free text without '=' is skipped.
  CurrentCsvParser p("d.csv");
  std::vector<CurrentRow> rows;
  std::vector<CsvLineError> errors;
  p.feed("# written by a logger\n"
         "# axis = x, measure = space-vector, torque_constant_nm_per_a = 1.25, pole_pairs = 4\n"
         "#axis=y,measure=rms,colour = blue\n"
         "time_s,axis,iu_a,iv_a,iw_a,speed_rad_s\n0,x,1,-0.5,-0.5,3\n",
         rows, errors, true);
  p.finish(rows, errors, true);
  ASSERT_EQ(p.comments().size(), 2u);
  EXPECT_EQ(p.comments()[0].line, 2u);
  EXPECT_EQ(*p.comments()[0].find("pole_pairs"), "4");
  EXPECT_EQ(*p.comments()[1].find("colour"), "blue");
  EXPECT_EQ(p.recorded_measure("x")->first, CurrentMeasure::kSpaceVector);
  EXPECT_EQ(p.recorded_measure("y")->first, CurrentMeasure::kRms);
  EXPECT_EQ(p.recorded_measure("y")->second, 3u);
  EXPECT_FALSE(p.recorded_measure("z"));
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].line, 5u);
  // A comment without an axis key is for every axis.
  CurrentCsvParser all("e.csv");
  all.feed("# measure = rms\ntime_s,axis,iu_a,iv_a,iw_a,speed_rad_s\n0,z,1,-0.5,-0.5,3\n", rows,
           errors, true);
  EXPECT_EQ(all.recorded_measure("z")->first, CurrentMeasure::kRms);
}

TEST(MonitorCsvComments, MalformedCommentIsAnErrorNamingTheLine) {
  EXPECT_EQ(problem_of("# axis = x\n# axis = y, measure\ntime_s\n"),
            "line 2: comment item \"measure\": no '=' (a comment before the header is `# key = "
            "value, key = value, ...`)");
  EXPECT_EQ(problem_of("# axis = , measure = rms\n"),
            "line 1: comment item \"axis =\": empty value (a comment before the header is `# key "
            "= value, key = value, ...`)");
  EXPECT_EQ(problem_of("# axis = x, measure = peak\ntime_s\n"),
            "line 1: measure = \"peak\": must be rms or space-vector");
}

}  // namespace
}  // namespace cutdyn

namespace cutdyn {
namespace {

// A line with more fields than the header (two lines run together) is a bad line, not a good
// one whose time stands for the axis': in a 20 000-line stream with one such line far ahead in
// time, only that line is skipped, and every good line after it is read.
TEST(MonitorCsv, ALineWithMoreFieldsThanTheHeaderDoesNotPoisonTheRest) {
  std::string text = "time_s,axis,iu_a,iv_a,iw_a,speed_rad_s\n";
  for (int i = 0; i < 20000; ++i) {
    text += std::to_string(i * 1e-3) + ",x,1,2,3,4\n";
    if (i == 10000) text += "14.5,x,1,2,3,4,99.0,x\n";  // 14.5 s: 5 500 lines ahead
  }
  const Parsed r = parse(text, false);
  EXPECT_EQ(r.rows.size(), 20000u);
  ASSERT_EQ(r.errors.size(), 1u);
  EXPECT_EQ(r.errors[0].line, 10003u);
  EXPECT_EQ(r.errors[0].what, "the line has 8 fields, the header 6");
}

}  // namespace
}  // namespace cutdyn
