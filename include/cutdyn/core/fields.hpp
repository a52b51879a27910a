// Field lists: the keys of a library parameter struct, spelled once beside its members.
//
// A struct a user can set (lobes grid, stability options, ...) declares, for each member a
// user sets, its key as the case file writes it, the unit the case file writes it in and
// the conversion to the SI value the member holds, the allowed range (in that unit), a
// label for a figure's axis and its meaning for the docs. The struct's `validate()` walks
// the list (`check_fields`), so a key has exactly one range; the case file's tables
// (io/case_fields.cpp), the JSON echo, the schema and the docs' key tables take their rows
// from the same list (`io::detail::Row::field`). Rules that join several keys ("rpm_max
// greater than rpm_min") stay explicit code in `validate()`.
#pragma once

#include <cmath>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <variant>

#include "cutdyn/core/error.hpp"

namespace cutdyn {

/// An allowed interval for a number in the user's unit, with its rule text ("must be
/// positive", "must be at least 0 and less than 1", ...).
struct FieldRange {
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  double lo = -kInf;
  bool lo_open = true;
  double hi = kInf;
  bool hi_open = true;
  bool nonzero = false;        // and not 0
  std::string_view rule_text;  // the message's rule and the doc's range, instead of generated

  bool contains(double v) const;
  /// The message's rule for a number: "must be positive", "must be greater than 0 and at most 1".
  std::string rule() const;
  /// The doc's range: "> 0", "0 ≤ . < 1", "2 … 100000" (integer), "" for any finite number.
  std::string doc(bool integer) const;

  static constexpr FieldRange make(double lo, bool lo_open, double hi, bool hi_open) {
    FieldRange r;
    r.lo = lo;
    r.lo_open = lo_open;
    r.hi = hi;
    r.hi_open = hi_open;
    return r;
  }
  static constexpr FieldRange any() { return {}; }
  static constexpr FieldRange positive() { return make(0.0, true, kInf, true); }
  static constexpr FieldRange non_negative() { return make(0.0, false, kInf, true); }
  static constexpr FieldRange open(double lo, double hi) { return make(lo, true, hi, true); }
  static constexpr FieldRange closed(double lo, double hi) { return make(lo, false, hi, false); }
  static constexpr FieldRange open_closed(double lo, double hi) {
    return make(lo, true, hi, false);
  }
  static constexpr FieldRange closed_open(double lo, double hi) {
    return make(lo, false, hi, true);
  }
};

/// The unit a key is written in and its conversion to the SI value the member holds.
struct FieldUnit {
  std::string_view text;  // as the docs show it: "mm", "N/mm²", "–" (none)
  double (*to_si)(double);
  double (*from_si)(double);

  /// The unit in a message: "" for a pure number.
  std::string_view message_text() const { return text == "–" ? std::string_view{} : text; }
};

namespace fields {
inline double same(double v) { return v; }
inline constexpr FieldUnit unit(std::string_view text) { return {text, same, same}; }
inline constexpr FieldUnit kNone = unit("–");
}  // namespace fields

enum class FieldType { kNumber, kInteger, kBoolean };

/// A key shared by several structs (the depth limit of every stability method): its
/// spelling, unit and range once; make_field attaches it to one struct's member.
struct FieldSpec {
  std::string_view key;
  FieldType type = FieldType::kNumber;
  FieldUnit unit = fields::kNone;
  FieldRange range;
  std::string_view label;
  std::string_view meaning;
};

/// One member of S a user can set.
template <class S>
struct Field {
  std::string_view key;
  FieldType type = FieldType::kNumber;
  FieldUnit unit = fields::kNone;
  FieldRange range;
  std::variant<double S::*, int S::*, bool S::*> member;
  std::string_view label;    // a few words for a figure's axis ("spindle speed")
  std::string_view meaning;  // for the docs, after the range

  /// The member's value in the user's unit (booleans as 0 or 1).
  double user_value(const S& s) const {
    if (const auto* d = std::get_if<double S::*>(&member)) return unit.from_si(s.**d);
    if (const auto* i = std::get_if<int S::*>(&member)) return static_cast<double>(s.**i);
    return s.*std::get<bool S::*>(member) ? 1.0 : 0.0;
  }
  /// Sets the member from a value in the user's unit (an integer member takes it as is: the
  /// range check says whether it is a whole number in range).
  void set_user_value(S& s, double v) const {
    if (const auto* d = std::get_if<double S::*>(&member)) {
      s.**d = unit.to_si(v);
    } else if (const auto* i = std::get_if<int S::*>(&member)) {
      s.**i = static_cast<int>(v);
    } else {
      s.*std::get<bool S::*>(member) = v != 0.0;
    }
  }
};

template <class S, class M>
Field<S> make_field(const FieldSpec& spec, M S::*member) {
  return {spec.key, spec.type, spec.unit, spec.range, member, spec.label, spec.meaning};
}

/// The field named `key` in `list`; nullptr when there is none.
template <class S>
const Field<S>* find_field(std::span<const Field<S>> list, std::string_view key) {
  for (const Field<S>& f : list)
    if (f.key == key) return &f;
  return nullptr;
}

/// Records a problem for every number of `s` outside its field's range (or not finite):
/// "key = value unit: rule", the value in the user's unit.
template <class S>
void check_fields(const S& s, std::span<const Field<S>> list, Validator& v) {
  for (const Field<S>& f : list) {
    if (f.type == FieldType::kBoolean) continue;
    const double value = f.user_value(s);
    if (!(std::isfinite(value) && f.range.contains(value)))  // the rule's text only then
      v.require(false, f.key, value, f.unit.message_text(), f.range.rule());
  }
}

/// A number as text: integral values without a fraction or exponent ("100000"), others
/// shortest ("0.05", "2.26e+08").
std::string number_text(double value);

}  // namespace cutdyn
