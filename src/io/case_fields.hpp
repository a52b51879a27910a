// The field tables of the case file: one table per case section, one row per key, with the
// key as the user writes it, its type and unit, the conversion to SI (used both ways), the
// range check, whether it is required or its default, the process that takes it, and the
// Case member it fills. The tables drive reading (case_file.cpp), the unknown-key check,
// `to_json`, `with_value` and the key tables of docs/case-files.md (key_table_markdown).
//
// Per-key facts only: rules between keys ("not with [force_law]", "give entry_deg and
// exit_deg together") are explicit code in case_file.cpp.
#pragma once

#include <cstddef>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "cutdyn/core/fields.hpp"
#include "cutdyn/io/case_file.hpp"

namespace cutdyn::io::detail {

inline constexpr double kInf = FieldRange::kInf;

/// Ranges and units are the library's (core/fields.hpp): a row made from a library struct's
/// field list (Row::field) carries them unchanged.
using Range = FieldRange;
using Unit = FieldUnit;

enum class Type { kNumber, kInteger, kBoolean, kChoice, kText, kNumbers };

/// Which dynamics process takes a key (in the other one the key is an error).
enum class Uses { kBoth, kTurning, kMilling };

/// A key's value in the Case: numbers in SI (integers too), flags, names, arrays in SI.
using Value = std::variant<double, bool, std::string, std::vector<double>>;

/// Reads the value of a key from the Case (element `index` of an array section); nullopt
/// when the Case holds none (an optional key not given, a table that is absent).
using Getter = std::function<std::optional<Value>(const Case&, std::size_t index)>;
/// Sets it; returns "" or why the value cannot be taken (the rule of the problem).
using Setter = std::function<std::string(Case&, std::size_t index, const Value&)>;
/// A condition on the Case (for conditional requirements and what `to_json` writes).
using Predicate = std::function<bool(const Case&, std::size_t index)>;

struct Field {
  std::string_view key;
  Type type = Type::kNumber;
  Unit unit;
  Range range;                            // numbers and integers (each element of an array)
  std::vector<std::string_view> choices;  // kChoice
  int array_size = 0;                     // kNumbers: exact count, 0 = any
  bool required = false;
  Predicate required_if;  // required when this holds (message "missing (required)")
  Uses uses = Uses::kBoth;
  bool echo = true;   // written by to_json (not: mass_kg, echoed as stiffness; axis, as direction)
  Predicate echo_if;  // written by to_json only when this holds
  Getter get;
  Setter set;
  // The doc's cells: "required / default" (generated from the required flag or the default
  // Case when empty), the process cell (generated from `uses` when empty), and the meaning
  // after the range in the rule cell.
  std::string_view default_doc, process_doc, meaning;
  // What a number key is, in a few words, for a figure's axis ("spindle speed"); the axis
  // adds the unit (key_axis_label).
  std::string_view label;

  bool numeric() const { return type == Type::kNumber || type == Type::kInteger; }
  bool used_in(Process process) const;
};

/// Another name of a key in one process, read with a warning.
struct Alias {
  std::string_view key;        // the old name, e.g. "kt_n_per_mm2"
  std::string_view canonical;  // the field it fills, e.g. "kf_n_per_mm2"
  Uses uses;                   // the process in which `key` is the alias
  std::string_view warning;    // why, for the load warning
};

struct Section {
  std::string_view name;        // TOML path: "" (top level), "cutting", "modes", "material.thermal"
  bool array = false;           // [[name]]
  bool plan = false;            // a table of a plan case ([bore], [cutter], [process], [limits])
  bool process_column = false;  // the doc's table has a process column
  bool echo_empty = true;       // to_json writes the table even without keys
  std::vector<Field> fields;
  std::vector<Alias> aliases;
  std::vector<std::string_view> subtables;  // known sub-tables ("johnson_cook", "thermal")
  /// Elements in the Case: an array's size, else 1 when the table is present, 0 when not.
  std::function<std::size_t(const Case&)> count;
  /// Adds the absent table to the Case (for with_value); returns "" or why it cannot.
  std::function<std::string(Case&)> create;

  const Field* find(std::string_view key) const;
  /// The alias `key` in `process`, if it is one.
  const Alias* alias(std::string_view key, Process process) const;
};

/// Every section of a dynamics case (top level first) and of a plan case, in the order of
/// docs/case-files.md.
const std::vector<Section>& case_sections();
const Section* find_section(std::string_view name, bool plan);

/// A key as it would be written in a TOML path: bare if it can be, else quoted.
std::string key_text(std::string_view key);
using cutdyn::number_text;
/// A value converted back to the user's unit, rounded to 15 significant digits (so that the
/// unit round trip prints what the file said); integral values as integers.
double tidy_number(double value);
/// The value as the user would write it: "30", "0.05", "true", "\"down\"", "[120, 240]".
std::string value_text(const Field& field, const Value& value);

/// The axis label of a number key (a TOML path as `with_value` takes it) in the case's
/// tables: its label in words and its unit, "spindle speed (rpm)", "damping ratio ζ" (no
/// unit for a ratio), with the element of an array section, "natural frequency, modes[1]
/// (Hz)"; an alias takes its field's label. The key itself, with its unit when known, when
/// the key has no label or is not in the tables.
std::string key_axis_label(const Case& c, std::string_view key);

/// The markdown key table of a section, as in docs/case-files.md.
std::string key_table_markdown(const Section& section);

/// The field tables as JSON (io::case_schema).
nlohmann::json schema_json();

}  // namespace cutdyn::io::detail
