// The library structs' field lists (core/fields.hpp) and every place that spells a key of
// theirs: the case file's reader (through a sweep, which reads a value as the file would), the
// JSON echo, the schema, the docs' key table and the struct's own validate() agree on the
// key, the unit, the conversion to SI and the range, field by field.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/fields.hpp"
#include "cutdyn/io/case_file.hpp"
#include "cutdyn/stability/lobes.hpp"
#include "cutdyn/stability/milling.hpp"
#include "cutdyn/stability/multi_frequency.hpp"
#include "cutdyn/stability/turning.hpp"
#include "io/case_fields.hpp"

namespace cutdyn::io {
namespace {

using ::testing::HasSubstr;

// Values inside and outside a range, in the user's unit (whole numbers for integers).
double inside(const FieldRange& r, bool integer) {
  double v = 1.0;
  if (std::isfinite(r.lo) && std::isfinite(r.hi)) {
    v = 0.5 * (r.lo + r.hi);
  } else if (std::isfinite(r.lo)) {
    v = r.lo + 1.0;
  } else if (std::isfinite(r.hi)) {
    v = r.hi - 1.0;
  }
  return integer ? std::round(v) : v;
}

std::vector<double> outside(const FieldRange& r, bool integer) {
  std::vector<double> out;
  const double step = integer ? 1.0 : 0.0;
  if (std::isfinite(r.lo)) out.push_back(r.lo_open ? r.lo : r.lo - (integer ? step : 1e-6));
  if (std::isfinite(r.hi)) out.push_back(r.hi_open ? r.hi : r.hi + (integer ? step : 1e-6));
  return out;
}

template <class S>
double member_si(const S& s, const Field<S>& f) {
  if (const auto* d = std::get_if<double S::*>(&f.member)) return s.**d;
  if (const auto* i = std::get_if<int S::*>(&f.member)) return s.**i;
  return s.*std::get<bool S::*>(f.member) ? 1.0 : 0.0;
}

// Every field of `list` that `section_name` has as a key, checked against the library.
// `at` finds the struct in a Case; `base` is a case that has the table.
template <class S>
void expect_section_follows_library(std::string_view section_name,
                                    std::span<const Field<S>> list, S* (*at)(Case&),
                                    const Case& base, int expected_keys) {
  const detail::Section* section = detail::find_section(section_name, false);
  ASSERT_NE(section, nullptr) << section_name;
  const nlohmann::json schema = case_schema()[std::string(section_name)]["keys"];
  const std::string table = detail::key_table_markdown(*section);
  int seen = 0;
  for (const Field<S>& lib : list) {
    const detail::Field* io = section->find(lib.key);
    if (io == nullptr) continue;  // a library option the case file does not expose
    ++seen;
    const std::string key = std::string(section_name) + "." + std::string(lib.key);
    const bool integer = lib.type == FieldType::kInteger;
    SCOPED_TRACE(key);
    // The reader's row is the library's.
    EXPECT_EQ(io->unit.text, lib.unit.text);
    EXPECT_EQ(io->label, lib.label);
    EXPECT_EQ(io->meaning, lib.meaning);
    EXPECT_EQ(io->type == detail::Type::kInteger, integer);
    EXPECT_EQ(io->type == detail::Type::kBoolean, lib.type == FieldType::kBoolean);
    EXPECT_EQ(io->range.lo, lib.range.lo);
    EXPECT_EQ(io->range.hi, lib.range.hi);
    EXPECT_EQ(io->range.lo_open, lib.range.lo_open);
    EXPECT_EQ(io->range.hi_open, lib.range.hi_open);
    // The schema and the docs' table show the library's unit and range.
    ASSERT_TRUE(schema.contains(std::string(lib.key)));
    EXPECT_EQ(schema[std::string(lib.key)]["unit"], std::string(lib.unit.text));
    const std::string doc_range = lib.range.doc(integer);
    EXPECT_THAT(schema[std::string(lib.key)]["rule"].get<std::string>(), HasSubstr(doc_range));
    const std::string row = "| `" + std::string(lib.key) + "` |";
    const auto at_row = table.find(row);
    ASSERT_NE(at_row, std::string::npos);
    const std::string line = table.substr(at_row, table.find('\n', at_row) - at_row);
    EXPECT_THAT(line, HasSubstr(" " + std::string(lib.unit.text) + " "));
    EXPECT_THAT(line, HasSubstr(doc_range));
    if (lib.type == FieldType::kBoolean) continue;

    // A value in range reaches the struct in SI and is echoed in the user's unit: 10 % above
    // the case's own (so that rules joining keys still hold), else one inside the range.
    Case copy = base;
    double good = 1.1 * lib.user_value(*at(copy));
    if (integer) good = std::round(good);
    if (!lib.range.contains(good) || good == lib.user_value(*at(copy)))
      good = inside(lib.range, integer);
    Case c = with_value(base, key, good);
    EXPECT_DOUBLE_EQ(member_si(*at(c), lib), integer ? good : lib.unit.to_si(good));
    EXPECT_DOUBLE_EQ(to_json(c)[std::string(section_name)][std::string(lib.key)].get<double>(),
                     good);
    S s = *at(c);
    for (const std::string& p : s.validate()) EXPECT_THAT(p, ::testing::Not(HasSubstr(lib.key)));

    // A value out of range is refused by the reader and by validate(), naming the key.
    for (double bad : outside(lib.range, integer)) {
      SCOPED_TRACE(bad);
      try {
        (void)with_value(base, key, bad);
        ADD_FAILURE() << "reader took " << key << " = " << bad;
      } catch (const InvalidInput& e) {
        ASSERT_FALSE(e.problems().empty());
        EXPECT_THAT(e.problems().front(), HasSubstr(key + " = "));
      }
      S t = *at(c);
      lib.set_user_value(t, bad);
      bool named = false;
      for (const std::string& p : t.validate())
        named = named || p.rfind(std::string(lib.key) + " = ", 0) == 0;
      EXPECT_TRUE(named) << "validate() let " << lib.key << " = " << bad << " pass";
    }
  }
  EXPECT_EQ(seen, expected_keys) << section_name << ": keys taken from the library's list";
}

LobesOptions* lobes_grid(Case& c) { return &c.lobes.grid; }

TEST(LibraryFields, LobesGridKeysAreTheLibrarysEverywhere) {
  const Case c = load_example("milling-insperger");
  expect_section_follows_library<LobesOptions>("lobes", LobesOptions::fields(), lobes_grid, c, 5);
}

// Keys several library structs share (stability/method.hpp): the [lobes] row is the spec's,
// the schema and the docs show its unit and range, and the reader, the milling options, the
// turning options and the multi-frequency options refuse the same values and take the same
// ones (one range for the key everywhere).
TEST(LibraryFields, SharedStabilityKeysHaveOneRangeEverywhere) {
  const detail::Section* lobes = detail::find_section("lobes", false);
  ASSERT_NE(lobes, nullptr);
  const nlohmann::json schema = case_schema()["lobes"]["keys"];
  const std::string table = detail::key_table_markdown(*lobes);
  const Case base = load_example("milling-insperger");
  for (const FieldSpec* spec : {&stability_fields::kDepthMax, &stability_fields::kHarmonics}) {
    const std::string key = "lobes." + std::string(spec->key);
    SCOPED_TRACE(key);
    const bool integer = spec->type == FieldType::kInteger;
    const detail::Field* io = lobes->find(spec->key);
    ASSERT_NE(io, nullptr);
    EXPECT_EQ(io->unit.text, spec->unit.text);
    EXPECT_EQ(io->label, spec->label);
    EXPECT_EQ(io->meaning, spec->meaning);
    EXPECT_EQ(io->type == detail::Type::kInteger, integer);
    EXPECT_EQ(io->range.lo, spec->range.lo);
    EXPECT_EQ(io->range.hi, spec->range.hi);
    EXPECT_EQ(io->range.lo_open, spec->range.lo_open);
    EXPECT_EQ(io->range.hi_open, spec->range.hi_open);
    EXPECT_EQ(schema[std::string(spec->key)]["unit"], std::string(spec->unit.text));
    EXPECT_THAT(schema[std::string(spec->key)]["rule"].get<std::string>(),
                HasSubstr(spec->range.doc(integer)));
    EXPECT_THAT(table, HasSubstr("| `" + std::string(spec->key) + "` |"));

    const auto named = [&](const std::vector<std::string>& problems) {
      for (const std::string& p : problems)
        if (p.rfind(std::string(spec->key) + " = ", 0) == 0) return true;
      return false;
    };
    for (double v : {inside(spec->range, integer), spec->range.hi}) {
      SCOPED_TRACE(v);
      const Case c = with_value(base, key, v);  // the reader takes it
      MillingStabilityOptions mo;
      TurningStabilityOptions to;
      MultiFrequencyOptions fo;
      if (spec == &stability_fields::kDepthMax) {
        mo.depth_max_m = to.depth_max_m = spec->unit.to_si(v);
        EXPECT_DOUBLE_EQ(c.lobes.depth_max_m, spec->unit.to_si(v));
      } else {
        mo.harmonics = to.harmonics = fo.harmonics = static_cast<int>(v);
        EXPECT_EQ(c.lobes.harmonics, static_cast<int>(v));
      }
      EXPECT_FALSE(named(mo.validate()));
      EXPECT_FALSE(named(to.validate()));
      EXPECT_FALSE(named(fo.validate()));
    }
    for (double bad : outside(spec->range, integer)) {
      SCOPED_TRACE(bad);
      EXPECT_THROW((void)with_value(base, key, bad), InvalidInput);
      MillingStabilityOptions mo;
      TurningStabilityOptions to;
      MultiFrequencyOptions fo;
      if (spec == &stability_fields::kDepthMax) {
        mo.depth_max_m = to.depth_max_m = spec->unit.to_si(bad);
      } else {
        mo.harmonics = to.harmonics = fo.harmonics = static_cast<int>(bad);
        EXPECT_TRUE(named(fo.validate()));
      }
      EXPECT_TRUE(named(mo.validate()));
      EXPECT_TRUE(named(to.validate()));
    }
  }
}

// Each field's own range and the struct's validate(): a value at each end of the range
// passes, one beyond fails, and the message is in the user's unit.
TEST(LibraryFields, ValidateWalksTheFieldList) {
  for (const Field<LobesOptions>& f : LobesOptions::fields()) {
    if (f.type == FieldType::kBoolean) continue;
    SCOPED_TRACE(std::string(f.key));
    const bool integer = f.type == FieldType::kInteger;
    for (double bad : outside(f.range, integer)) {
      LobesOptions o;
      o.refine = false;  // the joint rule refine_max_points >= rpm_steps out of the way
      f.set_user_value(o, bad);
      const auto problems = o.validate();
      ASSERT_FALSE(problems.empty()) << bad;
      EXPECT_THAT(problems.front(), HasSubstr(std::string(f.key) + " = " + format_value(bad)));
      EXPECT_THAT(problems.front(), HasSubstr(f.range.rule()));
    }
  }
  LobesOptions o;
  EXPECT_TRUE(o.validate().empty());
  o.rpm_max = o.rpm_min;
  EXPECT_THAT(o.validate(), ::testing::ElementsAre(HasSubstr("must be greater than rpm_min")));
}

}  // namespace
}  // namespace cutdyn::io
