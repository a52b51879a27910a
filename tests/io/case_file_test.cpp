#include "cutdyn/io/case_file.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn::io {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

// The table-2 structure of [Chikishev2018]: 228.8 Hz, 2.26e8 N/m, zeta = 0.01.
constexpr const char* kMinimal = R"(
process = "turning"
[[modes]]
direction = "x"
natural_hz = 228.8
damping_ratio = 0.01
stiffness_n_per_m = 2.26e8
)";

// Parses `text`, expects it to fail, and returns the problems (where() must be "test.toml").
std::vector<std::string> problems_of(const std::string& text) {
  try {
    parse_case(text, "test.toml");
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where(), "test.toml");
    return e.problems();
  }
  ADD_FAILURE() << "expected InvalidInput for:\n" << text;
  return {};
}

// kMinimal plus `extra` appended.
std::string with(const std::string& extra) { return std::string(kMinimal) + extra; }

// The same structure as a milling case, plus `extra`.
std::string milling_with(const std::string& extra) {
  std::string text = with(extra);
  text.replace(text.find("turning"), 7, "milling");
  return text;
}

void expect_table2_mode(const Case& c) {
  ASSERT_EQ(c.modal.modes.size(), 1u);
  const Mode& m = c.modal.modes[0];
  EXPECT_EQ(m.direction, Direction::kX);
  EXPECT_NEAR(m.natural_rad_s, 2.0 * units::kPi * 228.8, 1e-9 * 2.0 * units::kPi * 228.8);
  EXPECT_DOUBLE_EQ(m.damping_ratio, 0.01);
  EXPECT_DOUBLE_EQ(m.stiffness_n_per_m, 2.26e8);
}

// ---- the built-in examples ------------------------------------------------------------

TEST(CaseFileExamples, ListIsSortedAndEveryExampleLoads) {
  const auto& list = examples();
  ASSERT_GE(list.size(), 4u);
  EXPECT_TRUE(std::is_sorted(list.begin(), list.end(),
                             [](const auto& a, const auto& b) { return a.first < b.first; }));
  for (const auto& [name, text] : list) {
    SCOPED_TRACE(std::string(name));
    EXPECT_EQ(example_text(name), text);
    const Case c = load_example(name);
    EXPECT_EQ(c.source, "example " + std::string(name));
    if (name == "bore-plan") {  // a plan case: no modes
      EXPECT_EQ(c.process, Process::kBoreMilling);
      ASSERT_TRUE(c.bore.has_value());
      EXPECT_TRUE(c.bore->validate().empty());
      continue;
    }
    EXPECT_TRUE(c.modal.validate().empty());
    if (name.rfind("milling", 0) == 0 || name.rfind("ermolaev2020", 0) == 0) {
      EXPECT_EQ(c.process, Process::kMilling);
      ASSERT_TRUE(c.tool.has_value());
    } else {
      EXPECT_EQ(c.process, Process::kTurning);
      expect_table2_mode(c);
    }
  }
}

TEST(CaseFileExamples, TurningConventionalIsTable2InSi) {
  const Case c = load_example("turning-conventional");
  expect_table2_mode(c);
  ASSERT_TRUE(c.cutting.kf_pa);
  EXPECT_DOUBLE_EQ(*c.cutting.kf_pa, 850e6);
  ASSERT_TRUE(c.cutting.uncut_chip_thickness_m);
  EXPECT_DOUBLE_EQ(*c.cutting.uncut_chip_thickness_m, 0.05e-3);
  EXPECT_FALSE(c.cutting.kc_pa);
  EXPECT_FALSE(c.vibration);
  EXPECT_FALSE(c.tool);
  EXPECT_FALSE(c.operation);
  EXPECT_DOUBLE_EQ(c.lobes.grid.rpm_min, 500.0);
  EXPECT_DOUBLE_EQ(c.lobes.grid.rpm_max, 5000.0);
  EXPECT_EQ(c.lobes.grid.rpm_steps, 200);
  EXPECT_DOUBLE_EQ(c.lobes.depth_max_m, 0.03);
  EXPECT_EQ(c.lobes.method, StabilityMethod::kAuto);
  ASSERT_TRUE(c.simulate.rpm);
  EXPECT_DOUBLE_EQ(*c.simulate.rpm, 1400.0);
  ASSERT_TRUE(c.simulate.depth_m);
  EXPECT_DOUBLE_EQ(*c.simulate.depth_m, 6e-3);
  EXPECT_DOUBLE_EQ(c.simulate.duration_s, 2.0);
  EXPECT_DOUBLE_EQ(c.simulate.initial_displacement_m, 1e-6);  // default
}

TEST(CaseFileExamples, UltrasonicCasesCarryTheirVibration) {
  const Case fixed = load_example("turning-ultrasonic");
  ASSERT_TRUE(fixed.vibration);
  EXPECT_DOUBLE_EQ(fixed.vibration->frequency_hz, 20000.0);
  ASSERT_TRUE(fixed.vibration->duty_cycle);
  EXPECT_DOUBLE_EQ(*fixed.vibration->duty_cycle, 0.6);
  EXPECT_FALSE(fixed.vibration->amplitude_m);
  EXPECT_FALSE(fixed.vibration->workpiece_diameter_m);
  EXPECT_DOUBLE_EQ(fixed.lobes.depth_max_m, 0.03);

  const Case speed = load_example("turning-ultrasonic-speed");
  ASSERT_TRUE(speed.vibration);
  ASSERT_TRUE(speed.vibration->amplitude_m);
  EXPECT_DOUBLE_EQ(*speed.vibration->amplitude_m, 20e-6);
  ASSERT_TRUE(speed.vibration->workpiece_diameter_m);
  EXPECT_DOUBLE_EQ(*speed.vibration->workpiece_diameter_m, 0.04);
  EXPECT_FALSE(speed.vibration->duty_cycle);
  EXPECT_DOUBLE_EQ(speed.lobes.grid.rpm_min, 200.0);
  EXPECT_DOUBLE_EQ(speed.lobes.depth_max_m, 0.04);

  const Case force = load_example("ultrasonic-force");
  EXPECT_DOUBLE_EQ(*force.cutting.kc_pa, 2100e6);
  EXPECT_DOUBLE_EQ(*force.cutting.kf_pa, 1200e6);
  EXPECT_DOUBLE_EQ(*force.cutting.speed_m_per_s, 1.0);  // 60 m/min
  EXPECT_DOUBLE_EQ(*force.cutting.uncut_chip_thickness_m, 0.15e-3);
  EXPECT_DOUBLE_EQ(*force.cutting.width_m, 0.2e-3);
  EXPECT_DOUBLE_EQ(*force.vibration->amplitude_m, 20e-6);
  // No [lobes] or [simulate]: the defaults.
  EXPECT_DOUBLE_EQ(force.lobes.grid.rpm_max, 5000.0);
  EXPECT_EQ(force.lobes.grid.rpm_steps, 200);
  EXPECT_DOUBLE_EQ(force.simulate.duration_s, 1.0);
  EXPECT_FALSE(force.simulate.rpm);
}

TEST(CaseFileExamples, UnknownExampleListsTheAvailableNames) {
  EXPECT_FALSE(example_text("nope"));
  try {
    load_example("nope");
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where(), "example nope");
    ASSERT_EQ(e.problems().size(), 1u);
    EXPECT_EQ(e.problems()[0],
              "no built-in example called \"nope\"; available: bore-plan, ermolaev2020, "
              "ermolaev2020-fig6a, ermolaev2020-fig6b, ermolaev2020-fig7, ermolaev2020-fig8, "
              "milling-insperger, milling-variable-pitch, oxley-aisi1045, turning-conventional, "
              "turning-ultrasonic, turning-ultrasonic-speed, ultrasonic-force, "
              "ultrasonic-force-aa5083");
  }
}

TEST(CaseFileExamples, EmbeddedTextMatchesTheFilesOnDisk) {
  for (const auto& [name, text] : examples()) {
    std::ifstream in(std::filesystem::path(CUTDYN_EXAMPLES_DIR) / (std::string(name) + ".toml"));
    ASSERT_TRUE(in) << name;
    const std::string disk((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(disk, text) << name;
  }
}

// ---- what a valid file gives ------------------------------------------------------------

TEST(CaseFileParse, ConvertsEveryKeyToSi) {
  const Case c = parse_case(R"(
process = "milling"
[[modes]]
direction = "x"
natural_hz = 500
damping_ratio = 0
mass_kg = 2                       # k = m (2 pi 500)^2
[[modes]]
direction = "y"
natural_hz = 922.0
damping_ratio = 0.039
stiffness_n_per_m = 1.2e7
[cutting]
kt_n_per_mm2 = 600
kr_n_per_mm2 = 0
kte_n_per_mm = 12.5
kre_n_per_mm = 0
[tool]
teeth = 2
diameter_mm = 20
helix_deg = 30
[operation]
radial_immersion = 0.5
direction = "up"
[lobes]
rpm_min = 5000
rpm_max = 25000
rpm_steps = 2
depth_max_mm = 10000
method = "full-discretization"
harmonics = 0
steps_per_period = 100000
[simulate]
rpm = 12000
depth_mm = 1.5
revolutions = 1e6
summary_revolutions = 0.5
)",
                            "m.toml");
  EXPECT_EQ(c.source, "m.toml");
  EXPECT_EQ(c.process, Process::kMilling);
  ASSERT_EQ(c.modal.modes.size(), 2u);
  const double w0 = units::hz_to_rad_per_s(500.0);
  EXPECT_DOUBLE_EQ(c.modal.modes[0].natural_rad_s, w0);
  EXPECT_DOUBLE_EQ(c.modal.modes[0].stiffness_n_per_m, 2.0 * w0 * w0);
  EXPECT_DOUBLE_EQ(c.modal.modes[0].mass_kg(), 2.0);
  EXPECT_DOUBLE_EQ(c.modal.modes[0].damping_ratio, 0.0);
  EXPECT_EQ(c.modal.modes[1].direction, Direction::kY);
  EXPECT_DOUBLE_EQ(c.modal.modes[1].stiffness_n_per_m, 1.2e7);
  EXPECT_DOUBLE_EQ(*c.cutting.kt_pa, 600e6);
  EXPECT_DOUBLE_EQ(*c.cutting.kr_pa, 0.0);
  EXPECT_DOUBLE_EQ(*c.cutting.kte_n_per_m, 12.5e3);
  EXPECT_DOUBLE_EQ(*c.cutting.kre_n_per_m, 0.0);
  ASSERT_TRUE(c.tool);
  EXPECT_EQ(c.tool->teeth, 2);
  EXPECT_DOUBLE_EQ(c.tool->diameter_m, 0.02);
  EXPECT_DOUBLE_EQ(c.tool->helix_rad, units::kPi / 6.0);
  ASSERT_TRUE(c.operation);
  EXPECT_DOUBLE_EQ(c.operation->engagement.radial_immersion, 0.5);
  EXPECT_FALSE(c.operation->engagement.down_milling);
  EXPECT_DOUBLE_EQ(c.lobes.grid.rpm_min, 5000.0);
  EXPECT_DOUBLE_EQ(c.lobes.grid.rpm_max, 25000.0);
  EXPECT_EQ(c.lobes.grid.rpm_steps, 2);
  EXPECT_DOUBLE_EQ(c.lobes.depth_max_m, 10.0);
  EXPECT_EQ(c.lobes.method, StabilityMethod::kFullDiscretization);
  EXPECT_EQ(c.lobes.harmonics, 0);
  EXPECT_EQ(c.lobes.steps_per_period, 100000);
  EXPECT_DOUBLE_EQ(*c.simulate.rpm, 12000.0);
  EXPECT_DOUBLE_EQ(*c.simulate.depth_m, 1.5e-3);
  EXPECT_DOUBLE_EQ(c.simulate.revolutions, 1e6);
  EXPECT_DOUBLE_EQ(c.simulate.summary_revolutions, 0.5);
}

TEST(CaseFileParse, OptionalTablesGetTheirDefaults) {
  const Case c = parse_case(milling_with(R"(
[tool]
teeth = 4
diameter_mm = 12
[operation]
)"),
                            "d.toml");
  EXPECT_DOUBLE_EQ(c.tool->helix_rad, 0.0);
  EXPECT_DOUBLE_EQ(c.operation->engagement.radial_immersion, 1.0);
  EXPECT_TRUE(c.operation->engagement.down_milling);
  EXPECT_FALSE(c.cutting.kt_pa);
  EXPECT_DOUBLE_EQ(c.lobes.grid.rpm_min, 500.0);
  EXPECT_DOUBLE_EQ(c.lobes.grid.rpm_max, 5000.0);
  EXPECT_DOUBLE_EQ(c.lobes.depth_max_m, 0.03);
  EXPECT_EQ(c.lobes.harmonics, 5);
  EXPECT_EQ(c.lobes.steps_per_period, 0);
}

TEST(CaseFileParse, EnumNames) {
  EXPECT_STREQ(to_string(Process::kTurning), "turning");
  EXPECT_STREQ(to_string(Process::kMilling), "milling");
  EXPECT_STREQ(to_string(StabilityMethod::kAuto), "auto");
  EXPECT_STREQ(to_string(StabilityMethod::kClosedForm), "closed-form");
  EXPECT_STREQ(to_string(StabilityMethod::kMultiFrequency), "multi-frequency");
  EXPECT_STREQ(to_string(StabilityMethod::kFullDiscretization), "full-discretization");
  EXPECT_STREQ(to_string(StabilityMethod::kZeroOrder), "zero-order");
  EXPECT_STREQ(to_string(StabilityMethod::kFullDiscretizationDense), "full-discretization-dense");
  for (const char* method : {"auto", "zero-order", "closed-form", "multi-frequency",
                             "full-discretization", "full-discretization-dense"}) {
    const Case c = parse_case(with(std::string("[lobes]\nmethod = \"") + method + "\"\n"), "t");
    EXPECT_STREQ(to_string(c.lobes.method), method);
  }
}

// ---- one test per kind of problem -------------------------------------------------------

TEST(CaseFileErrors, SyntaxErrorGivesLineAndColumn) {
  const auto p = problems_of("process = \"turning\"\n[[modes]]\nnatural_hz = = 3\n");
  ASSERT_EQ(p.size(), 1u);
  EXPECT_THAT(p[0], ::testing::StartsWith("line 3, column 14: "));
  const auto dup = problems_of(with("[lobes]\nrpm_min = 1\nrpm_min = 2\n"));
  ASSERT_EQ(dup.size(), 1u);
  EXPECT_THAT(dup[0], ::testing::StartsWith("line 10, column "));
  EXPECT_THAT(dup[0], HasSubstr("rpm_min"));
}

TEST(CaseFileErrors, MissingRequiredKeys) {
  // Neither process (turning by default) nor [[modes]] is required to read a case: each
  // command asks for what it uses (the stability and simulation jobs for the modes).
  const Case empty = parse_case("", "test.toml");
  EXPECT_EQ(empty.process, Process::kTurning);
  EXPECT_TRUE(empty.modal.modes.empty());
  EXPECT_THAT(problems_of(with("[[modes]]\ndirection = \"x\"\ndamping_ratio = 0.02\n"
                               "stiffness_n_per_m = 1e7\n")),
              ElementsAre("modes[1].natural_hz: missing (required)"));
  EXPECT_THAT(problems_of(with("[[modes]]\ndirection = \"x\"\nnatural_hz = 100\n"
                               "damping_ratio = 0.02\n")),
              ElementsAre("modes[1].stiffness_n_per_m: missing (required unless mass_kg is "
                          "given)"));
  EXPECT_THAT(
      problems_of(milling_with("[tool]\nhelix_deg = 30\n")),
      ElementsAre("tool.teeth: missing (required)", "tool.diameter_mm: missing (required)"));
  EXPECT_THAT(problems_of(with("[vibration]\nfrequency_hz = 20000\n")),
              ElementsAre("vibration.amplitude_um: missing (required unless duty_cycle is "
                          "given)"));
  EXPECT_THAT(problems_of(with("[vibration]\nduty_cycle = 0.5\n")),
              ElementsAre("vibration.frequency_hz: missing (required)"));
  EXPECT_THAT(problems_of("process = \"milling\"\nmodes = []\n"),
              ElementsAre("modes = []: must hold at least one mode"));
}

TEST(CaseFileErrors, WrongTypes) {
  EXPECT_THAT(problems_of(with("[cutting]\nkt_n_per_mm2 = \"850\"\n")),
              ElementsAre("cutting.kt_n_per_mm2 = \"850\": wrong type: expected a number, got a "
                          "string"));
  EXPECT_THAT(problems_of(with("[simulate]\nrpm = true\n")),
              ElementsAre("simulate.rpm = true: wrong type: expected a number, got a boolean"));
  EXPECT_THAT(problems_of(with("[lobes]\nrpm_steps = 2.5\n")),
              ElementsAre("lobes.rpm_steps = 2.5: wrong type: expected an integer, got a float"));
  EXPECT_THAT(problems_of(milling_with("[tool]\nteeth = 2.0\ndiameter_mm = 20\n")),
              ElementsAre("tool.teeth = 2.0: wrong type: expected an integer, got a float"));
  EXPECT_THAT(problems_of(with("[lobes]\nmethod = 3\n")),
              ElementsAre("lobes.method = 3: wrong type: expected a string, got an integer"));
  EXPECT_THAT(problems_of("lobes = 3\n" + std::string(kMinimal)),
              ElementsAre("lobes = 3: wrong type: expected a table ([lobes]), got an integer"));
  EXPECT_THAT(problems_of("process = \"turning\"\n[modes]\ndirection = \"x\"\n"),
              ElementsAre("modes: wrong type: expected an array of tables ([[modes]]), got a "
                          "table"));
  EXPECT_THAT(problems_of("process = \"turning\"\nmodes = [1]\n"),
              ElementsAre("modes[0] = 1: wrong type: expected a table, got an integer"));
  EXPECT_THAT(problems_of(with("[cutting]\nwidth_mm = [1, 2]\n")),
              ElementsAre("cutting.width_mm = [1, 2]: wrong type: expected a number, got an "
                          "array"));
}

TEST(CaseFileErrors, ValuesOutOfRange) {
  EXPECT_THAT(problems_of("process = \"turning\"\n[[modes]]\ndirection = \"x\"\n"
                          "natural_hz = 0\ndamping_ratio = 1.0\nmass_kg = -2.5\n"),
              ElementsAre("modes[0].natural_hz = 0: must be positive",
                          "modes[0].damping_ratio = 1.0: must be at least 0 and less than 1",
                          "modes[0].mass_kg = -2.5: must be positive"));
  EXPECT_THAT(problems_of(milling_with("[operation]\nradial_immersion = 0\n")),
              ElementsAre("operation.radial_immersion = 0: must be greater than 0 and at most 1"));
  EXPECT_THAT(
      problems_of(milling_with("[operation]\nradial_immersion = 1.01\ndirection = \"climb\"\n")),
      ElementsAre("operation.radial_immersion = 1.01: must be greater than 0 and at most 1",
                  "operation.direction = \"climb\": must be one of \"down\", \"up\""));
  EXPECT_THAT(problems_of(with("[lobes]\nrpm_steps = 100001\n")),
              ElementsAre("lobes.rpm_steps = 100001: must be an integer from 2 to 100000"));
  EXPECT_THAT(
      problems_of(with("[lobes]\nrpm_steps = 1\nharmonics = 101\nsteps_per_period = -1\n"
                       "depth_max_mm = 1e5\nmethod = \"fast\"\n")),
      ElementsAre(
          "lobes.rpm_steps = 1: must be an integer from 2 to 100000",
          "lobes.depth_max_mm = 1e5: must be greater than 0 and at most 10000",
          "lobes.method = \"fast\": must be one of \"auto\", \"zero-order\", \"closed-form\", "
          "\"multi-frequency\", \"full-discretization\", \"full-discretization-dense\"",
          "lobes.harmonics = 101: must be an integer from 0 to 100",
          "lobes.steps_per_period = -1: must be an integer from 0 to 100000"));
  EXPECT_THAT(problems_of(milling_with("[tool]\nteeth = 0\ndiameter_mm = 20\nhelix_deg = 90\n")),
              ElementsAre("tool.teeth = 0: must be an integer from 1 to 200",
                          "tool.helix_deg = 90: must be at least 0 and less than 90"));
  EXPECT_THAT(problems_of(with("[simulate]\nduration_s = 1000.5\ninitial_displacement_um = -1\n")),
              ElementsAre("simulate.duration_s = 1000.5: must be greater than 0 and at most 1000",
                          "simulate.initial_displacement_um = -1: must be positive"));
  EXPECT_THAT(problems_of(with("[cutting]\nkc_n_per_mm2 = 0\n")),
              ElementsAre("cutting.kc_n_per_mm2 = 0: must be positive"));
  EXPECT_THAT(problems_of(milling_with("[cutting]\nkr_n_per_mm2 = -0.5\n")),
              ElementsAre("cutting.kr_n_per_mm2 = -0.5: must be at least 0"));
  EXPECT_THAT(problems_of("process = \"drilling\"\n[[modes]]\ndirection = \"z\"\n"
                          "natural_hz = 1\ndamping_ratio = 0\nstiffness_n_per_m = 1\n"),
              ElementsAre("process = \"drilling\": must be one of \"turning\", \"milling\"",
                          "modes[0].direction = \"z\": must be one of \"x\", \"y\""));
}

TEST(CaseFileErrors, RpmMaxMustExceedRpmMin) {
  EXPECT_THAT(problems_of(with("[lobes]\nrpm_min = 5000\nrpm_max = 5000\n")),
              ElementsAre("lobes.rpm_max = 5000: must be greater than lobes.rpm_min = 5000"));
  EXPECT_THAT(problems_of(with("[lobes]\nrpm_max = 400\n")),
              ElementsAre("lobes.rpm_max = 400: must be greater than lobes.rpm_min = 500 "
                          "(default)"));
  EXPECT_THAT(problems_of(with("[lobes]\nrpm_min = 6e3\n")),
              ElementsAre("lobes.rpm_min = 6e3: must be less than lobes.rpm_max = 5000 "
                          "(default)"));
  // An invalid bound is reported once, not also as an inconsistency.
  EXPECT_THAT(
      problems_of(with("[lobes]\nrpm_min = -1\nrpm_max = -2\n")),
      ElementsAre("lobes.rpm_min = -1: must be positive", "lobes.rpm_max = -2: must be positive"));
}

TEST(CaseFileErrors, NanAndInfAreRejected) {
  EXPECT_THAT(problems_of(with("[cutting]\nkt_n_per_mm2 = nan\nwidth_mm = +inf\n"
                               "[simulate]\nrpm = -inf\n")),
              ElementsAre("cutting.kt_n_per_mm2 = nan: must be a finite number",
                          "cutting.width_mm = +inf: must be a finite number",
                          "simulate.rpm = -inf: must be a finite number"));
  EXPECT_THAT(problems_of(with("[lobes]\nrpm_steps = nan\n")),
              ElementsAre("lobes.rpm_steps = nan: wrong type: expected an integer, got a float"));
}

TEST(CaseFileErrors, InitialDisplacementMustBePositive) {
  // The disturbance whose growth decides chatter: zero was read and then refused by the
  // simulation with a message naming its internal field; now the key is named.
  const auto problems = problems_of(with("[simulate]\ninitial_displacement_um = 0\n"));
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].rfind("simulate.initial_displacement_um = 0: ", 0), 0u) << problems[0];
}

TEST(CaseFileErrors, UnknownKeysAndTables) {
  EXPECT_THAT(problems_of(with("[lobes]\nrpm_stepz = 200\n")),
              ElementsAre("lobes.rpm_stepz: unknown key (did you mean rpm_steps?)"));
  EXPECT_THAT(problems_of(with("[lobes]\ncolour = \"red\"\n")),
              ElementsAre("lobes.colour: unknown key"));
  EXPECT_THAT(problems_of(with("[lobez]\nrpm_min = 1\n")),
              ElementsAre("lobez: unknown table (did you mean lobes?)"));
  EXPECT_THAT(problems_of(with("[coolant]\ntype = \"flood\"\n")),
              ElementsAre("coolant: unknown table"));
  EXPECT_THAT(problems_of("Process = \"turning\"\n" + with("")),
              ElementsAre("Process: unknown key (did you mean process?)"));
  EXPECT_THAT(problems_of(with("natural_Hz = 3\n")),
              ElementsAre("modes[0].natural_Hz: unknown key (did you mean natural_hz?)"));
  EXPECT_THAT(problems_of(with("[simulate.extra]\na = 1\n")),
              ElementsAre("simulate.extra: unknown table"));
  EXPECT_THAT(problems_of(with("[cutting]\n\"kt n\" = 1\n")),
              ElementsAre("cutting.\"kt n\": unknown key"));
}

TEST(CaseFileErrors, StiffnessAndMassBothGiven) {
  EXPECT_THAT(problems_of(with("mass_kg = 3\n")),
              ElementsAre("modes[0].stiffness_n_per_m = 2.26e8 and modes[0].mass_kg = 3: give "
                          "either stiffness_n_per_m or mass_kg, not both"));
}

TEST(CaseFileErrors, DutyCycleAndWorkpieceDiameterBothGiven) {
  EXPECT_THAT(problems_of(with("[vibration]\nfrequency_hz = 20000\nduty_cycle = 0.6\n"
                               "workpiece_diameter_mm = 40\n")),
              ElementsAre("vibration.duty_cycle = 0.6 and vibration.workpiece_diameter_mm = 40: "
                          "give either duty_cycle (fixed) or workpiece_diameter_mm (duty cycle "
                          "from the cutting speed), not both"));
  EXPECT_THAT(problems_of(with("[vibration]\nfrequency_hz = 20000\nduty_cycle = 1.5\n")),
              ElementsAre("vibration.duty_cycle = 1.5: must be greater than 0 and at most 1"));
}

TEST(CaseFileErrors, TurningModesActInXOnly) {
  EXPECT_THAT(problems_of(with("[[modes]]\ndirection = 'y'\nnatural_hz = 300\n"
                               "damping_ratio = 0.02\nstiffness_n_per_m = 1e7\n")),
              ElementsAre("modes[1].direction = 'y': turning models the feed direction \"x\" "
                          "only"));
  // The same mode is fine in milling.
  std::string milling = with(
      "[[modes]]\ndirection = 'y'\nnatural_hz = 300\n"
      "damping_ratio = 0.02\nstiffness_n_per_m = 1e7\n");
  milling.replace(milling.find("turning"), 7, "milling");
  EXPECT_EQ(parse_case(milling, "t").modal.count(Direction::kY), 1);
}

TEST(CaseFileErrors, EveryProblemInAFileIsReported) {
  const auto p = problems_of(R"(
process = "turning"
[[modes]]
direction = "y"
natural_hz = -228.8
damping_ratio = 1.5
[cutting]
kt_n_per_mm2 = "850"
[vibration]
frequency_hz = 0
[lobes]
rpm_min = 5000
rpm_max = 500
rpm_stepz = 10
[extra]
)");
  EXPECT_THAT(
      p, ElementsAre("modes[0].natural_hz = -228.8: must be positive",
                     "modes[0].damping_ratio = 1.5: must be at least 0 and less than 1",
                     "modes[0].stiffness_n_per_m: missing (required unless mass_kg is given)",
                     "modes[0].direction = \"y\": turning models the feed direction \"x\" only",
                     "cutting.kt_n_per_mm2 = \"850\": wrong type: expected a number, got a string",
                     "vibration.frequency_hz = 0: must be positive",
                     "vibration.amplitude_um: missing (required unless duty_cycle is given)",
                     "lobes.rpm_max = 500: must be greater than lobes.rpm_min = 5000",
                     "lobes.rpm_stepz: unknown key (did you mean rpm_steps?)",
                     "extra: unknown table"));
  EXPECT_EQ(p.size(), 10u);
}

TEST(CaseFileErrors, ValuesAreQuotedAsWritten) {
  // Underscores, exponents, hex and literal strings are echoed exactly, in the user's unit.
  EXPECT_THAT(
      problems_of(with("[lobes]\ndepth_max_mm = 1_000_0.5\nrpm_steps = 0x186A1\n"
                       "method = 'Auto'   # comment\n")),
      ElementsAre(
          "lobes.rpm_steps = 0x186A1: must be an integer from 2 to 100000",
          "lobes.depth_max_mm = 1_000_0.5: must be greater than 0 and at most "
          "10000",
          "lobes.method = 'Auto': must be one of \"auto\", \"zero-order\", \"closed-form\", "
          "\"multi-frequency\", \"full-discretization\", \"full-discretization-dense\""));
  EXPECT_THAT(problems_of(milling_with("[operation]\ndirection = \"é-down\"\n")),
              ElementsAre("operation.direction = \"é-down\": must be one of \"down\", \"up\""));
}

TEST(CaseFileErrors, MessageNamesTheFile) {
  try {
    parse_case(with("[lobes]\nrpm_min = 0\n"), "cases/a.toml");
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where(), "cases/a.toml");
    EXPECT_STREQ(e.what(), "cases/a.toml: lobes.rpm_min = 0: must be positive");
  }
}

// ---- files -------------------------------------------------------------------------------

TEST(CaseFileLoad, ReadsAFileAndNamesItAsSource) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("cutdyn_case_file_test_" +
                     std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + ".toml");
  {
    std::ofstream out(path);
    out << kMinimal;
  }
  const Case c = load_case_file(path);
  std::filesystem::remove(path);
  EXPECT_EQ(c.source, path.string());
  expect_table2_mode(c);
}

TEST(CaseFileLoad, MissingFileOrFolderCannotBeRead) {
  const std::filesystem::path missing = "/nonexistent/cutdyn/case.toml";
  try {
    load_case_file(missing);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where(), missing.string());
    EXPECT_THAT(e.problems(), ElementsAre("cannot read the file: No such file or directory"));
  }
  try {
    load_case_file(std::filesystem::temp_directory_path());
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_THAT(e.problems(), ElementsAre("cannot read the file: Is a directory"));
  }
}

// ---- JSON --------------------------------------------------------------------------------

TEST(CaseFileJson, EchoesTheFileInItsOwnKeysAndUnits) {
  const nlohmann::json j = to_json(load_example("turning-ultrasonic-speed"));
  EXPECT_EQ(j["process"], "turning");
  ASSERT_EQ(j["modes"].size(), 1u);
  EXPECT_EQ(j["modes"][0]["direction"], "x");
  EXPECT_EQ(j["modes"][0]["natural_hz"].get<double>(), 228.8);
  EXPECT_EQ(j["modes"][0]["damping_ratio"].get<double>(), 0.01);
  EXPECT_EQ(j["modes"][0]["stiffness_n_per_m"].get<double>(), 2.26e8);
  EXPECT_EQ(j["cutting"],
            (nlohmann::json{{"kf_n_per_mm2", 850}, {"uncut_chip_thickness_mm", 0.05}}));
  EXPECT_EQ(j["vibration"],
            (nlohmann::json{
                {"frequency_hz", 20000}, {"amplitude_um", 20}, {"workpiece_diameter_mm", 40}}));
  EXPECT_EQ(j["lobes"], (nlohmann::json{{"rpm_min", 200},
                                        {"rpm_max", 2000},
                                        {"rpm_steps", 200},
                                        {"depth_max_mm", 40},
                                        {"method", "auto"},
                                        {"harmonics", 5},
                                        {"steps_per_period", 0},
                                        {"refine", true}}));
  EXPECT_EQ(
      j["simulate"],
      (nlohmann::json{
          {"rpm", 600}, {"depth_mm", 10}, {"duration_s", 2}, {"initial_displacement_um", 1}}));
  EXPECT_FALSE(j.contains("tool"));
  EXPECT_FALSE(j.contains("operation"));
}

// ---- [material] and [oxley] -------------------------------------------------------------

TEST(CaseFileMaterial, ALibraryNameWithOverridesAndOwnTables) {
  // A library entry.
  const Case lib = parse_case(with("[material]\nname = \"aisi 1045\"\n"), "a.toml");
  ASSERT_TRUE(lib.material.has_value());
  const WorkMaterial& entry = *find_material("AISI1045");
  EXPECT_EQ(lib.material->reference, entry.reference);  // the library's, not "given in the case"
  EXPECT_EQ(lib.material->flow.a_pa, entry.flow.a_pa);
  EXPECT_EQ(lib.material->flow.c, entry.flow.c);
  EXPECT_EQ(lib.material->thermal.density_kg_per_m3, entry.thermal.density_kg_per_m3);
  // The entry with one value overridden, the rest kept.
  const Case over = parse_case(
      with("[material]\nname = \"AISI1045\"\n[material.johnson_cook]\nc = 0.02\n"), "b.toml");
  EXPECT_NE(entry.flow.c, 0.02);
  EXPECT_EQ(over.material->flow.c, 0.02);
  EXPECT_EQ(over.material->flow.b_pa, 600.8e6);
  // A material of one's own: every required key, SI inside.
  const Case own = parse_case(with(R"([material]
name = "my steel"
[material.johnson_cook]
a_mpa = 500
b_mpa = 400
n = 0.3
c = 0.01
m = 1.1
reference_strain_rate_per_s = 0.001
melting_temperature_c = 1450
[material.thermal]
density_kg_per_m3 = 7800
specific_heat_j_per_kg_k = 450
conductivity_w_per_m_k = 40
conductivity_slope_w_per_m_k2 = -0.01
[cutting]
rake_deg = -5
workpiece_temperature_c = 300
[oxley]
c0_min = 1.5
delta_max = 0.3
)"),
                              "c.toml");
  const WorkMaterial& m = *own.material;
  EXPECT_EQ(m.reference, "given in the case");
  EXPECT_EQ(m.name, "my steel");
  EXPECT_EQ(m.flow.a_pa, 500e6);
  EXPECT_EQ(m.flow.reference_strain_rate_per_s, 0.001);
  EXPECT_EQ(m.flow.reference_temperature_c, 20.0);  // the default
  EXPECT_EQ(m.thermal.conductivity_slope_w_per_m_k2, -0.01);
  EXPECT_EQ(m.thermal.specific_heat_slope_j_per_kg_k2, 0.0);
  EXPECT_NEAR(*own.cutting.rake_rad, units::deg_to_rad(-5.0), 1e-15);
  EXPECT_EQ(*own.cutting.workpiece_temperature_c, 300.0);
  EXPECT_EQ(own.oxley.c0_min, 1.5);
  EXPECT_EQ(own.oxley.delta_max, 0.3);
  EXPECT_EQ(own.oxley.c0_max, OxleyOptions{}.c0_max);
  // to_json gives the material in full; read back, the same case.
  const nlohmann::json j = to_json(own);
  std::string again = with("[cutting]\nrake_deg = -5\nworkpiece_temperature_c = 300\n");
  again += "[material]\nname = " + j["material"]["name"].dump() + "\n";
  for (const char* table : {"johnson_cook", "thermal"}) {
    again += std::string("[material.") + table + "]\n";
    for (const auto& [key, value] : j["material"][table].items())
      again += key + " = " + value.dump() + "\n";
  }
  again += "[oxley]\n";
  for (const auto& [key, value] : j["oxley"].items()) again += key + " = " + value.dump() + "\n";
  EXPECT_EQ(to_json(parse_case(again, "d.toml")), j);
}

TEST(CaseFileMaterial, ProblemsAreNamed) {
  EXPECT_THAT(problems_of(with("[material]\nname = \"steel\"\n")),
              ElementsAre(::testing::StartsWith(
                  "material.name = \"steel\": is not in the material library (AISI1045, ")));
  EXPECT_THAT(problems_of(with("[material]\n[material.johnson_cook]\na_mpa = 1\n")),
              ElementsAre("material.name: missing (give a library material, or both "
                          "[material.johnson_cook] and [material.thermal])"));
  // Own tables without a library name: every required key.
  const auto missing =
      problems_of(with("[material]\nname = \"x\"\n[material.johnson_cook]\na_mpa = 500\nb_mpa = 1\n"
                       "n = 0.2\nc = 0\nm = 1\n[material.thermal]\ndensity_kg_per_m3 = 7800\n"));
  EXPECT_THAT(missing,
              ElementsAre("material.johnson_cook.melting_temperature_c: missing (required)",
                          "material.thermal.specific_heat_j_per_kg_k: missing (required)",
                          "material.thermal.conductivity_w_per_m_k: missing (required)"));
  // What only the whole material shows.
  EXPECT_THAT(problems_of(with("[material]\nname = \"AISI1045\"\n[material.johnson_cook]\n"
                               "melting_temperature_c = 10\n")),
              ElementsAre(::testing::StartsWith(
                  "material.johnson_cook.melting_temperature_c = 10 °C: must be above")));
  EXPECT_THAT(problems_of(with("[material]\nname = \"AISI1045\"\n[material.johnson_cook]\n"
                               "n = 1.5\nhardness = 3\n")),
              ElementsAre("material.johnson_cook.n = 1.5: must be at least 0 and less than 1",
                          "material.johnson_cook.hardness: unknown key"));
  // Coefficients and a material together; a material for milling.
  EXPECT_THAT(problems_of(with("[material]\nname = \"AISI1045\"\n[cutting]\nkt_n_per_mm2 = 900\n")),
              ElementsAre("cutting.kt_n_per_mm2 and [material]: give the force coefficients or "
                          "the material to predict them from, not both"));
  EXPECT_THAT(problems_of(with("[material]\nname = \"AISI1045\"\n[cutting]\nrake_deg = 50\n")),
              ElementsAre("cutting.rake_deg = 50: must be greater than -45 and less than 45"));
  EXPECT_THAT(
      problems_of(with("[material]\nname = \"AISI1045\"\n[oxley]\nc0_min = 5\nc0_max = 4\n")),
      ElementsAre("oxley.c0_min = 5 and oxley.c0_max = 4: c0_min must be less than "
                  "c0_max"));
}

// ---- which process takes which key (docs/case-files.md) ---------------------------------

// A key the case's process does not use would be ignored without a word (kc_n_per_mm2 in a
// milling case ran with Kr = 0): it is an error naming the key, the value as written and the
// keys the process takes, and it is the key's only problem (its range is not checked too).
TEST(CaseFileProcessKeys, KeysTheProcessDoesNotUseAreErrors) {
  EXPECT_THAT(problems_of(milling_with("[cutting]\nkt_n_per_mm2 = 600\nkc_n_per_mm2 = 1500\n")),
              ElementsAre("cutting.kc_n_per_mm2 = 1500: not used in a milling case (milling takes "
                          "kt_n_per_mm2, kr_n_per_mm2, kte_n_per_mm, kre_n_per_mm)"));
  EXPECT_THAT(problems_of(milling_with("[cutting]\nkt_n_per_mm2 = 600\nspeed_m_per_min = -1\n"
                                       "width_mm = 2\n")),
              ElementsAre(HasSubstr("cutting.speed_m_per_min = -1: not used in a milling case"),
                          HasSubstr("cutting.width_mm = 2: not used in a milling case")));
  EXPECT_THAT(problems_of(with("[cutting]\nkt_n_per_mm2 = 850\nkr_n_per_mm2 = 200\n")),
              ElementsAre("cutting.kr_n_per_mm2 = 200: not used in a turning case (turning takes "
                          "kf_n_per_mm2, kc_n_per_mm2, speed_m_per_min, uncut_chip_thickness_mm, "
                          "width_mm, rake_deg, workpiece_temperature_c)"));
  EXPECT_THAT(problems_of(with("[cutting]\nkte_n_per_mm = 5\n")),
              ElementsAre(HasSubstr("cutting.kte_n_per_mm = 5: not used in a turning case")));
  // Tables of the other process.
  EXPECT_THAT(problems_of(milling_with("[vibration]\nfrequency_hz = 20000\nduty_cycle = 0.6\n")),
              ElementsAre("vibration: not used in a milling case (vibration-assisted cutting is "
                          "modelled for turning)"));
  EXPECT_THAT(
      problems_of(with("[tool]\nteeth = 2\ndiameter_mm = 20\n[operation]\n"
                       "[force_law]\nc_n_per_mm = 25\n")),
      ElementsAre("tool: not used in a turning case (tool is a milling table: tool, operation, "
                  "force_law)",
                  "operation: not used in a turning case (operation is a milling table: tool, "
                  "operation, force_law)",
                  "force_law: not used in a turning case (force_law is a milling table: tool, "
                  "operation, force_law)"));
  EXPECT_THAT(problems_of(with("[[drives]]\naxis = \"x\"\ntransmission = \"lever\"\n")),
              ElementsAre(HasSubstr("drives: not used in a turning case")));
  // [simulate]: a milling run is set by revolutions, a turning run by its duration.
  EXPECT_THAT(problems_of(milling_with("[simulate]\nduration_s = 2\n")),
              ElementsAre("simulate.duration_s = 2: not used in a milling case (milling takes "
                          "rpm, depth_mm, revolutions, summary_revolutions, regenerative, "
                          "steps_per_tooth, slices, closed_form_helix; --duration-s on the "
                          "command line sets revolutions)"));
  EXPECT_THAT(problems_of(with("[simulate]\nrevolutions = 10\nregenerative = false\n")),
              ElementsAre(HasSubstr("simulate.regenerative = false: not used in a turning case"),
                          HasSubstr("simulate.revolutions = 10: not used in a turning case")));
  // Keys that one model of the process reads only.
  EXPECT_THAT(problems_of(with("[cutting]\nkt_n_per_mm2 = 850\nrake_deg = -5\n")),
              ElementsAre("cutting.rake_deg = -5: used only with a [material] (Oxley's theory "
                          "predicts the force coefficients from it)"));
  EXPECT_THAT(problems_of(with("[oxley]\neta = 0.8\n")),
              ElementsAre("oxley: used only with a [material] (the settings of Oxley's theory)"));
  EXPECT_THAT(problems_of(milling_with("[force_law]\nc_n_per_mm = 25\n[cutting]\n"
                                       "kt_n_per_mm2 = 600\nkre_n_per_mm = 3\n")),
              ElementsAre(HasSubstr("cutting.kre_n_per_mm = 3: not used with [force_law]")));
  // Unknown to every process: still "unknown key" with its suggestion.
  EXPECT_THAT(problems_of(milling_with("[cutting]\nkc_n_per_mm = 1\n")),
              ElementsAre("cutting.kc_n_per_mm: unknown key (did you mean kc_n_per_mm2?)"));
  // What each process does take loads (the values reach the case).
  const Case m = parse_case(milling_with("[cutting]\nkt_n_per_mm2 = 600\nkr_n_per_mm2 = 200\n"
                                         "kte_n_per_mm = 5\nkre_n_per_mm = 3\n"),
                            "m.toml");
  EXPECT_DOUBLE_EQ(*m.cutting.kr_pa, 200e6);
  EXPECT_DOUBLE_EQ(*m.cutting.kre_n_per_m, 3e3);
  const Case t = parse_case(with("[cutting]\nkt_n_per_mm2 = 850\nkc_n_per_mm2 = 2100\n"), "t");
  EXPECT_DOUBLE_EQ(*t.cutting.kc_pa, 2100e6);
}

// with_value (the sweeps) reads the case again with the same rule.
TEST(CaseFileProcessKeys, SweepOfAKeyTheProcessDoesNotUseIsAnError) {
  const Case c = load_example("milling-insperger");
  try {
    with_value(c, "cutting.kc_n_per_mm2", 1500.0);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_THAT(e.problems(), ElementsAre(HasSubstr("cutting.kc_n_per_mm2 = 1500: not used in a "
                                                    "milling case")));
  }
}

// [[drives]] seed: the current noise's seed, with the motor; each axis gets its own stream.
TEST(CaseFileDrives, SeedOfTheCurrentNoise) {
  const std::string motor =
      "[[drives]]\naxis = \"x\"\ntransmission = \"lever\"\n"
      "output_diameter_mm = 40\nstiffness_nm_s_per_rad = -100\n"
      "pole_pairs = 4\ntorque_constant_nm_per_a = 1.5\n";
  const std::string second =
      "[[drives]]\naxis = \"y\"\ntransmission = \"lever\"\n"
      "output_diameter_mm = 40\nstiffness_nm_s_per_rad = -100\n"
      "pole_pairs = 4\ntorque_constant_nm_per_a = 1.5\n";
  const Case c = parse_case(milling_with(motor + "seed = 42\n" + second), "s.toml");
  ASSERT_EQ(c.drives.size(), 2u);
  EXPECT_EQ(c.drives[0].motor->seed, 42u);
  EXPECT_EQ(c.drives[1].motor->seed, 1u);  // the default
  EXPECT_EQ(c.drives[0].motor->stream, 0u);
  EXPECT_EQ(c.drives[1].motor->stream, 1u);
  EXPECT_EQ(to_json(c)["drives"][0]["seed"], 42);
  EXPECT_THAT(problems_of(milling_with(motor + "seed = -1\n")),
              ElementsAre("drives[0].seed = -1: must be an integer from 0 to 2147483647"));
  EXPECT_THAT(problems_of(milling_with(motor + "seed = 1.5\n")),
              ElementsAre(HasSubstr("drives[0].seed = 1.5: wrong type: expected an integer")));
  std::string no_motor = motor;
  no_motor.erase(no_motor.find("pole_pairs"));
  EXPECT_THAT(problems_of(milling_with(no_motor + "seed = 3\n")),
              ElementsAre(HasSubstr("drives[0].seed")));
}

// The accuracy coefficient k of a plan case: the source's range 0.005 (finishing) … 0.1
// (roughing).
TEST(CaseFilePlan, AccuracyCoefficientInTheSourcesRange) {
  std::string text(*example_text("bore-plan"));
  const auto with_k = [&](const std::string& k) {
    std::string t = text;
    t.replace(t.find("accuracy_coefficient = 0.05"), 27, "accuracy_coefficient = " + k);
    return t;
  };
  for (const char* k : {"0.5", "0.004", "0.1001"})
    EXPECT_THAT(problems_of(with_k(k)),
                ElementsAre("process.accuracy_coefficient = " + std::string(k) +
                            ": must be from 0.005 (finishing) to 0.1 (roughing), the source's "
                            "range of k"));
  EXPECT_DOUBLE_EQ(parse_case(with_k("0.005"), "p").bore->accuracy_coefficient, 0.005);
  EXPECT_DOUBLE_EQ(parse_case(with_k("0.1"), "p").bore->accuracy_coefficient, 0.1);
}

TEST(CaseFileJson, RoundTripsThroughToml) {
  const std::string text = R"(
process = "milling"
[[modes]]
direction = "y"
natural_hz = 922.5
damping_ratio = 0.039
mass_kg = 0.03993
[cutting]
kt_n_per_mm2 = 644.5
kr_n_per_mm2 = 236.3
kte_n_per_mm = 18.7
[tool]
teeth = 2
diameter_mm = 19.05
helix_deg = 12.5
[operation]
radial_immersion = 0.05
direction = "up"
[lobes]
rpm_min = 5000.5
rpm_max = 25000
rpm_steps = 301
depth_max_mm = 7.5
method = "multi-frequency"
harmonics = 7
steps_per_period = 40
[simulate]
depth_mm = 0.33
revolutions = 12.5
regenerative = false
)";
  const Case first = parse_case(text, "a.toml");
  const nlohmann::json j = to_json(first);
  EXPECT_EQ(j["tool"], (nlohmann::json{{"teeth", 2}, {"diameter_mm", 19.05}, {"helix_deg", 12.5}}));
  EXPECT_EQ(j["operation"], (nlohmann::json{{"radial_immersion", 0.05}, {"direction", "up"}}));
  EXPECT_FALSE(j.contains("vibration"));
  EXPECT_EQ(j["cutting"]["kte_n_per_mm"].get<double>(), 18.7);
  // A milling case echoes the milling keys of [simulate] only (they read back).
  EXPECT_FALSE(j["simulate"].contains("duration_s"));
  EXPECT_FALSE(j["simulate"].contains("initial_displacement_um"));
  EXPECT_EQ(j["simulate"]["revolutions"].get<double>(), 12.5);
  EXPECT_EQ(j["lobes"]["rpm_min"].get<double>(), 5000.5);
  EXPECT_EQ(j["lobes"]["method"], "multi-frequency");
  EXPECT_EQ(j["simulate"]["depth_mm"].get<double>(), 0.33);
  EXPECT_FALSE(j["simulate"].contains("rpm"));
  EXPECT_EQ(j["modes"][0]["natural_hz"].get<double>(), 922.5);
  const double w = units::hz_to_rad_per_s(922.5);
  EXPECT_NEAR(j["modes"][0]["stiffness_n_per_m"].get<double>(), 0.03993 * w * w,
              1e-12 * 0.03993 * w * w);

  // Write the JSON back as TOML and load it again: the same case.
  std::string again = "process = \"milling\"\n";
  for (const auto& mode : j["modes"]) {
    again += "[[modes]]\n";
    for (const auto& [key, value] : mode.items()) again += key + " = " + value.dump() + "\n";
  }
  for (const char* table : {"cutting", "tool", "operation", "lobes", "simulate"}) {
    again += std::string("[") + table + "]\n";
    for (const auto& [key, value] : j[table].items()) again += key + " = " + value.dump() + "\n";
  }
  const Case second = parse_case(again, "b.toml");
  EXPECT_EQ(to_json(second), j);
  EXPECT_NEAR(second.modal.modes[0].stiffness_n_per_m, first.modal.modes[0].stiffness_n_per_m,
              1e-12 * first.modal.modes[0].stiffness_n_per_m);
  EXPECT_DOUBLE_EQ(second.tool->helix_rad, first.tool->helix_rad);
  EXPECT_DOUBLE_EQ(*second.cutting.kte_n_per_m, *first.cutting.kte_n_per_m);
  EXPECT_DOUBLE_EQ(second.lobes.depth_max_m, first.lobes.depth_max_m);
  EXPECT_DOUBLE_EQ(second.simulate.initial_displacement_m, first.simulate.initial_displacement_m);
}

}  // namespace
}  // namespace cutdyn::io

namespace cutdyn::io {
namespace {

TEST(CaseFileWithValue, SetsAKeyAndReadsTheCaseAgainWithEveryCheck) {
  const Case c = load_example("milling-insperger");
  const Case deeper = with_value(c, "simulate.depth_mm", 0.08);
  ASSERT_TRUE(deeper.simulate.depth_m.has_value());
  EXPECT_NEAR(*deeper.simulate.depth_m, 0.08e-3, 1e-18);
  EXPECT_EQ(deeper.source, "example milling-insperger with simulate.depth_mm = 0.08");
  EXPECT_EQ(deeper.tool->teeth, 2);  // the rest unchanged
  // A table that was absent is created; an integral value is written as an integer.
  const Case lawful = with_value(c, "force_law.c_n_per_mm", 25.0);
  ASSERT_TRUE(lawful.force_law.has_value());
  EXPECT_NEAR(lawful.force_law->c_n_per_m, 25e3, 1e-9);
  EXPECT_EQ(with_value(c, "tool.teeth", 4.0).tool->teeth, 4);
  // The loader's checks apply to the new value.
  EXPECT_THROW(with_value(c, "tool.teeth", 2.5), InvalidInput);
  EXPECT_THROW(with_value(c, "operation.radial_immersion", 1.5), InvalidInput);
  EXPECT_THROW(with_value(c, "process.x", 1.0), InvalidInput);  // not a table
  EXPECT_THROW(with_value(c, "a.b.c", 1.0), InvalidInput);
}

}  // namespace
}  // namespace cutdyn::io

namespace cutdyn::io {
namespace {

TEST(CaseFilePlan, AProcessTableMarksABoreMillingCase) {
  const Case c = load_example("bore-plan");
  ASSERT_TRUE(c.bore.has_value());
  EXPECT_NEAR(c.bore->bore_diameter_m, 0.5, 1e-15);
  EXPECT_NEAR(c.bore->cutting_speed_m_per_s, 2.0, 1e-15);  // 120 m/min
  EXPECT_NEAR(c.bore->lead_angle_rad, units::deg_to_rad(60.0), 1e-15);
  EXPECT_FALSE(c.axial_feed_m.has_value());
  // Round trip through the JSON echo's keys and units.
  const auto j = to_json(c);
  EXPECT_EQ(j["cutter"]["teeth"], 8);
  EXPECT_EQ(j["process"]["cutting_speed_m_per_min"], 120);
  // Every problem at once, named by key: a cutter as large as the bore, a missing knife
  // count, an unknown key, and no [bore] at all.
  try {
    parse_case(
        "[cutter]\ndiameter_mm = 600\noffset_mm = 1\nlead_angle_deg = 60\ncolour = 1\n"
        "[process]\ncutting_speed_m_per_min = 100\nmean_chip_thickness_mm = 0.1\n"
        "accuracy_coefficient = 0.05\n",
        "plan.toml");
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    const std::string all = e.what();
    EXPECT_NE(all.find("bore: missing"), std::string::npos) << all;
    EXPECT_NE(all.find("cutter.teeth: missing"), std::string::npos) << all;
    EXPECT_NE(all.find("cutter.colour"), std::string::npos) << all;
  }
}

TEST(CaseFile, ForceLawTakesT2InSecondsOrAsAnAngleNotBoth) {
  const Case angle =
      parse_case(milling_with("[force_law]\nc_n_per_mm = 25\nt2_deg = 72\n"), "test.toml");
  ASSERT_TRUE(angle.force_law && angle.force_law->t2_angle_rad);
  EXPECT_NEAR(*angle.force_law->t2_angle_rad, 0.4 * units::kPi, 1e-12);
  // T2 = ω·T2/ω: 0.2 s at 60 rpm, 0.02 s at 600 rpm.
  EXPECT_NEAR(angle.force_law->time_constant_s(units::rpm_to_rad_per_s(60.0)), 0.2, 1e-12);
  EXPECT_NEAR(angle.force_law->time_constant_s(units::rpm_to_rad_per_s(600.0)), 0.02, 1e-12);
  const auto p =
      problems_of(milling_with("[force_law]\nc_n_per_mm = 25\nt2_s = 0.2\nt2_deg = 72\n"));
  ASSERT_EQ(p.size(), 1u);
  EXPECT_THAT(p[0], HasSubstr("force_law.t2_s = 0.2 and force_law.t2_deg = 72"));
}

TEST(CaseFile, JsonCasesAreReadAsTheirToml) {
  // Every built-in example's effective case (the `case` object of --json) read back as JSON
  // gives the same case; rules and messages are the TOML reader's.
  for (const auto& [name, text] : examples()) {
    SCOPED_TRACE(std::string(name));
    const Case first = load_example(name);
    if (!first.frfs.empty()) continue;  // its FRF files are relative to the examples folder
    const nlohmann::json j = to_json(first);
    EXPECT_EQ(to_json(parse_case_json(j, "dict")), j);
  }
  nlohmann::json bad = to_json(load_example("milling-insperger"));
  bad["modes"][0]["natural_hz"] = -3;
  bad["tool"]["teeth"] = nullptr;  // absent: the key is required
  try {
    parse_case_json(bad, "dict");
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where(), "dict");
    const std::string all = ::testing::PrintToString(e.problems());
    EXPECT_THAT(all, HasSubstr("modes[0].natural_hz = -3"));
    EXPECT_THAT(all, HasSubstr("tool.teeth"));
  }
  EXPECT_THROW(parse_case_json(nlohmann::json::array(), "dict"), InvalidInput);
  nlohmann::json holed = to_json(load_example("milling-insperger"));
  holed["tool"]["pitch_deg"] = nlohmann::json::array({90, nullptr});
  try {
    parse_case_json(holed, "dict");
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_THAT(e.problems().at(0), HasSubstr("tool.pitch_deg[1] = null"));
  }
}

}  // namespace
}  // namespace cutdyn::io
