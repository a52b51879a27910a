// Case files (TOML). Keys carry their unit; the loaded Case is SI (names without a unit
// suffix are SI; a field in another unit says so in its name, e.g. `rpm_min`).
//
// Every value is checked when the file is loaded. All problems are collected and thrown
// together as cutdyn::InvalidInput whose where() is the file name (or "example NAME") and
// whose problems() read  `<key> = <value as written>: <rule>`,  with <key> the TOML path as
// the user wrote it ("modes[0].damping_ratio", "lobes.rpm_min", "vibration.amplitude_um").
// Kinds of problem: TOML syntax (with line and column), missing key, wrong type, value out
// of range or not finite, unknown key or table, inconsistent keys.
//
// The keys and rules are documented in docs/case-files.md.
#pragma once

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "cutdyn/drive/feed_drive.hpp"
#include "cutdyn/forces/oxley.hpp"
#include "cutdyn/forces/work_material.hpp"
#include "cutdyn/io/frf_file.hpp"
#include "cutdyn/modal/measured_frf.hpp"
#include "cutdyn/modal/modal_model.hpp"
#include "cutdyn/plan/bore_milling.hpp"
#include "cutdyn/process/milling.hpp"
#include "cutdyn/process/turning.hpp"
#include "cutdyn/stability/lobes.hpp"
#include "cutdyn/stability/method.hpp"

namespace cutdyn::io {

/// kBoreMilling: a `cutdyn plan` case, marked by a [process] table instead of the key.
enum class Process { kTurning, kMilling, kBoreMilling };

/// Stability method requested in [lobes].method.
using cutdyn::StabilityMethod;  // the library's: one name set everywhere

const char* to_string(Process process);

/// [cutting]. Which keys a command needs is checked by that command.
struct CuttingSection {
  std::optional<double> kt_pa;  // kt_n_per_mm2: milling tangential coefficient
  /// kf_n_per_mm2: turning feed-direction coefficient (kt_n_per_mm2 in a turning case is its
  /// old name, read into this member with a warning).
  std::optional<double> kf_pa;
  std::optional<double> kc_pa;          // kc_n_per_mm2: turning cutting-direction coefficient
  std::optional<double> kr_pa;          // kr_n_per_mm2: milling radial coefficient
  std::optional<double> speed_m_per_s;  // speed_m_per_min
  std::optional<double> uncut_chip_thickness_m;   // uncut_chip_thickness_mm (turning: feed/rev)
  std::optional<double> width_m;                  // width_mm (turning: depth of cut)
  std::optional<double> kte_n_per_m;              // kte_n_per_mm: milling edge coefficients
  std::optional<double> kre_n_per_m;              // kre_n_per_mm
  std::optional<double> rake_rad;                 // rake_deg: tool rake angle (Oxley)
  std::optional<double> workpiece_temperature_c;  // before cutting (Oxley); default: the
                                                  // material's Johnson–Cook reference
};

/// [operation] (milling): the engagement, and the feed per tooth of `cutdyn simulate`.
struct OperationSection {
  MillingEngagement engagement;            // radial_immersion, direction, entry_deg, exit_deg
  std::optional<double> feed_per_tooth_m;  // feed_per_tooth_mm (simulation)
};

/// [[frf]]: a measured receptance of the structure, read from `file` when the case is loaded.
struct FrfTable {
  std::string direction;  // "x", "y" or "xy" (cross)
  std::string file;       // as written: relative to the case file
  std::string format;     // "frf", "csv", "uff"; empty: from the content
  std::optional<int> dataset;
  std::string units;           // CutPro text: the file's units ("Hz, mm/N"); empty: its header's
  std::filesystem::path path;  // the file resolved
  MeasuredFrf data;            // receptance, m/N
};

/// [lobes]: the spindle-speed grid and the depth search range.
struct LobesSection {
  /// rpm_min, rpm_max, rpm_steps, refine: the library's grid (LobesOptions::fields()).
  LobesOptions grid;
  double depth_max_m = 0.03;  // depth_max_mm
  StabilityMethod method = StabilityMethod::kAuto;
  int harmonics = 5;         // multi-frequency: harmonics kept each side (stability_fields)
  int steps_per_period = 0;  // full discretization: 0 = automatic, else 1..100000
};

/// [simulate]: one time-domain run (command-line flags override these).
struct SimulateSection {
  std::optional<double> rpm;
  std::optional<double> depth_m;         // depth_mm
  double duration_s = 1.0;               // 0 < . <= 1000
  double initial_displacement_m = 1e-6;  // initial_displacement_um, >= 0
  // Milling:
  double revolutions = 30.0;         // simulated revolutions
  double summary_revolutions = 2.0;  // the last ones, for the summary
  bool regenerative = true;          // false: chip from the feed alone (force studies)
  int steps_per_tooth = 256;
  int slices = 0;                  // 0: automatic
  bool closed_form_helix = false;  // [Ermolaev2020] eqs. 8–9 instead of slices
};

/// The deepest cut any key or request may ask for (stability/method.hpp).
using cutdyn::kMaxDepthMm;

/// The spindle speed limit of a case that states none: above the fastest machining spindles.
inline constexpr double kDefaultSpindleMaxRpm = 60000.0;

struct Case {
  std::string source;  // file path as given, or "example NAME"
  std::string text;    // the TOML it was read from
  Process process = Process::kTurning;
  /// spindle_max_rpm: the fastest the spindle turns; a speed asked above it is warned about.
  double spindle_max_rpm = kDefaultSpindleMaxRpm;
  ModalModel modal;  // from [[modes]], SI
  /// [[modes]] mass_kg as given, one entry per mode (nullopt: given by stiffness_n_per_m);
  /// the stiffness follows it and natural_hz.
  std::vector<std::optional<double>> mode_mass_kg;
  std::vector<FrfTable> frfs;  // [[frf]]: measured receptances, beside or instead of [[modes]]
  CuttingSection cutting;
  std::optional<MillingTool> tool;            // [tool]
  std::optional<OperationSection> operation;  // [operation]
  std::optional<VibrationAssist> vibration;   // [vibration]: vibration-assisted turning
  /// [force_law]: the S1 force law of milling ([Ermolaev2020]) for `cutdyn simulate`; without
  /// it the simulation uses the mechanistic law of [cutting].
  std::optional<ErmolaevForceLaw> force_law;
  /// [material]: the work material for Oxley's predictive force model (`cutdyn force`, and
  /// Kt for the turning commands when [cutting] gives none), complete and validated. `name`
  /// picks a library entry; [material.johnson_cook] and [material.thermal] give or override
  /// its values key by key.
  std::optional<WorkMaterial> material;
  OxleyOptions oxley;            // [oxley]: search ranges and heat factors of the theory
  std::vector<FeedAxis> drives;  // [[drives]]: feed axes for `cutdyn drive`
  /// A bore-milling plan ([bore], [cutter], [process] tables; `cutdyn plan`).
  std::optional<BoreMillingCase> bore;
  std::optional<double> axial_feed_m;  // process.axial_feed_mm: a fixed S0 (else the largest)
  std::optional<BoreMillingLimits> bore_limits;  // [limits]: `cutdyn plan` then optimises
  LobesSection lobes;
  SimulateSection simulate;
  /// What the loader accepted but the user should change (an old key name); the commands
  /// print each as "cutdyn: warning: SOURCE: ...".
  std::vector<std::string> warnings;
};

/// Reads the file a [[frf]] table names: `file` as the case writes it, with the table's
/// reader options. Throws cutdyn::InvalidInput for a file it may not or cannot read.
using FrfFileReader =
    std::function<FrfReadResult(const std::string& file, const FrfFileOptions& options)>;

/// Values whose magnitude looks like a unit slip (Kt in Pa, a diameter in m, a stiffness in
/// N/mm …; the table is in docs/case-files.md, "Plausible magnitudes"), each as a warning
/// naming the key, the value and the probable fix. parse_case adds them to `warnings`.
std::vector<std::string> plausibility_warnings(const Case& c);

/// Parses and validates TOML text. `source` names it in error messages. The [[frf]] files are
/// read by `read_frf`; without one, from disk, relative to the folder of `source`.
Case parse_case(std::string_view toml_text, std::string_view source,
                const FrfFileReader& read_frf = {});

/// Parses and validates a case given as JSON (the same keys, tables and arrays of tables as
/// the TOML, e.g. the `case` object of any command's --json output, or a Python dict): it is
/// written as TOML and read by parse_case, so every key and rule is checked the same way.
/// `null` stands for an absent key. A value TOML cannot hold (null in an array, an array
/// mixing tables and values) throws cutdyn::InvalidInput naming its key.
Case parse_case_json(const nlohmann::json& j, std::string_view source,
                     const FrfFileReader& read_frf = {});

/// The case with one number key set to `value` in the key's own unit (a sweep step): set
/// through the field table on a copy and checked again with every rule of the loader.
/// `key` is the TOML path as in the messages: "lobes.rpm_max", "modes[0].damping_ratio",
/// "drives[1].ratio", "material.johnson_cook.a_mpa", or a top-level key. An absent table is
/// created (its other required keys are then missing). The copy's source reads
/// "SOURCE with KEY = VALUE". Throws cutdyn::InvalidInput naming the key and value for an
/// unknown key or table, a key that is not a number, an index out of range, a value out of
/// range, and anything the loader would refuse.
Case with_value(const Case& c, std::string_view key, double value);

/// Reads and parses a file. A missing or unreadable file throws cutdyn::InvalidInput
/// with where() = the path and a problem saying why.
Case load_case_file(const std::filesystem::path& path);

/// Built-in example cases (examples/*.toml, embedded at build time): name and text,
/// sorted by name.
const std::vector<std::pair<std::string_view, std::string_view>>& examples();

/// Text of a built-in example, or nullopt.
std::optional<std::string_view> example_text(std::string_view name);

/// Loads a built-in example (source = "example NAME"); throws cutdyn::InvalidInput
/// listing the available names if there is none called `name`.
Case load_example(std::string_view name);

/// The effective case as JSON, in the case file's own keys and units (so that it could
/// be written back as TOML): {"process": ..., "modes": [...], "cutting": {...}, ...}.
/// Optional sections that are absent are omitted.
nlohmann::json to_json(const Case& c);

/// Every table of a case file and its keys, from the same field tables the reader checks with:
/// {"modes": {"array": true, "keys": {"natural_hz": {"type", "unit", "default", "process",
/// "rule", "label", "choices"}}}, ...}; the top-level keys under "(top level)", a plan case's
/// tables with " (plan)". For a front end's inputs (and their units, choices and rules).
nlohmann::json case_schema();

}  // namespace cutdyn::io
