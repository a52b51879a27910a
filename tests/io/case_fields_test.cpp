// The field tables of the case file (src/io/case_fields.hpp): reading every section through
// them, the echo read back, unknown keys, ranges in the user's unit, sweeps of any number key
// (indexed ones too) and the old key name of the turning feed-direction coefficient.
#include "io/case_fields.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/io/case_file.hpp"

namespace cutdyn::io {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

// A turning case with every turning table and most of their keys.
constexpr const char* kFullTurning = R"(
process = "turning"
[[modes]]
direction = "x"
natural_hz = 228.8
damping_ratio = 0.01
stiffness_n_per_m = 2.26e8
[[modes]]
direction = "x"
natural_hz = 512.5
damping_ratio = 0.03
mass_kg = 2.5
[cutting]
speed_m_per_min = 200
uncut_chip_thickness_mm = 0.1
width_mm = 2
rake_deg = -5
workpiece_temperature_c = 25
[material]
name = "AISI1045"
[material.johnson_cook]
c = 0.02
reference_temperature_c = 22
[material.thermal]
conductivity_slope_w_per_m_k2 = -0.01
[oxley]
c0_min = 1.5
c0_max = 9
delta_min = 0.01
delta_max = 0.3
eta = 0.8
psi = 0.85
[vibration]
frequency_hz = 20000
amplitude_um = 15
workpiece_diameter_mm = 40
[lobes]
rpm_min = 300.5
rpm_max = 4000
rpm_steps = 150
depth_max_mm = 12.5
method = "multi-frequency"
harmonics = 7
steps_per_period = 40
refine = false
[simulate]
rpm = 1400
depth_mm = 0.5
duration_s = 0.25
initial_displacement_um = 2
)";

// Turning with given coefficients and a fixed duty cycle.
constexpr const char* kCoefficientTurning = R"(
process = "turning"
[[modes]]
direction = "x"
natural_hz = 228.8
damping_ratio = 0.01
stiffness_n_per_m = 2.26e8
[cutting]
kc_n_per_mm2 = 2100
kf_n_per_mm2 = 1200
speed_m_per_min = 60
uncut_chip_thickness_mm = 0.15
width_mm = 0.2
[vibration]
frequency_hz = 20000
duty_cycle = 0.6
)";

// A milling case with every milling table but [force_law] (which takes no edge forces).
constexpr const char* kFullMilling = R"(
process = "milling"
[[modes]]
direction = "x"
natural_hz = 922.5
damping_ratio = 0.039
stiffness_n_per_m = 1.34e6
[[modes]]
direction = "y"
natural_hz = 950
damping_ratio = 0.04
mass_kg = 0.04
residue_phase_deg = -12.5
[cutting]
kt_n_per_mm2 = 644.5
kr_n_per_mm2 = 236.3
kte_n_per_mm = 18.7
kre_n_per_mm = 5
[tool]
teeth = 4
diameter_mm = 19.05
helix_deg = 30
pitch_deg = [80, 100, 80, 100]
[operation]
radial_immersion = 0.5
direction = "up"
feed_per_tooth_mm = 0.05
entry_deg = 30
exit_deg = 120
[lobes]
rpm_min = 5000
rpm_max = 25000
[simulate]
rpm = 10000
depth_mm = 1
revolutions = 12.5
summary_revolutions = 3
regenerative = false
steps_per_tooth = 128
slices = 8
closed_form_helix = true
[[drives]]
axis = "x"
transmission = "lever"
output_diameter_mm = 40
ratio = 0.1
idle_torque_nm = 0.05
stiffness_nm_s_per_rad = -10000
pole_pairs = 4
torque_constant_nm_per_a = 1.5
current_measure = "rms"
current_noise_a = 0.01
current_offset_a = [0.1, 0, -0.1]
seed = 7
[[drives]]
direction = [0, 1, 1]
transmission = "ball-screw"
lead_mm = 10
efficiency = 0.9
gear_ratio = 2
idle_torque_nm = 0.1
model = "dynamic"
inertia_kg_m2 = 0.001
viscous_nm_s_per_rad = 0.01
kp_nm_s_per_rad = 0.5
ki_nm_per_rad = 10
torque_limit_nm = 20
)";

// The S1 force law.
constexpr const char* kForceLawMilling = R"(
process = "milling"
[[modes]]
direction = "y"
natural_hz = 922.5
damping_ratio = 0.039
stiffness_n_per_m = 1.34e6
[cutting]
kt_n_per_mm2 = 644.5
[tool]
teeth = 2
diameter_mm = 20
[force_law]
c_n_per_mm = 25
t2_s = 1e-4
p0_n = 10
t1_mm = 0.5
phi_rez_deg = 10
phi_skv_deg = -20
lag_input = "unwindowed"
)";

constexpr const char* kPlanWithFeed = R"(
[bore]
diameter_mm = 500
length_mm = 300
allowance_mm = 5
[cutter]
diameter_mm = 200
teeth = 8
offset_mm = 3.109375
lead_angle_deg = 60
inclination_deg = 5
[process]
cutting_speed_m_per_min = 120
mean_chip_thickness_mm = 0.2
accuracy_coefficient = 0.05
axial_feed_mm = 1.5
[limits]
offset_min_mm = 0
offset_max_mm = 40
cutting_speed_max_m_per_min = 150
cutter_rpm_max = 600
workpiece_rpm_max = 5
faceting_max_mm = 0.01
max_chip_thickness_mm = 1.5
)";

std::vector<std::string> problems_of(const std::string& text) {
  try {
    parse_case(text, "t.toml");
  } catch (const InvalidInput& e) {
    return e.problems();
  }
  ADD_FAILURE() << "expected InvalidInput for:\n" << text;
  return {};
}

std::vector<std::string> sweep_problems(const Case& c, const std::string& key, double value) {
  try {
    with_value(c, key, value);
  } catch (const InvalidInput& e) {
    return e.problems();
  }
  ADD_FAILURE() << "expected InvalidInput for " << key << " = " << value;
  return {};
}

// The JSON echo written as TOML: top-level keys, then tables, nested tables and arrays of
// tables.
std::string toml_of(const nlohmann::json& j) {
  std::string scalars, tables;
  const auto keys = [](const nlohmann::json& t, std::string& out) {
    for (const auto& [key, value] : t.items())
      if (!value.is_object()) out += key + " = " + value.dump() + "\n";
  };
  for (const auto& [name, value] : j.items()) {
    if (value.is_array() && !value.empty() && value[0].is_object()) {
      for (const auto& element : value) {
        tables += "[[" + name + "]]\n";
        keys(element, tables);
      }
    } else if (value.is_object()) {
      tables += "[" + name + "]\n";
      keys(value, tables);
      for (const auto& [sub, inner] : value.items()) {
        if (!inner.is_object()) continue;
        tables += "[" + name + "." + sub + "]\n";
        keys(inner, tables);
      }
    } else {
      scalars += name + " = " + value.dump() + "\n";
    }
  }
  return scalars + tables;
}

bool near(const detail::Value& a, const detail::Value& b, double rel) {
  const auto close = [rel](double x, double y) {
    return std::abs(x - y) <= rel * std::max(std::abs(x), std::abs(y));
  };
  if (a.index() != b.index()) return false;
  if (const double* x = std::get_if<double>(&a)) return close(*x, std::get<double>(b));
  if (const auto* v = std::get_if<std::vector<double>>(&a)) {
    const auto& w = std::get<std::vector<double>>(b);
    if (v->size() != w.size()) return false;
    for (std::size_t i = 0; i < v->size(); ++i)
      if (!close((*v)[i], w[i])) return false;
    return true;
  }
  return a == b;
}

// Every key the tables echo holds the same value in both cases (`rel` = 0: bit for bit).
void expect_same_values(const Case& a, const Case& b, double rel = 0.0) {
  const bool plan = a.process == Process::kBoreMilling;
  ASSERT_EQ(a.process, b.process);
  for (const detail::Section& s : detail::case_sections()) {
    if (s.plan != plan) continue;
    ASSERT_EQ(s.count(a), s.count(b)) << s.name;
    for (std::size_t i = 0; i < s.count(a); ++i) {
      for (const detail::Field& f : s.fields) {
        if (!f.echo) continue;
        const auto va = f.get(a, i), vb = f.get(b, i);
        ASSERT_EQ(va.has_value(), vb.has_value()) << s.name << "[" << i << "]." << f.key;
        if (va) {
          EXPECT_TRUE(near(*va, *vb, rel)) << s.name << "[" << i << "]." << f.key;
        }
      }
    }
  }
}

// ---- reading every section through the tables ----------------------------------------------

TEST(CaseFields, EverySectionRoundTripsThroughTheEchoAsToml) {
  std::set<std::string> echoed;  // "section.key" of every key some echo writes
  std::set<std::string> present;
  // A milling case with a measured FRF beside its modes (the file by its absolute path).
  const std::string measured = std::string(kFullMilling) +
                               "[[frf]]\ndirection = \"x\"\nfile = \"" CUTDYN_EXAMPLES_DIR
                               "/frf/tool_x.uff\"\nformat = \"uff\"\ndataset = 0\n";
  // CutPro text with its units given.
  const std::string given_units = std::string(kFullMilling) +
                                  "[[frf]]\ndirection = \"y\"\nfile = \"" CUTDYN_EXAMPLES_DIR
                                  "/frf/tool_y.frf\"\nunits = \"Hz, m/N\"\n";
  // T2 as an angle instead of seconds.
  std::string angle = kForceLawMilling;
  angle.replace(angle.find("t2_s = 1e-4"), 11, "t2_deg = 72");
  for (const std::string& text :
       {std::string(kFullTurning), std::string(kCoefficientTurning), std::string(kFullMilling),
        std::string(kForceLawMilling), std::string(kPlanWithFeed), measured, given_units,
        angle}) {
    const Case first = parse_case(text, "first.toml");
    EXPECT_TRUE(first.warnings.empty());
    const nlohmann::json j = to_json(first);
    const Case second = parse_case(toml_of(j), "second.toml");
    EXPECT_EQ(to_json(second), j) << toml_of(j);
    // The echo is rounded to 15 digits.
    expect_same_values(first, second, 1e-14);
    for (const detail::Section& s : detail::case_sections()) {
      if (s.plan != (first.process == Process::kBoreMilling) || s.count(first) == 0) continue;
      present.insert(std::string(s.name));
      for (const detail::Field& f : s.fields)
        if (f.echo && f.get(first, 0))
          echoed.insert(std::string(s.name) + "." + std::string(f.key));
    }
  }
  // The cases cover every section and every key the echo writes.
  for (const detail::Section& s : detail::case_sections()) {
    EXPECT_TRUE(present.count(std::string(s.name))) << "section " << s.name;
    for (const detail::Field& f : s.fields) {
      if (f.echo) {
        EXPECT_TRUE(echoed.count(std::string(s.name) + "." + std::string(f.key)))
            << s.name << "." << f.key;
      }
    }
  }
}

TEST(CaseFields, TablesReachTheCaseInSi) {
  const Case t = parse_case(kFullTurning, "t.toml");
  const double w = units::hz_to_rad_per_s(512.5);
  EXPECT_EQ(t.modal.modes[1].stiffness_n_per_m, 2.5 * w * w);
  EXPECT_EQ(*t.mode_mass_kg[1], 2.5);
  EXPECT_FALSE(t.mode_mass_kg[0].has_value());
  EXPECT_EQ(*t.cutting.speed_m_per_s, 200.0 / 60.0);
  EXPECT_EQ(t.material->flow.reference_temperature_c, 22.0);
  EXPECT_EQ(t.oxley.psi, 0.85);
  EXPECT_EQ(*t.vibration->amplitude_m, 15e-6);
  EXPECT_EQ(t.lobes.method, StabilityMethod::kMultiFrequency);
  EXPECT_FALSE(t.lobes.grid.refine);
  const Case m = parse_case(kFullMilling, "m.toml");
  EXPECT_NEAR(m.tool->pitch_rad[1], units::deg_to_rad(100.0), 1e-15);
  EXPECT_FALSE(m.operation->engagement.down_milling);
  EXPECT_EQ(m.simulate.slices, 8);
  ASSERT_EQ(m.drives.size(), 2u);
  EXPECT_EQ(m.drives[0].name, "x");
  EXPECT_EQ(m.drives[0].motor->seed, 7u);
  EXPECT_EQ(m.drives[0].motor->measure, CurrentMeasure::kRms);
  EXPECT_FALSE(m.drives[1].motor.has_value());
  EXPECT_EQ(m.drives[1].drive.model, FeedDrive::Model::kDynamic);
  EXPECT_NEAR(m.drives[1].direction[2], std::sqrt(0.5), 1e-15);
  EXPECT_EQ(m.drives[1].drive.transmission.lead_m, 0.01);
  const Case p = parse_case(kPlanWithFeed, "p.toml");
  EXPECT_EQ(*p.axial_feed_m, 1.5e-3);
  EXPECT_EQ(p.bore_limits->cutter_rev_per_s_max, 10.0);
}

// ---- errors --------------------------------------------------------------------------------

TEST(CaseFields, UnknownKeysInEverySection) {
  for (const char* text :
       {kFullTurning, kCoefficientTurning, kFullMilling, kForceLawMilling, kPlanWithFeed}) {
    const nlohmann::json j = to_json(parse_case(text, "a.toml"));
    for (const detail::Section& s : detail::case_sections()) {
      const Case c = parse_case(text, "a.toml");
      if (s.name.empty() || s.plan != (c.process == Process::kBoreMilling) || s.count(c) == 0)
        continue;
      nlohmann::json bad = j;
      const std::string name(s.name);
      const auto dot = name.find('.');
      nlohmann::json& table = s.array ? bad[name][0]
                              : dot == std::string::npos
                                  ? bad[name]
                                  : bad[name.substr(0, dot)][name.substr(dot + 1)];
      table["colour"] = 1;
      table[std::string(s.fields.front().key) + "x"] = 1;
      const std::string path = s.array ? name + "[0]" : name;
      std::vector<std::string> expected = {path + ".colour: unknown key",
                                           path + "." + std::string(s.fields.front().key) +
                                               "x: unknown key (did you mean " +
                                               std::string(s.fields.front().key) + "?)"};
      auto got = problems_of(toml_of(bad));
      std::sort(expected.begin(), expected.end());
      std::sort(got.begin(), got.end());
      EXPECT_EQ(got, expected) << name;
    }
  }
}

TEST(CaseFields, RangeErrorsNameTheKeyAndTheUsersUnit) {
  std::string text = kFullMilling;
  text.replace(text.find("diameter_mm = 19.05"), 19, "diameter_mm = -19.05");
  text.replace(text.find("depth_mm = 1\n"), 13, "depth_mm = 0\n");
  text.replace(text.find("lead_mm = 10"), 12, "lead_mm = 0");
  EXPECT_THAT(problems_of(text),
              ElementsAre("drives[1].lead_mm = 0: must be positive",
                          "tool.diameter_mm = -19.05: must be positive",
                          "simulate.depth_mm = 0: must be greater than 0 and at most 10000"));
  // The rule is in the key's unit (mm), not SI.
  const Case c = parse_case(kFullMilling, "m.toml");
  EXPECT_THAT(sweep_problems(c, "lobes.depth_max_mm", 20000),
              ElementsAre("lobes.depth_max_mm = 20000: must be greater than 0 and at most 10000"));
  EXPECT_THAT(sweep_problems(c, "operation.entry_deg", 190),
              ElementsAre("operation.entry_deg = 190: must be at least 0 and at most 180"));
  EXPECT_THAT(sweep_problems(c, "drives[0].stiffness_nm_s_per_rad", 0),
              ElementsAre("drives[0].stiffness_nm_s_per_rad = 0: must not be 0 (|β|, the slope "
                          "of the characteristic)"));
}

// ---- sweeps --------------------------------------------------------------------------------

// A sweep step equals the case file with the key written in by hand.
void expect_sweep_is_the_edited_file(const std::string& text, const std::string& key, double value,
                                     const std::string& from, const std::string& to) {
  const Case swept = with_value(parse_case(text, "a.toml"), key, value);
  std::string edited = text;
  const auto at = edited.find(from);
  ASSERT_NE(at, std::string::npos) << from;
  edited.replace(at, from.size(), to);
  const Case expected = parse_case(edited, "a.toml");
  expect_same_values(swept, expected);
  EXPECT_EQ(to_json(swept), to_json(expected)) << key;
  for (std::size_t i = 0; i < expected.modal.modes.size(); ++i) {
    EXPECT_EQ(swept.modal.modes[i].natural_rad_s, expected.modal.modes[i].natural_rad_s);
    EXPECT_EQ(swept.modal.modes[i].stiffness_n_per_m, expected.modal.modes[i].stiffness_n_per_m);
  }
}

TEST(CaseFields, SweepsEqualTheFileWrittenByHand) {
  expect_sweep_is_the_edited_file(kFullMilling, "lobes.rpm_max", 12000, "rpm_max = 25000",
                                  "rpm_max = 12000");
  expect_sweep_is_the_edited_file(kFullMilling, "simulate.depth_mm", 0.08, "depth_mm = 1\n",
                                  "depth_mm = 0.08\n");
  expect_sweep_is_the_edited_file(kFullMilling, "tool.helix_deg", 12.5, "helix_deg = 30",
                                  "helix_deg = 12.5");
  expect_sweep_is_the_edited_file(kFullMilling, "cutting.kt_n_per_mm2", 700.3,
                                  "kt_n_per_mm2 = 644.5", "kt_n_per_mm2 = 700.3");
  expect_sweep_is_the_edited_file(kFullTurning, "vibration.amplitude_um", 7.5, "amplitude_um = 15",
                                  "amplitude_um = 7.5");
  expect_sweep_is_the_edited_file(kFullTurning, "cutting.speed_m_per_min", 75,
                                  "speed_m_per_min = 200", "speed_m_per_min = 75");
  expect_sweep_is_the_edited_file(kFullTurning, "material.johnson_cook.c", 0.03, "c = 0.02",
                                  "c = 0.03");
  expect_sweep_is_the_edited_file(kPlanWithFeed, "process.axial_feed_mm", 2.25,
                                  "axial_feed_mm = 1.5", "axial_feed_mm = 2.25");
  // Indexed keys: an element of [[modes]] or [[drives]].
  expect_sweep_is_the_edited_file(kFullMilling, "modes[0].damping_ratio", 0.05,
                                  "damping_ratio = 0.039", "damping_ratio = 0.05");
  expect_sweep_is_the_edited_file(kFullMilling, "drives[0].ratio", 0.25, "ratio = 0.1",
                                  "ratio = 0.25");
  expect_sweep_is_the_edited_file(kFullMilling, "drives[1].lead_mm", 5, "lead_mm = 10",
                                  "lead_mm = 5");
  // A mode given by its mass keeps it: the stiffness follows the natural frequency.
  expect_sweep_is_the_edited_file(kFullMilling, "modes[1].natural_hz", 1000, "natural_hz = 950",
                                  "natural_hz = 1000");
  expect_sweep_is_the_edited_file(kFullMilling, "modes[1].mass_kg", 0.05, "mass_kg = 0.04",
                                  "mass_kg = 0.05");
  // An integer key takes an integral value.
  expect_sweep_is_the_edited_file(kFullMilling, "simulate.steps_per_tooth", 64,
                                  "steps_per_tooth = 128", "steps_per_tooth = 64");
}

TEST(CaseFields, SweepOfAnAbsentTableCreatesIt) {
  const Case c = parse_case(kForceLawMilling, "a.toml");
  const Case with_operation = with_value(c, "operation.radial_immersion", 0.25);
  ASSERT_TRUE(with_operation.operation.has_value());
  EXPECT_EQ(with_operation.operation->engagement.radial_immersion, 0.25);
  EXPECT_TRUE(with_operation.operation->engagement.down_milling);  // the default
  EXPECT_THAT(sweep_problems(parse_case(kFullTurning, "t"), "simulate.depth_mm", -1),
              ElementsAre("simulate.depth_mm = -1: must be greater than 0 and at most 10000"));
}

TEST(CaseFields, SweepProblemsNameTheKeyAndWhatIsWrong) {
  const Case c = parse_case(kFullMilling, "m.toml");
  EXPECT_THAT(sweep_problems(c, "modes[2].damping_ratio", 0.05),
              ElementsAre("modes[2].damping_ratio = 0.05: index out of range: the case has 2 "
                          "[[modes]] tables"));
  EXPECT_THAT(sweep_problems(c, "drives[3].ratio", 0.5),
              ElementsAre(HasSubstr("index out of range: the case has 2 [[drives]] tables")));
  EXPECT_THAT(sweep_problems(c, "modes.damping_ratio", 0.05),
              ElementsAre(HasSubstr("modes is an array of tables: give the index, e.g. "
                                    "modes[0].damping_ratio")));
  EXPECT_THAT(sweep_problems(c, "lobes[0].rpm_max", 5),
              ElementsAre(HasSubstr("lobes is a table, not an array of tables")));
  EXPECT_THAT(sweep_problems(c, "lobes.rpm_maks", 6000),
              ElementsAre("lobes.rpm_maks = 6000: unknown key (did you mean rpm_max?)"));
  EXPECT_THAT(sweep_problems(c, "lobez.rpm_max", 6000),
              ElementsAre("lobez.rpm_max = 6000: lobez: unknown table (did you mean lobes?)"));
  EXPECT_THAT(sweep_problems(c, "lobes.method", 1),
              ElementsAre(HasSubstr("not a number key (method takes a string)")));
  EXPECT_THAT(sweep_problems(c, "lobes.refine", 1),
              ElementsAre(HasSubstr("not a number key (refine takes true or false)")));
  EXPECT_THAT(sweep_problems(c, "tool.teeth", 2.5),
              ElementsAre("tool.teeth = 2.5: wrong type: expected an integer, got a float"));
  // Rules between keys: the pitch has one angle per tooth; rpm_max above rpm_min.
  EXPECT_THAT(sweep_problems(c, "tool.teeth", 3),
              ElementsAre("tool.pitch_deg = [80, 100, 80, 100]: must give one angle per tooth "
                          "(teeth = 3), got 4"));
  EXPECT_THAT(sweep_problems(c, "lobes.rpm_max", 4000),
              ElementsAre("lobes.rpm_max = 4000: must be greater than lobes.rpm_min = 5000"));
  EXPECT_THAT(sweep_problems(c, "modes[0].mass_kg", 2),
              ElementsAre(HasSubstr("give either stiffness_n_per_m or mass_kg, not both")));
  EXPECT_THAT(sweep_problems(c, "drives[1].current_noise_a", 0.1),
              ElementsAre("drives[1].current_noise_a = 0.1: needs the motor: pole_pairs and "
                          "torque_constant_nm_per_a"));
  EXPECT_THAT(sweep_problems(c, "vibration.frequency_hz", 1000),
              ElementsAre(HasSubstr("not used in a milling case")));
  EXPECT_THAT(sweep_problems(parse_case(kForceLawMilling, "f"), "cutting.kte_n_per_mm", 3),
              ElementsAre(HasSubstr("not used with [force_law]")));
  EXPECT_THAT(sweep_problems(parse_case(kFullTurning, "t"), "cutting.kc_n_per_mm2", 2000),
              ElementsAre("cutting.kc_n_per_mm2 and [material]: give the force coefficients or "
                          "the material to predict them from, not both"));
  EXPECT_THAT(sweep_problems(parse_case(kFullTurning, "t"),
                             "material.johnson_cook.melting_temperature_c", 0),
              ElementsAre(HasSubstr("material.johnson_cook.melting_temperature_c = 0 °C: must "
                                    "be above")));
  EXPECT_THAT(sweep_problems(parse_case(kForceLawMilling, "f"), "lobes.rpm_min", 1e5),
              ElementsAre(HasSubstr("must be greater than lobes.rpm_min = 100000")));
  // A new table's other required keys are missing.
  EXPECT_THAT(sweep_problems(c, "force_law.t2_s", 1e-4),
              ElementsAre("force_law.c_n_per_mm: missing (required)"));
  try {
    with_value(c, "lobes.rpm_max", 4000);
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where(), "m.toml with lobes.rpm_max = 4000");
  }
}

// ---- the feed-direction coefficient of turning ------------------------------------------------

TEST(CaseFields, TurningKtIsTheOldNameOfKfWithAWarning) {
  constexpr const char* kTurning =
      "process = \"turning\"\n[[modes]]\ndirection = \"x\"\nnatural_hz = 228.8\n"
      "damping_ratio = 0.01\nstiffness_n_per_m = 2.26e8\n[cutting]\n";
  const Case kf = parse_case(std::string(kTurning) + "kf_n_per_mm2 = 850\n", "kf.toml");
  EXPECT_TRUE(kf.warnings.empty());
  EXPECT_EQ(*kf.cutting.kf_pa, 850e6);
  const Case kt = parse_case(std::string(kTurning) + "kt_n_per_mm2 = 850\n", "kt.toml");
  EXPECT_EQ(*kt.cutting.kf_pa, 850e6);
  ASSERT_EQ(kt.warnings.size(), 1u);
  EXPECT_THAT(kt.warnings[0], HasSubstr("cutting.kt_n_per_mm2: in a turning case kt_n_per_mm2 "
                                        "is the old name of kf_n_per_mm2"));
  // The echo writes the new name.
  EXPECT_EQ(to_json(kt)["cutting"], (nlohmann::json{{"kf_n_per_mm2", 850}}));
  // Both names: one is enough.
  EXPECT_THAT(problems_of(std::string(kTurning) + "kt_n_per_mm2 = 850\nkf_n_per_mm2 = 900\n"),
              ElementsAre("cutting.kt_n_per_mm2 = 850 and cutting.kf_n_per_mm2 = 900: give "
                          "kf_n_per_mm2 only (kt_n_per_mm2 is its old name)"));
  // In milling kt_n_per_mm2 is the tangential coefficient (no warning), kf_n_per_mm2 unused.
  const Case m = parse_case(kFullMilling, "m.toml");
  EXPECT_TRUE(m.warnings.empty());
  std::string kf_milling = kFullMilling;
  kf_milling.replace(kf_milling.find("kt_n_per_mm2"), 12, "kf_n_per_mm2");
  EXPECT_THAT(problems_of(kf_milling),
              ElementsAre(HasSubstr("cutting.kf_n_per_mm2 = 644.5: not used in a milling case "
                                    "(milling takes kt_n_per_mm2, kr_n_per_mm2")));
  // A sweep may use either name in turning.
  EXPECT_EQ(*with_value(kt, "cutting.kt_n_per_mm2", 900).cutting.kf_pa, 900e6);
  EXPECT_EQ(*with_value(kt, "cutting.kf_n_per_mm2", 900).cutting.kf_pa, 900e6);
}

}  // namespace
}  // namespace cutdyn::io
