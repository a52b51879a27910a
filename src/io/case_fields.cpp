// The field tables of the case file (case_fields.hpp) and the doc tables made from them.
#include "case_fields.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <span>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/drive/equivalent_current.hpp"

namespace cutdyn::io::detail {

bool Field::used_in(Process process) const {
  if (uses == Uses::kBoth) return true;
  return (uses == Uses::kTurning) == (process == Process::kTurning);
}

const Field* Section::find(std::string_view key) const {
  for (const Field& f : fields)
    if (f.key == key) return &f;
  return nullptr;
}

const Alias* Section::alias(std::string_view key, Process process) const {
  for (const Alias& a : aliases)
    if (a.key == key &&
        (a.uses == Uses::kBoth || (a.uses == Uses::kTurning) == (process == Process::kTurning)))
      return &a;
  return nullptr;
}

std::string key_text(std::string_view key) {
  const bool bare = !key.empty() && std::all_of(key.begin(), key.end(), [](char ch) {
    return (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') ||
           ch == '_' || ch == '-';
  });
  if (bare) return std::string(key);
  std::string quoted = "\"";
  for (char ch : key) {
    if (ch == '"' || ch == '\\') quoted += '\\';
    quoted += ch;
  }
  return quoted + "\"";
}

double tidy_number(double value) {
  if (!std::isfinite(value)) return value;
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.15g", value);
  return std::strtod(buffer, nullptr);
}

std::string value_text(const Field& field, const Value& value) {
  if (const double* v = std::get_if<double>(&value))
    return number_text(tidy_number(field.unit.from_si(*v)));
  if (const bool* b = std::get_if<bool>(&value)) return *b ? "true" : "false";
  if (const std::string* s = std::get_if<std::string>(&value)) return "\"" + *s + "\"";
  std::string text = "[";
  for (double v : std::get<std::vector<double>>(value)) {
    if (text.size() > 1) text += ", ";
    text += number_text(tidy_number(field.unit.from_si(v)));
  }
  return text + "]";
}

namespace {

// ---- units -------------------------------------------------------------------------------

double n_per_mm_to_n_per_m(double v) { return 1e3 * v; }
double n_per_m_to_n_per_mm(double v) { return 1e-3 * v; }
double mpa_to_pa(double v) { return v * 1e6; }
double pa_to_mpa(double v) { return v / 1e6; }
double per_min_to_per_s(double v) { return v / 60.0; }
double per_s_to_per_min(double v) { return 60.0 * v; }

using fields::kNone;
using fields::unit;
constexpr Unit kMm{"mm", units::mm_to_m, units::m_to_mm};
constexpr Unit kUm{"µm", units::um_to_m, units::m_to_um};
constexpr Unit kDeg{"deg", units::deg_to_rad, units::rad_to_deg};
constexpr Unit kNPerMm2{"N/mm²", units::n_per_mm2_to_pa, units::pa_to_n_per_mm2};
constexpr Unit kNPerMm{"N/mm", n_per_mm_to_n_per_m, n_per_m_to_n_per_mm};
constexpr Unit kMPerMin{"m/min", units::m_per_min_to_m_per_s, units::m_per_s_to_m_per_min};
constexpr Unit kHzAsRadPerS{"Hz", units::hz_to_rad_per_s, units::rad_per_s_to_hz};
constexpr Unit kMpa{"MPa", mpa_to_pa, pa_to_mpa};
constexpr Unit kPlanMPerMin{"m/min", per_min_to_per_s, per_s_to_per_min};
constexpr Unit kRpmAsRevPerS{"rpm", per_min_to_per_s, per_s_to_per_min};
constexpr Unit kCelsius = unit("°C");

constexpr Range kAny = Range::any();
constexpr Range kPositive = Range::positive();
constexpr Range kNonNegative = Range::non_negative();
constexpr Range open_closed(double lo, double hi) { return Range::open_closed(lo, hi); }
constexpr Range closed_open(double lo, double hi) { return Range::closed_open(lo, hi); }
constexpr Range open(double lo, double hi) { return Range::open(lo, hi); }
constexpr Range closed(double lo, double hi) { return Range::closed(lo, hi); }

// ---- building rows -----------------------------------------------------------------------

template <class T>
struct IsOptional : std::false_type {};
template <class T>
struct IsOptional<std::optional<T>> : std::true_type {};

// Where a section's struct is in the Case (element `index` of an array); nullptr when absent.
template <class S>
using Locate = S* (*)(Case&, std::size_t);

class Row {
 public:
  Row(std::string_view key, Type type, Unit u = kNone, Range range = kAny) {
    f_.key = key;
    f_.type = type;
    f_.unit = u;
    f_.range = range;
  }
  Row& required() {
    f_.required = true;
    return *this;
  }
  Row& required_if(Predicate p) {
    f_.required_if = std::move(p);
    return *this;
  }
  Row& uses(Uses u) {
    f_.uses = u;
    return *this;
  }
  Row& no_echo() {
    f_.echo = false;
    return *this;
  }
  Row& echo_if(Predicate p) {
    f_.echo_if = std::move(p);
    return *this;
  }
  Row& size(int n) {
    f_.array_size = n;
    return *this;
  }
  Row& choices(std::initializer_list<std::string_view> names) {
    f_.choices = names;
    return *this;
  }
  Row& deflt(std::string_view text) {
    f_.default_doc = text;
    return *this;
  }
  Row& process(std::string_view text) {
    f_.process_doc = text;
    return *this;
  }
  Row& label(std::string_view text) {
    f_.label = text;
    return *this;
  }
  Row& meaning(std::string_view text) {
    f_.meaning = text;
    return *this;
  }
  Row& access(Getter get, Setter set) {
    f_.get = std::move(get);
    f_.set = std::move(set);
    return *this;
  }
  // The Case member: double, int, unsigned, bool or std::optional<double>.
  template <class S, class M>
  Row& member(Locate<S> at, M S::*m, std::string_view absent = "its table is absent") {
    f_.get = [at, m](const Case& c, std::size_t i) -> std::optional<Value> {
      const S* s = at(const_cast<Case&>(c), i);
      if (s == nullptr) return std::nullopt;
      const M& v = s->*m;
      if constexpr (IsOptional<M>::value) {
        if (!v) return std::nullopt;
        return Value(static_cast<double>(*v));
      } else if constexpr (std::is_same_v<M, bool>) {
        return Value(v);
      } else {
        return Value(static_cast<double>(v));
      }
    };
    f_.set = [at, m, absent](Case& c, std::size_t i, const Value& v) -> std::string {
      S* s = at(c, i);
      if (s == nullptr) return std::string(absent);
      if constexpr (IsOptional<M>::value) {
        s->*m = std::get<double>(v);
      } else if constexpr (std::is_same_v<M, bool>) {
        s->*m = std::get<bool>(v);
      } else {
        s->*m = static_cast<M>(std::get<double>(v));
      }
      return {};
    };
    return *this;
  }
  // A row from a library struct's field list (core/fields.hpp): its key, unit, range, label
  // and meaning as the library spells them, the member reached through `at`.
  // `echo_default`: the echo writes the key at its default too (false for a key added after
  // outputs that echo the case were published: they stay the same unless the key is set).
  template <class S>
  static Row field(std::span<const cutdyn::Field<S>> list, std::string_view key, Locate<S> at,
                   bool echo_default = true) {
    const cutdyn::Field<S>* lib = find_field(list, key);
    if (lib == nullptr) throw std::logic_error("no library field " + std::string(key));
    Row r = spec({lib->key, lib->type, lib->unit, lib->range, lib->label, lib->meaning});
    std::visit([&](auto member) { r.member(at, member); }, lib->member);
    if (!echo_default) {
      r.echo_if([at, f = *lib](const Case& c, std::size_t i) {
        const S* s = at(const_cast<Case&>(c), i);
        return s != nullptr && f.user_value(*s) != f.user_value(S{});
      });
    }
    return r;
  }
  // A row from a key the library spells once for several structs (FieldSpec); the Case
  // member is given with member() or access().
  static Row spec(const FieldSpec& lib) {
    const Type type = lib.type == FieldType::kInteger   ? Type::kInteger
                      : lib.type == FieldType::kBoolean ? Type::kBoolean
                                                        : Type::kNumber;
    Row r(lib.key, type, lib.unit, lib.range);
    r.label(lib.label).meaning(lib.meaning);
    return r;
  }
  operator Field() const { return f_; }  // NOLINT: rows are written as fields

 private:
  Field f_;
};

Row number(std::string_view key, Unit u, Range range) { return Row(key, Type::kNumber, u, range); }
Row integer(std::string_view key, int lo, int hi) {
  return Row(key, Type::kInteger, kNone, closed(lo, hi));
}
Row boolean(std::string_view key) { return Row(key, Type::kBoolean); }
Row choice(std::string_view key, std::initializer_list<std::string_view> names) {
  Row r(key, Type::kChoice);
  r.choices(names);
  return r;
}

const std::string& text_of(const Value& v) { return std::get<std::string>(v); }

// ---- where each section is in the Case -------------------------------------------------

Case* whole(Case& c, std::size_t) { return &c; }
Mode* mode(Case& c, std::size_t i) {
  return i < c.modal.modes.size() ? &c.modal.modes[i] : nullptr;
}
CuttingSection* cutting(Case& c, std::size_t) { return &c.cutting; }
MillingTool* tool(Case& c, std::size_t) { return c.tool ? &*c.tool : nullptr; }
OperationSection* operation(Case& c, std::size_t) { return c.operation ? &*c.operation : nullptr; }
MillingEngagement* engagement(Case& c, std::size_t) {
  return c.operation ? &c.operation->engagement : nullptr;
}
VibrationAssist* vibration(Case& c, std::size_t) { return c.vibration ? &*c.vibration : nullptr; }
ErmolaevForceLaw* force_law(Case& c, std::size_t) { return c.force_law ? &*c.force_law : nullptr; }
LobesSection* lobes(Case& c, std::size_t) { return &c.lobes; }
LobesOptions* lobes_grid(Case& c, std::size_t) { return &c.lobes.grid; }
Row lobes_row(std::string_view key, bool echo_default = true) {
  return Row::field(LobesOptions::fields(), key, lobes_grid, echo_default);
}
SimulateSection* simulate(Case& c, std::size_t) { return &c.simulate; }
JohnsonCook* johnson_cook(Case& c, std::size_t) { return c.material ? &c.material->flow : nullptr; }
ThermalProperties* thermal(Case& c, std::size_t) {
  return c.material ? &c.material->thermal : nullptr;
}
OxleyOptions* oxley(Case& c, std::size_t) { return &c.oxley; }
Transmission* transmission(Case& c, std::size_t i) {
  return i < c.drives.size() ? &c.drives[i].drive.transmission : nullptr;
}
FeedDrive* drive(Case& c, std::size_t i) {
  return i < c.drives.size() ? &c.drives[i].drive : nullptr;
}
PmsmMotor* motor(Case& c, std::size_t i) {
  return i < c.drives.size() && c.drives[i].motor ? &*c.drives[i].motor : nullptr;
}
BoreMillingCase* bore(Case& c, std::size_t) { return c.bore ? &*c.bore : nullptr; }
BoreMillingLimits* limits(Case& c, std::size_t) {
  return c.bore_limits ? &*c.bore_limits : nullptr;
}

constexpr std::string_view kNeedsMotor = "needs the motor: pole_pairs and torque_constant_nm_per_a";

bool is_lever(const Case& c, std::size_t i) {
  return i < c.drives.size() &&
         c.drives[i].drive.transmission.kind == Transmission::Kind::kLeverArm;
}
bool is_dynamic(const Case& c, std::size_t i) {
  return i < c.drives.size() && c.drives[i].drive.model == FeedDrive::Model::kDynamic;
}
bool has_motor(const Case& c, std::size_t i) { return i < c.drives.size() && c.drives[i].motor; }

// The stiffness of a mode given by its mass follows the natural frequency.
void refresh_mass_mode(Case& c, std::size_t i) {
  if (i < c.mode_mass_kg.size() && c.mode_mass_kg[i] && i < c.modal.modes.size()) {
    Mode& m = c.modal.modes[i];
    m.stiffness_n_per_m = mode_from_mass(m.direction, m.natural_rad_s, m.damping_ratio,
                                         *c.mode_mass_kg[i]).stiffness_n_per_m;
  }
}

std::function<std::size_t(const Case&)> always() {
  return [](const Case&) -> std::size_t { return 1; };
}
template <class T>
std::function<std::size_t(const Case&)> if_present(std::optional<T> Case::*m) {
  return [m](const Case& c) -> std::size_t { return (c.*m).has_value() ? 1 : 0; };
}
template <class T>
std::function<std::string(Case&)> emplace(std::optional<T> Case::*m) {
  return [m](Case& c) -> std::string {
    (c.*m).emplace();
    return {};
  };
}
std::function<std::string(Case&)> refuse(std::string_view why) {
  return [why](Case&) { return std::string(why); };
}

// ---- the tables ----------------------------------------------------------------------------

Section top_level_section() {
  Section top;
  top.name = "";
  top.subtables = {"modes",    "cutting",   "tool",   "operation", "vibration", "lobes",
                   "simulate", "force_law", "drives", "material",  "oxley",     "frf"};
  top.fields = {choice("process", {"turning", "milling"})
                    .access(
                        [](const Case& c, std::size_t) -> std::optional<Value> {
                          return Value(std::string(to_string(c.process)));
                        },
                        [](Case& c, std::size_t, const Value& v) -> std::string {
                          c.process =
                              text_of(v) == "turning" ? Process::kTurning : Process::kMilling;
                          return {};
                        }),
                number("spindle_max_rpm", unit("rpm"), kPositive)
                    .label("spindle speed limit")
                    .deflt("60000")
                    .meaning("the fastest the spindle turns: a speed asked above it (`--rpm`, "
                             "`[lobes] rpm_max`, `[simulate] rpm`) is warned about")
                    .echo_if([](const Case& c, std::size_t) {
                      return c.spindle_max_rpm != kDefaultSpindleMaxRpm;
                    })
                    .member(whole, &Case::spindle_max_rpm)};
  top.count = always();
  top.create = refuse("");
  return top;
}

Section modes_section() {
  Section modes;
  modes.name = "modes";
  modes.array = true;
  modes.fields = {
      choice("direction", {"x", "y"})
          .required()
          .meaning("turning models the feed direction `\"x\"` only")
          .access(
              [](const Case& c, std::size_t i) -> std::optional<Value> {
                if (i >= c.modal.modes.size()) return std::nullopt;
                return Value(std::string(c.modal.modes[i].direction == Direction::kX ? "x" : "y"));
              },
              [](Case& c, std::size_t i, const Value& v) -> std::string {
                c.modal.modes.at(i).direction = text_of(v) == "x" ? Direction::kX : Direction::kY;
                return {};
              }),
      number("natural_hz", kHzAsRadPerS, kPositive)
          .label("natural frequency")
          .required()
          .access(
              [](const Case& c, std::size_t i) -> std::optional<Value> {
                if (i >= c.modal.modes.size()) return std::nullopt;
                return Value(c.modal.modes[i].natural_rad_s);
              },
              [](Case& c, std::size_t i, const Value& v) -> std::string {
                c.modal.modes.at(i).natural_rad_s = std::get<double>(v);
                refresh_mass_mode(c, i);
                return {};
              }),
      number("damping_ratio", kNone, closed_open(0.0, 1.0))
          .label("damping ratio ζ")
          .required()
          .access(
              [](const Case& c, std::size_t i) -> std::optional<Value> {
                if (i >= c.modal.modes.size()) return std::nullopt;
                return Value(c.modal.modes[i].damping_ratio);
              },
              [](Case& c, std::size_t i, const Value& v) -> std::string {
                c.modal.modes.at(i).damping_ratio = std::get<double>(v);
                refresh_mass_mode(c, i);
                return {};
              }),
      number("stiffness_n_per_m", unit("N/m"), kPositive)
          .label("modal stiffness")
          .deflt("one of the two")
          .member(mode, &Mode::stiffness_n_per_m),
      number("residue_phase_deg", kDeg, open(-90.0, 90.0))
          .label("residue phase φ")
          .meaning("phase of the mode's residue from a real mode's: a non-proportionally "
                   "damped mode as `cutdyn fit` finds it in a measured FRF "
                   "(docs/models/modal-fitting.md §10)")
          .echo_if([](const Case& c, std::size_t i) {
            return i < c.modal.modes.size() && c.modal.modes[i].residue_phase_rad != 0.0;
          })
          .member(mode, &Mode::residue_phase_rad),
      number("mass_kg", unit("kg"), kPositive)
          .label("modal mass")
          .deflt("one of the two")
          .meaning("stiffness k = m·(2π·natural_hz)²")
          .no_echo()
          .access(
              [](const Case& c, std::size_t i) -> std::optional<Value> {
                if (i >= c.mode_mass_kg.size() || !c.mode_mass_kg[i]) return std::nullopt;
                return Value(*c.mode_mass_kg[i]);
              },
              [](Case& c, std::size_t i, const Value& v) -> std::string {
                if (c.mode_mass_kg.size() <= i) c.mode_mass_kg.resize(i + 1);
                c.mode_mass_kg[i] = std::get<double>(v);
                refresh_mass_mode(c, i);
                return {};
              })};
  modes.count = [](const Case& c) { return c.modal.modes.size(); };
  modes.create = refuse("");
  return modes;
}

Section frf_section() {
  Section frf;
  frf.name = "frf";
  frf.array = true;
  const auto frf_text = [](std::string FrfTable::*member) {
    return [member](const Case& c, std::size_t i) -> std::optional<Value> {
      if (i >= c.frfs.size() || (c.frfs[i].*member).empty()) return std::nullopt;
      return Value(c.frfs[i].*member);
    };
  };
  const auto set_frf_text = [](std::string FrfTable::*member) {
    return [member](Case& c, std::size_t i, const Value& v) -> std::string {
      c.frfs.at(i).*member = text_of(v);
      return {};
    };
  };
  frf.fields = {
      choice("direction", {"x", "y", "xy"})
          .required()
          .meaning("the direct receptance in x (feed) or y, or the cross receptance `\"xy\"` "
                   "(taken equal to yx); tables of one direction add (tool and workpiece)")
          .access(frf_text(&FrfTable::direction), set_frf_text(&FrfTable::direction)),
      Row("file", Type::kText)
          .required()
          .meaning("the measured FRF, relative to the case file: CutPro text (`.frf`), CSV or "
                   "UFF 58/58b (docs/frf-files.md)")
          // Echoed as the file read (absolute for a case file's), so that the echo of a case
          // reads the same files from any folder.
          .access(
              [](const Case& c, std::size_t i) -> std::optional<Value> {
                if (i >= c.frfs.size() || c.frfs[i].file.empty()) return std::nullopt;
                const FrfTable& t = c.frfs[i];
                return Value(t.path.empty() ? t.file : t.path.string());
              },
              set_frf_text(&FrfTable::file)),
      choice("format", {"frf", "csv", "uff"})
          .deflt("from the content")
          .access(frf_text(&FrfTable::format), set_frf_text(&FrfTable::format)),
      integer("dataset", 0, 100000)
          .label("UFF dataset index")
          .deflt("the first FRF")
          .meaning("UFF: which dataset 58 of the file (0-based)")
          .access(
              [](const Case& c, std::size_t i) -> std::optional<Value> {
                if (i >= c.frfs.size() || !c.frfs[i].dataset) return std::nullopt;
                return Value(static_cast<double>(*c.frfs[i].dataset));
              },
              [](Case& c, std::size_t i, const Value& v) -> std::string {
                c.frfs.at(i).dataset = static_cast<int>(std::get<double>(v));
                return {};
              }),
      Row("units", Type::kText)
          .deflt("from the file's header, else Hz and m/N")
          .meaning("CutPro text: the file's units in place of its header's, an FRF unit "
                   "optionally after a frequency unit, e.g. `\"kHz, mm/N\"` "
                   "(docs/frf-files.md)")
          .access(frf_text(&FrfTable::units), set_frf_text(&FrfTable::units))};
  frf.count = [](const Case& c) { return c.frfs.size(); };
  frf.create = refuse("");
  return frf;
}

Section cutting_section() {
  Section cut;
  cut.name = "cutting";
  cut.process_column = true;
  cut.echo_empty = false;
  cut.fields = {
      number("kt_n_per_mm2", kNPerMm2, kPositive)
          .label("tangential cutting coefficient Kt")
          .uses(Uses::kMilling)
          .deflt("optional")
          .process("milling; turning: the old name of `kf_n_per_mm2` (a warning)")
          .meaning("tangential coefficient")
          .member(cutting, &CuttingSection::kt_pa),
      number("kf_n_per_mm2", kNPerMm2, kPositive)
          .label("feed-direction cutting coefficient Kf")
          .uses(Uses::kTurning)
          .deflt("optional")
          .meaning("feed-direction (thrust) coefficient")
          .member(cutting, &CuttingSection::kf_pa),
      number("kc_n_per_mm2", kNPerMm2, kPositive)
          .label("cutting-direction coefficient Kc")
          .uses(Uses::kTurning)
          .meaning("cutting-direction coefficient (`cutdyn force`)")
          .member(cutting, &CuttingSection::kc_pa),
      number("kr_n_per_mm2", kNPerMm2, kNonNegative)
          .label("radial cutting coefficient Kr")
          .uses(Uses::kMilling)
          .meaning("radial coefficient")
          .member(cutting, &CuttingSection::kr_pa),
      number("speed_m_per_min", kMPerMin, kPositive)
          .label("cutting speed")
          .uses(Uses::kTurning)
          .member(cutting, &CuttingSection::speed_m_per_s),
      number("uncut_chip_thickness_mm", kMm, kPositive)
          .label("feed per revolution")
          .uses(Uses::kTurning)
          .meaning("feed per revolution")
          .member(cutting, &CuttingSection::uncut_chip_thickness_m),
      number("width_mm", kMm, kPositive)
          .label("depth of cut")
          .uses(Uses::kTurning)
          .meaning("depth of cut")
          .member(cutting, &CuttingSection::width_m),
      number("kte_n_per_mm", kNPerMm, kNonNegative)
          .label("tangential edge coefficient Kte")
          .uses(Uses::kMilling)
          .deflt("0")
          .meaning("simulation: tangential edge coefficient (force per unit axial depth); not "
                   "with `[force_law]`")
          .member(cutting, &CuttingSection::kte_n_per_m),
      number("kre_n_per_mm", kNPerMm, kNonNegative)
          .label("radial edge coefficient Kre")
          .uses(Uses::kMilling)
          .deflt("0")
          .meaning("simulation: radial edge coefficient; not with `[force_law]`")
          .member(cutting, &CuttingSection::kre_n_per_m),
      number("rake_deg", kDeg, open(-45.0, 45.0))
          .label("rake angle")
          .uses(Uses::kTurning)
          .process("turning, with `[material]`")
          .deflt("required with `[material]`")
          .meaning("tool rake angle (Oxley)")
          .member(cutting, &CuttingSection::rake_rad),
      number("workpiece_temperature_c", kCelsius, Range::make(-273.15, true, kInf, true))
          .label("workpiece temperature")
          .uses(Uses::kTurning)
          .process("turning, with `[material]`")
          .deflt("the material's Johnson–Cook reference temperature")
          .meaning("and below melting; workpiece temperature before cutting (Oxley)")
          .member(cutting, &CuttingSection::workpiece_temperature_c)};
  cut.aliases = {{"kt_n_per_mm2", "kf_n_per_mm2", Uses::kTurning,
                  "in a turning case kt_n_per_mm2 is the old name of kf_n_per_mm2, the "
                  "feed-direction (thrust) coefficient; write kf_n_per_mm2 (in milling "
                  "kt_n_per_mm2 is the tangential coefficient)"}};
  cut.count = always();
  cut.create = refuse("");
  return cut;
}

Section material_section() {
  Section material;
  material.name = "material";
  material.subtables = {"johnson_cook", "thermal"};
  material.fields = {Row("name", Type::kText)
                         .deflt("required unless both sub-tables are given")
                         .meaning("a library entry, or your label")
                         .access(
                             [](const Case& c, std::size_t) -> std::optional<Value> {
                               if (!c.material) return std::nullopt;
                               return Value(c.material->name);
                             },
                             [](Case& c, std::size_t, const Value& v) -> std::string {
                               if (!c.material) return "its table is absent";
                               c.material->name = text_of(v);
                               return {};
                             })};
  material.count = if_present(&Case::material);
  material.create = refuse("the case has no [material] (give its name or both of its tables)");
  return material;
}

Section johnson_cook_section() {
  Section jc;
  jc.name = "material.johnson_cook";
  jc.fields = {number("a_mpa", kMpa, kPositive)
                   .label("Johnson–Cook yield stress A")
                   .required()
                   .member(johnson_cook, &JohnsonCook::a_pa),
               number("b_mpa", kMpa, kNonNegative)
                   .label("Johnson–Cook hardening modulus B")
                   .required()
                   .member(johnson_cook, &JohnsonCook::b_pa),
               number("n", kNone, closed_open(0.0, 1.0))
                   .label("Johnson–Cook hardening exponent n")
                   .required()
                   .member(johnson_cook, &JohnsonCook::n),
               number("c", kNone, closed_open(0.0, 1.0))
                   .label("Johnson–Cook strain-rate coefficient C")
                   .required()
                   .member(johnson_cook, &JohnsonCook::c),
               number("m", kNone, open_closed(0.0, 10.0))
                   .label("Johnson–Cook thermal exponent m")
                   .required()
                   .member(johnson_cook, &JohnsonCook::m),
               number("reference_strain_rate_per_s", unit("1/s"), kPositive)
                   .label("reference strain rate")
                   .member(johnson_cook, &JohnsonCook::reference_strain_rate_per_s),
               number("reference_temperature_c", kCelsius, Range::make(-273.15, true, kInf, true))
                   .label("reference temperature")
                   .member(johnson_cook, &JohnsonCook::reference_temperature_c),
               number("melting_temperature_c", kCelsius, Range::make(-273.15, true, kInf, true))
                   .label("melting temperature")
                   .required()
                   .meaning("above the reference temperature")
                   .member(johnson_cook, &JohnsonCook::melting_temperature_c)};
  jc.count = if_present(&Case::material);
  jc.create = refuse("the case has no [material] (give its name or both of its tables)");
  return jc;
}

Section thermal_section() {
  Section th;
  th.name = "material.thermal";
  th.fields = {number("density_kg_per_m3", unit("kg/m³"), kPositive)
                   .label("work-material density")
                   .required()
                   .member(thermal, &ThermalProperties::density_kg_per_m3),
               number("specific_heat_j_per_kg_k", unit("J/(kg·K)"), kPositive)
                   .label("specific heat")
                   .required()
                   .meaning("S0")
                   .member(thermal, &ThermalProperties::specific_heat_j_per_kg_k),
               number("specific_heat_slope_j_per_kg_k2", unit("J/(kg·K²)"), kAny)
                   .label("specific-heat slope")
                   .meaning("S1; S(T) > 0 from Tr to Tm")
                   .member(thermal, &ThermalProperties::specific_heat_slope_j_per_kg_k2),
               number("conductivity_w_per_m_k", unit("W/(m·K)"), kPositive)
                   .label("thermal conductivity")
                   .required()
                   .meaning("K0")
                   .member(thermal, &ThermalProperties::conductivity_w_per_m_k),
               number("conductivity_slope_w_per_m_k2", unit("W/(m·K²)"), kAny)
                   .label("conductivity slope")
                   .meaning("K1; K(T) > 0 from Tr to Tm")
                   .member(thermal, &ThermalProperties::conductivity_slope_w_per_m_k2)};
  th.count = if_present(&Case::material);
  th.create = refuse("the case has no [material] (give its name or both of its tables)");
  return th;
}

Section oxley_section() {
  Section ox;
  ox.name = "oxley";
  ox.fields = {number("c0_min", kNone, kPositive)
                   .label("smallest strain-rate constant C0")
                   .meaning("less than `c0_max`: range of the strain-rate constant C0")
                   .member(oxley, &OxleyOptions::c0_min),
               number("c0_max", kNone, kPositive)
                   .label("largest strain-rate constant C0")
                   .member(oxley, &OxleyOptions::c0_max),
               number("delta_min", kNone, open(0.0, 1.0))
                   .label("smallest δ")
                   .meaning("less than `delta_max`: range of δ")
                   .member(oxley, &OxleyOptions::delta_min),
               number("delta_max", kNone, open(0.0, 1.0))
                   .label("largest δ")
                   .member(oxley, &OxleyOptions::delta_max),
               number("eta", kNone, open_closed(0.0, 1.0))
                   .label("shear-plane temperature factor η")
                   .meaning("shear-plane temperature factor η")
                   .member(oxley, &OxleyOptions::eta),
               number("psi", kNone, open_closed(0.0, 1.0))
                   .label("interface temperature factor ψ")
                   .meaning("interface temperature factor ψ")
                   .member(oxley, &OxleyOptions::psi)};
  ox.count = [](const Case& c) -> std::size_t { return c.material ? 1 : 0; };
  ox.create = refuse("used only with a [material] (the settings of Oxley's theory)");
  return ox;
}

Section tool_section() {
  Section tl;
  tl.name = "tool";
  tl.fields = {integer("teeth", 1, 200)
                   .label("number of teeth")
                   .required()
                   .member(tool, &MillingTool::teeth),
               number("diameter_mm", kMm, kPositive)
                   .label("cutter diameter")
                   .required()
                   .member(tool, &MillingTool::diameter_m),
               number("helix_deg", kDeg, closed_open(0.0, 90.0))
                   .label("helix angle")
                   .meaning("with a helix the stability methods cut the flute into axial slices "
                            "(docs/models/milling-stability.md)")
                   .member(tool, &MillingTool::helix_rad),
               Row("pitch_deg", Type::kNumbers, kDeg, open(0.0, 360.0))
                   .deflt("even pitch")
                   .meaning("one angle per tooth, adding up to 360: `pitch_deg[j]` is the angle by "
                            "which tooth j trails tooth j − 1 (uneven pitch)")
                   .access(
                       [](const Case& c, std::size_t) -> std::optional<Value> {
                         if (!c.tool || c.tool->pitch_rad.empty()) return std::nullopt;
                         return Value(c.tool->pitch_rad);
                       },
                       [](Case& c, std::size_t, const Value& v) -> std::string {
                         if (!c.tool) return "its table is absent";
                         const auto& p = std::get<std::vector<double>>(v);
                         const int teeth = c.tool->teeth;
                         double sum = 0.0;
                         for (double x : p) sum += units::rad_to_deg(x);
                         if (static_cast<int>(p.size()) != teeth && teeth > 0)
                           return "must give one angle per tooth (teeth = " +
                                  std::to_string(teeth) + "), got " + std::to_string(p.size());
                         if (std::abs(sum - 360.0) > 1e-6)
                           return "the angles must add up to 360, they add up to " +
                                  format_value(tidy_number(sum));
                         // Exactly one revolution, whatever the rounding of the degrees.
                         double total = 0.0;
                         for (double x : p) total += x;
                         const double scale = units::kTwoPi / total;
                         c.tool->pitch_rad = p;
                         for (double& x : c.tool->pitch_rad) x *= scale;
                         return {};
                       })};
  tl.count = if_present(&Case::tool);
  tl.create = emplace(&Case::tool);
  return tl;
}

Section operation_section() {
  Section op;
  op.name = "operation";
  op.fields = {
      number("radial_immersion", unit("– (a_e/D)"), open_closed(0.0, 1.0))
          .label("radial immersion a_e/D")
          .member(engagement, &MillingEngagement::radial_immersion),
      choice("direction", {"down", "up"})
          .access(
              [](const Case& c, std::size_t) -> std::optional<Value> {
                if (!c.operation) return std::nullopt;
                return Value(std::string(c.operation->engagement.down_milling ? "down" : "up"));
              },
              [](Case& c, std::size_t, const Value& v) -> std::string {
                if (!c.operation) return "its table is absent";
                c.operation->engagement.down_milling = text_of(v) == "down";
                return {};
              }),
      number("feed_per_tooth_mm", kMm, kPositive)
          .label("feed per tooth")
          .deflt("required by `cutdyn simulate`")
          .member(operation, &OperationSection::feed_per_tooth_m),
      number("entry_deg", kDeg, closed(0.0, 180.0))
          .label("entry angle")
          .deflt("from the immersion")
          .meaning("the engagement window itself (angles clockwise from +y), instead of "
                   "`radial_immersion` and `direction`; give both, entry < exit")
          .member(engagement, &MillingEngagement::entry_rad),
      number("exit_deg", kDeg, closed(0.0, 180.0))
          .label("exit angle")
          .deflt("from the immersion")
          .meaning("greater than `entry_deg`")
          .member(engagement, &MillingEngagement::exit_rad)};
  op.count = if_present(&Case::operation);
  op.create = emplace(&Case::operation);
  return op;
}

Section force_law_section() {
  Section fl;
  fl.name = "force_law";
  fl.fields = {number("c_n_per_mm", kNPerMm, kNonNegative)
                   .label("cutting stiffness c")
                   .required()
                   .meaning("cutting stiffness c of the engaged flute: P = c·U")
                   .member(force_law, &ErmolaevForceLaw::c_n_per_m),
               number("t2_s", unit("s"), kNonNegative)
                   .label("chip-formation time constant T2")
                   .meaning("chip-formation time constant T2 (T2·dU/dt + U = X)")
                   .member(force_law, &ErmolaevForceLaw::t2_s),
               number("t2_deg", kDeg, kNonNegative)
                   .label("chip-formation lag ω·T2")
                   .deflt("none (`t2_s`)")
                   .meaning("instead of `t2_s`: the cutter's rotation during T2, so that T2 "
                            "scales with the tooth's passage (T2 = ℓ/v)")
                   .member(force_law, &ErmolaevForceLaw::t2_angle_rad),
               number("p0_n", unit("N"), kNonNegative)
                   .label("flank contact force P0")
                   .meaning("flank contact force P0 (F = P0·e^(−X/T1))")
                   .member(force_law, &ErmolaevForceLaw::p0_n),
               number("t1_mm", kMm, kPositive)
                   .label("flank contact length T1")
                   .deflt("1000 (none)")
                   .meaning("T1")
                   .member(force_law, &ErmolaevForceLaw::t1_m),
               number("phi_rez_deg", kDeg, closed(-90.0, 90.0))
                   .label("cutting-force angle φrez")
                   .meaning("cutting force from the tangent (towards the centre)")
                   .member(force_law, &ErmolaevForceLaw::phi_rez_rad),
               number("phi_skv_deg", kDeg, closed(-90.0, 90.0))
                   .label("contact-force angle φskv")
                   .meaning("contact force from the tangent")
                   .member(force_law, &ErmolaevForceLaw::phi_skv_rad),
               choice("lag_input", {"chip", "unwindowed"})
                   .deflt("\"chip\"")
                   .meaning("what U lags: the chip while the tooth cuts (`\"chip\"`), or "
                            "s_z·sin θ around the whole revolution, windowed after the lag "
                            "(`\"unwindowed\"`, [Ermolaev2020] eqs. 3 and 5 as printed)")
                   .access(
                       [](const Case& c, std::size_t) -> std::optional<Value> {
                         if (!c.force_law) return std::nullopt;
                         return Value(std::string(c.force_law->lag_input ==
                                                          ErmolaevForceLaw::LagInput::kUnwindowed
                                                      ? "unwindowed"
                                                      : "chip"));
                       },
                       [](Case& c, std::size_t, const Value& v) -> std::string {
                         if (!c.force_law) return "its table is absent";
                         c.force_law->lag_input = text_of(v) == "unwindowed"
                                                      ? ErmolaevForceLaw::LagInput::kUnwindowed
                                                      : ErmolaevForceLaw::LagInput::kChip;
                         return {};
                       })};
  fl.count = if_present(&Case::force_law);
  fl.create = emplace(&Case::force_law);
  return fl;
}

// [[drives]]: the axis and its transmission.
std::vector<Field> drive_axis_fields() {
  return {
      choice("axis", {"x", "y", "z"})
          .deflt("`axis` or `direction`")
          .meaning("the feed is `\"x\"`")
          .no_echo()
          .access(
              [](const Case& c, std::size_t i) -> std::optional<Value> {
                if (i >= c.drives.size()) return std::nullopt;
                return Value(c.drives[i].name);
              },
              [](Case& c, std::size_t i, const Value& v) -> std::string {
                FeedAxis& a = c.drives.at(i);
                a.name = text_of(v);
                for (int k = 0; k < 3; ++k) a.direction[k] = k == a.name[0] - 'x' ? 1.0 : 0.0;
                return {};
              }),
      Row("direction", Type::kNumbers)
          .size(3)
          .deflt("`axis` or `direction`")
          .meaning("not all zero; normalised")
          .access(
              [](const Case& c, std::size_t i) -> std::optional<Value> {
                if (i >= c.drives.size()) return std::nullopt;
                const double* d = c.drives[i].direction;
                return Value(std::vector<double>{d[0], d[1], d[2]});
              },
              [](Case& c, std::size_t i, const Value& v) -> std::string {
                const auto& d = std::get<std::vector<double>>(v);
                const double norm = d.size() == 3 ? std::hypot(d[0], d[1], d[2]) : 0.0;
                if (d.size() != 3 || !(norm > 0.0))
                  return "must be three numbers (x, y, z), not all zero";
                for (int k = 0; k < 3; ++k)
                  c.drives.at(i).direction[k] = d[static_cast<std::size_t>(k)] / norm;
                return {};
              }),
      choice("transmission", {"ball-screw", "lever"})
          .required()
          .access(
              [](const Case& c, std::size_t i) -> std::optional<Value> {
                if (i >= c.drives.size()) return std::nullopt;
                return Value(std::string(is_lever(c, i) ? "lever" : "ball-screw"));
              },
              [](Case& c, std::size_t i, const Value& v) -> std::string {
                c.drives.at(i).drive.transmission.kind = text_of(v) == "lever"
                                                             ? Transmission::Kind::kLeverArm
                                                             : Transmission::Kind::kBallScrew;
                return {};
              }),
      number("lead_mm", kMm, kPositive)
          .label("ball-screw lead")
          .required_if([](const Case& c, std::size_t i) { return !is_lever(c, i); })
          .echo_if([](const Case& c, std::size_t i) { return !is_lever(c, i); })
          .deflt("required for a ball screw")
          .member(transmission, &Transmission::lead_m),
      number("efficiency", kNone, open_closed(0.0, 1.0))
          .label("transmission efficiency")
          .echo_if([](const Case& c, std::size_t i) { return !is_lever(c, i); })
          .member(transmission, &Transmission::efficiency),
      number("gear_ratio", kNone, kPositive)
          .label("gear ratio")
          .echo_if([](const Case& c, std::size_t i) { return !is_lever(c, i); })
          .meaning("motor speed / screw speed")
          .member(transmission, &Transmission::gear_ratio),
      number("output_diameter_mm", kMm, kPositive)
          .label("lever output diameter")
          .required_if(is_lever)
          .echo_if(is_lever)
          .deflt("required for a lever")
          .meaning("d of eq. 12")
          .member(transmission, &Transmission::output_diameter_m),
      number("ratio", kNone, kPositive)
          .label("lever ratio iΣ")
          .echo_if(is_lever)
          .meaning("iΣ of eq. 12")
          .member(transmission, &Transmission::ratio),
      number("idle_torque_nm", unit("N·m"), kAny)
          .label("idle torque")
          .meaning("Mc0")
          .member(transmission, &Transmission::idle_torque_nm)};
}

// [[drives]]: the drive's dynamics and controller.
std::vector<Field> drive_dynamics_fields() {
  return {
      choice("model", {"static", "dynamic"})
          .meaning("static: eq. 13; dynamic: the PI loop")
          .access(
              [](const Case& c, std::size_t i) -> std::optional<Value> {
                if (i >= c.drives.size()) return std::nullopt;
                return Value(std::string(is_dynamic(c, i) ? "dynamic" : "static"));
              },
              [](Case& c, std::size_t i, const Value& v) -> std::string {
                c.drives.at(i).drive.model = text_of(v) == "dynamic" ? FeedDrive::Model::kDynamic
                                                                     : FeedDrive::Model::kStatic;
                return {};
              }),
      number(
          "stiffness_nm_s_per_rad", unit("N·m·s/rad"),
          {-kInf, true, kInf, true, true, "must not be 0 (|β|, the slope of the characteristic)"})
          .label("drive stiffness |β|")
          .required_if([](const Case& c, std::size_t i) { return !is_dynamic(c, i); })
          .echo_if([](const Case& c, std::size_t i) { return !is_dynamic(c, i); })
          .deflt("required for static")
          .meaning("β (its magnitude is used)")
          .member(drive, &FeedDrive::stiffness_nm_s_per_rad),
      number("inertia_kg_m2", unit("kg·m²"), kPositive)
          .label("drive inertia")
          .required_if(is_dynamic)
          .echo_if(is_dynamic)
          .deflt("required for dynamic")
          .meaning("motor + load at the motor")
          .member(drive, &FeedDrive::inertia_kg_m2),
      number("viscous_nm_s_per_rad", unit("N·m·s/rad"), kNonNegative)
          .label("viscous friction")
          .echo_if(is_dynamic)
          .member(drive, &FeedDrive::viscous_nm_s_per_rad),
      number("kp_nm_s_per_rad", unit("N·m·s/rad"), kPositive)
          .label("speed-loop gain Kp")
          .required_if(is_dynamic)
          .echo_if(is_dynamic)
          .deflt("required for dynamic")
          .meaning("speed-loop gain")
          .member(drive, &FeedDrive::kp_nm_s_per_rad),
      number("ki_nm_per_rad", unit("N·m/rad"), kNonNegative)
          .label("speed-loop gain Ki")
          .required_if(is_dynamic)
          .echo_if(is_dynamic)
          .deflt("required for dynamic")
          .meaning("speed-loop gain")
          .member(drive, &FeedDrive::ki_nm_per_rad),
      number("torque_limit_nm", unit("N·m"), kNonNegative)
          .label("torque limit")
          .echo_if(is_dynamic)
          .deflt("0 (none)")
          .member(drive, &FeedDrive::torque_limit_nm)};
}

// [[drives]]: the motor behind the current estimate.
std::vector<Field> drive_motor_fields() {
  return {integer("pole_pairs", 1, 100)
              .label("motor pole pairs")
              .required_if(has_motor)
              .deflt("with the motor")
              .member(motor, &PmsmMotor::pole_pairs, kNeedsMotor),
          number("torque_constant_nm_per_a", unit("N·m/A"), kPositive)
              .label("motor torque constant")
              .required_if(has_motor)
              .deflt("with the motor")
              .meaning("in `current_measure`'s measure")
              .member(motor, &PmsmMotor::torque_constant_nm_per_a, kNeedsMotor),
          choice("current_measure", {"rms", "space-vector"})
              .access(
                  [](const Case& c, std::size_t i) -> std::optional<Value> {
                    if (!has_motor(c, i)) return std::nullopt;
                    return Value(std::string(to_string(c.drives[i].motor->measure)));
                  },
                  [](Case& c, std::size_t i, const Value& v) -> std::string {
                    if (!has_motor(c, i)) return std::string(kNeedsMotor);
                    c.drives[i].motor->measure = *parse_current_measure(text_of(v));
                    return {};
                  }),
          number("current_noise_a", unit("A"), kNonNegative)
              .label("current noise σ")
              .meaning("σ of white noise per phase")
              .member(motor, &PmsmMotor::noise_a, kNeedsMotor),
          Row("current_offset_a", Type::kNumbers, unit("A"))
              .size(3)
              .deflt("0")
              .meaning("sensor offsets of u, v, w")
              .access(
                  [](const Case& c, std::size_t i) -> std::optional<Value> {
                    if (!has_motor(c, i)) return std::nullopt;
                    const double* o = c.drives[i].motor->offset_a;
                    return Value(std::vector<double>{o[0], o[1], o[2]});
                  },
                  [](Case& c, std::size_t i, const Value& v) -> std::string {
                    if (!has_motor(c, i)) return std::string(kNeedsMotor);
                    const auto& o = std::get<std::vector<double>>(v);
                    if (o.size() != 3) return "must be three numbers (phases u, v, w)";
                    for (int k = 0; k < 3; ++k)
                      c.drives[i].motor->offset_a[k] = o[static_cast<std::size_t>(k)];
                    return {};
                  }),
          integer("seed", 0, 2147483647)
              .label("noise seed")
              .meaning("with the motor; the seed of the current noise. Each axis draws its own "
                       "stream of it (mixed with its index in `[[drives]]`), so axes are "
                       "independent even with the same seed; `cutdyn drive --seed N` overrides it "
                       "for every axis")
              .member(motor, &PmsmMotor::seed, kNeedsMotor)};
}

Section drives_section() {
  Section dr;
  dr.name = "drives";
  dr.array = true;
  for (auto part : {drive_axis_fields, drive_dynamics_fields, drive_motor_fields})
    for (Field& f : part()) dr.fields.push_back(std::move(f));
  dr.count = [](const Case& c) { return c.drives.size(); };
  dr.create = refuse("");
  return dr;
}

Section vibration_section() {
  Section vib;
  vib.name = "vibration";
  vib.fields = {
      number("frequency_hz", unit("Hz"), kPositive)
          .label("vibration frequency")
          .required()
          .member(vibration, &VibrationAssist::frequency_hz),
      number("amplitude_um", kUm, kPositive)
          .label("vibration amplitude")
          .deflt("required unless `duty_cycle` is given")
          .member(vibration, &VibrationAssist::amplitude_m),
      number("workpiece_diameter_mm", kMm, kPositive)
          .label("workpiece diameter")
          .meaning("the duty cycle then follows from the cutting speed at each spindle speed")
          .member(vibration, &VibrationAssist::workpiece_diameter_m),
      number("duty_cycle", kNone, open_closed(0.0, 1.0))
          .label("duty cycle")
          .meaning("a fixed duty cycle r")
          .member(vibration, &VibrationAssist::duty_cycle)};
  vib.count = if_present(&Case::vibration);
  vib.create = emplace(&Case::vibration);
  return vib;
}

Section lobes_section() {
  Section lb;
  lb.name = "lobes";
  lb.fields = {
      lobes_row("rpm_min"),
      lobes_row("rpm_max"),
      lobes_row("rpm_steps"),
      Row::spec(stability_fields::kDepthMax).member(lobes, &LobesSection::depth_max_m),
      choice("method", {"auto", "zero-order", "closed-form", "multi-frequency",
                        "full-discretization", "full-discretization-dense"})
          .meaning(
              "the same names as `--method`. `zero-order` and `closed-form` are one method: in "
              "turning the closed form (Tlusty; the averaged theory with vibration), in milling "
              "the averaged solution (Altintas & Budak); `auto` is the closed form for "
              "conventional turning and the full discretization otherwise")
          .access(
              [](const Case& c, std::size_t) -> std::optional<Value> {
                return Value(std::string(to_string(c.lobes.method)));
              },
              [](Case& c, std::size_t, const Value& v) -> std::string {
                c.lobes.method = *parse_stability_method(text_of(v));
                return {};
              }),
      Row::spec(stability_fields::kHarmonics).member(lobes, &LobesSection::harmonics),
      integer("steps_per_period", 0, 100000)
          .label("steps per period")
          .meaning("full discretization, 0 = automatic")
          .member(lobes, &LobesSection::steps_per_period),
      lobes_row("refine"),
      lobes_row("refine_levels", false)};
  lb.count = always();
  lb.create = refuse("");
  return lb;
}

Section simulate_section() {
  Section sim;
  sim.name = "simulate";
  sim.process_column = true;
  sim.fields = {
      number("rpm", unit("rpm"), kPositive)
          .label("spindle speed")
          .member(simulate, &SimulateSection::rpm),
      number("depth_mm", kMm, open_closed(0.0, kMaxDepthMm))
          .label("depth of cut")
          .member(simulate, &SimulateSection::depth_m),
      number("duration_s", unit("s"), open_closed(0.0, 1000.0))
          .label("simulated time")
          .uses(Uses::kTurning)
          .member(simulate, &SimulateSection::duration_s),
      number("initial_displacement_um", kUm, kPositive)
          .label("initial displacement")
          .uses(Uses::kTurning)
          .member(simulate, &SimulateSection::initial_displacement_m),
      number("revolutions", kNone, closed(1.0, 1e6))
          .label("revolutions simulated")
          .uses(Uses::kMilling)
          .meaning("`--duration-s` sets it from the speed")
          .member(simulate, &SimulateSection::revolutions),
      number("summary_revolutions", kNone, kPositive)
          .label("revolutions summarised")
          .uses(Uses::kMilling)
          .meaning("at most `revolutions`; the last ones, for the summary (ΔP, means, chatter "
                   "indicator)")
          .member(simulate, &SimulateSection::summary_revolutions),
      boolean("regenerative")
          .uses(Uses::kMilling)
          .meaning("false: the chip comes from the feed alone (force studies)")
          .member(simulate, &SimulateSection::regenerative),
      integer("steps_per_tooth", 8, 100000)
          .label("steps per tooth")
          .uses(Uses::kMilling)
          .meaning("raised with regeneration to 64 steps per shortest mode period")
          .member(simulate, &SimulateSection::steps_per_tooth),
      integer("slices", 0, 10000)
          .label("axial slices")
          .uses(Uses::kMilling)
          .meaning("axial slices of a helical flute, 0 = automatic (one angle step of lag each)")
          .member(simulate, &SimulateSection::slices),
      boolean("closed_form_helix")
          .uses(Uses::kMilling)
          .meaning("true: the S1 closed form (eqs. 8–9) instead of slices")
          .member(simulate, &SimulateSection::closed_form_helix)};
  sim.count = always();
  sim.create = refuse("");
  return sim;
}

// A plan case's table.
Section bore_section() {
  Section bo;
  bo.name = "bore";
  bo.plan = true;
  bo.fields = {number("diameter_mm", kMm, kPositive)
                   .label("bore diameter d")
                   .required()
                   .meaning("d, the machined bore")
                   .member(bore, &BoreMillingCase::bore_diameter_m),
               number("length_mm", kMm, kPositive)
                   .label("bore length L")
                   .required()
                   .meaning("L")
                   .member(bore, &BoreMillingCase::length_m),
               number("allowance_mm", kMm, kPositive)
                   .label("allowance t")
                   .required()
                   .meaning("less than the bore's radius; t, radial")
                   .member(bore, &BoreMillingCase::allowance_m)};
  bo.count = if_present(&Case::bore);
  bo.create = refuse("");
  return bo;
}

// A plan case's table.
Section cutter_section() {
  Section cu;
  cu.name = "cutter";
  cu.plan = true;
  cu.fields = {
      number("diameter_mm", kMm, kPositive)
          .label("cutter diameter D")
          .required()
          .meaning("less than `bore.diameter_mm`; D")
          .member(bore, &BoreMillingCase::cutter_diameter_m),
      integer("teeth", 1, 500)
          .label("number of teeth z")
          .required()
          .meaning("z")
          .member(bore, &BoreMillingCase::teeth),
      number("offset_mm", kMm, kAny)
          .label("offset h")
          .required()
          .meaning("h; −h is the mirror image of +h; the cutter must fit (D/2 + \\|h\\| < d/2); "
                   "at h* = (2dt − t²)/(8D) the edge sets share the allowance evenly "
                   "(docs/models/bore-milling.md)")
          .member(bore, &BoreMillingCase::offset_m),
      number("lead_angle_deg", kDeg, open_closed(0.0, 90.0))
          .label("lead angle φ")
          .required()
          .meaning("φ")
          .member(bore, &BoreMillingCase::lead_angle_rad),
      number("inclination_deg", kDeg, open(-90.0, 90.0))
          .label("inclination λ")
          .meaning("λ")
          .member(bore, &BoreMillingCase::inclination_rad)};
  cu.count = if_present(&Case::bore);
  cu.create = refuse("");
  return cu;
}

// A plan case's table.
Section plan_process_section() {
  Section pr;
  pr.name = "process";
  pr.plan = true;
  pr.fields = {number("cutting_speed_m_per_min", kPlanMPerMin, kPositive)
                   .label("cutting speed v")
                   .required()
                   .meaning("v")
                   .member(bore, &BoreMillingCase::cutting_speed_m_per_s),
               number("mean_chip_thickness_mm", kMm, kPositive)
                   .label("mean chip thickness a_cp")
                   .required()
                   .meaning("a_cp")
                   .member(bore, &BoreMillingCase::mean_chip_thickness_m),
               number("accuracy_coefficient", kNone,
                      {kAccuracyCoefficientMin, false, kAccuracyCoefficientMax, false, false,
                       "must be from 0.005 (finishing) to 0.1 (roughing), the source's range of k"})
                   .label("accuracy coefficient k")
                   .required()
                   .meaning("k: Δ1 ≤ k·t (the source's range: 0.1 roughing … 0.005 finishing)")
                   .member(bore, &BoreMillingCase::accuracy_coefficient),
               number("axial_feed_mm", kMm, kPositive)
                   .label("axial feed S0")
                   .deflt("the largest")
                   .meaning("a fixed S0")
                   .member(whole, &Case::axial_feed_m)};
  pr.count = if_present(&Case::bore);
  pr.create = refuse("");
  return pr;
}

// A plan case's table.
Section limits_section() {
  Section li;
  li.name = "limits";
  li.plan = true;
  li.fields = {number("offset_min_mm", kMm, kAny)
                   .label("smallest offset h")
                   .required()
                   .meaning("the range of h for the optimiser, taken as \\|h\\| and kept below "
                            "(dt − t²)/(2D), where both edge sets cut")
                   .member(limits, &BoreMillingLimits::offset_min_m),
               number("offset_max_mm", kMm, kAny)
                   .label("largest offset h")
                   .required()
                   .meaning("at least `offset_min_mm`")
                   .member(limits, &BoreMillingLimits::offset_max_m),
               number("cutting_speed_max_m_per_min", kPlanMPerMin, kPositive)
                   .label("highest cutting speed")
                   .required()
                   .member(limits, &BoreMillingLimits::cutting_speed_max_m_per_s),
               number("cutter_rpm_max", kRpmAsRevPerS, kPositive)
                   .label("highest cutter speed")
                   .required()
                   .member(limits, &BoreMillingLimits::cutter_rev_per_s_max),
               number("workpiece_rpm_max", kRpmAsRevPerS, kPositive)
                   .label("highest workpiece speed")
                   .required()
                   .member(limits, &BoreMillingLimits::workpiece_rev_per_s_max),
               number("faceting_max_mm", kMm, kPositive)
                   .label("largest faceting Δ2")
                   .required()
                   .meaning("Δ2")
                   .member(limits, &BoreMillingLimits::faceting_max_m),
               number("max_chip_thickness_mm", kMm, kPositive)
                   .label("largest chip thickness a_max")
                   .required()
                   .meaning("a_max")
                   .member(limits, &BoreMillingLimits::max_chip_thickness_m)};
  li.count = if_present(&Case::bore_limits);
  li.create = emplace(&Case::bore_limits);
  return li;
}

std::vector<Section> make_sections() {
  std::vector<Section> all;
  all.push_back(top_level_section());
  all.push_back(modes_section());
  all.push_back(frf_section());
  all.push_back(cutting_section());
  all.push_back(material_section());
  all.push_back(johnson_cook_section());
  all.push_back(thermal_section());
  all.push_back(oxley_section());
  all.push_back(tool_section());
  all.push_back(operation_section());
  all.push_back(force_law_section());
  all.push_back(drives_section());
  all.push_back(vibration_section());
  all.push_back(lobes_section());
  all.push_back(simulate_section());
  all.push_back(bore_section());
  all.push_back(cutter_section());
  all.push_back(plan_process_section());
  all.push_back(limits_section());
  return all;
}

// ---- the doc tables ------------------------------------------------------------------------

// A Case with every table present and its defaults, for the doc's default column.
const Case& defaults_case() {
  static const Case c = [] {
    Case d;
    d.modal.modes.emplace_back();
    d.mode_mass_kg.emplace_back();
    d.tool.emplace();
    d.operation.emplace();
    d.vibration.emplace();
    d.force_law.emplace();
    d.material.emplace();
    d.bore.emplace();
    d.bore_limits.emplace();
    d.drives.emplace_back();
    d.drives.back().motor.emplace();
    return d;
  }();
  return c;
}

std::string type_doc(const Field& f) {
  switch (f.type) {
    case Type::kNumber:
      return "number";
    case Type::kInteger:
      return "integer";
    case Type::kBoolean:
      return "boolean";
    case Type::kChoice:
    case Type::kText:
      return "string";
    case Type::kNumbers:
      return f.array_size > 0 ? "array of " + std::to_string(f.array_size) + " numbers"
                              : "array of numbers";
  }
  return "?";
}

std::string default_doc(const Field& f) {
  if (!f.default_doc.empty()) return std::string(f.default_doc);
  if (f.required) return "required";
  const auto v = f.get ? f.get(defaults_case(), 0) : std::nullopt;
  if (!v) return "optional";
  if (const std::string* s = std::get_if<std::string>(&*v)) return "`\"" + *s + "\"`";
  return value_text(f, *v);
}

std::string process_doc(const Field& f) {
  if (!f.process_doc.empty()) return std::string(f.process_doc);
  switch (f.uses) {
    case Uses::kBoth:
      return "both";
    case Uses::kTurning:
      return "turning";
    case Uses::kMilling:
      return "milling";
  }
  return "?";
}

std::string rule_doc(const Field& f) {
  std::string range;
  if (f.type == Type::kChoice) {
    for (std::size_t i = 0; i < f.choices.size(); ++i) {
      if (i > 0) range += i + 1 == f.choices.size() ? " or " : ", ";
      range += "`\"" + std::string(f.choices[i]) + "\"`";
    }
  } else if (f.numeric() || f.type == Type::kNumbers) {
    range = f.range.doc(f.type == Type::kInteger);
    if (f.type == Type::kNumbers && !range.empty()) range = "each " + range;
  }
  if (f.meaning.empty()) return range;
  if (range.empty()) return std::string(f.meaning);
  return range + "; " + std::string(f.meaning);
}

}  // namespace

const std::vector<Section>& case_sections() {
  static const std::vector<Section> all = make_sections();
  return all;
}

const Section* find_section(std::string_view name, bool plan) {
  for (const Section& s : case_sections())
    if (s.name == name && s.plan == plan) return &s;
  return nullptr;
}

std::string key_axis_label(const Case& c, std::string_view key) {
  const std::size_t dot = key.rfind('.');
  const std::string_view name = dot == std::string_view::npos ? key : key.substr(dot + 1);
  std::string_view table = dot == std::string_view::npos ? std::string_view{} : key.substr(0, dot);
  std::string_view element;  // "modes[1]" for an array section
  if (!table.empty() && table.back() == ']' && table.find('[') != std::string_view::npos) {
    element = table;
    table = table.substr(0, table.find('['));
  }
  const Section* section = find_section(table, c.process == Process::kBoreMilling);
  const Field* field = section ? section->find(name) : nullptr;
  if (section && c.process != Process::kBoreMilling)
    if (const Alias* a = section->alias(name, c.process)) field = section->find(a->canonical);
  if (field == nullptr) return std::string(key);
  const std::string_view unit = field->unit.text;
  const bool ratio = unit.empty() || unit.rfind("–", 0) == 0;  // "–", "– (a_e/D)"
  std::string text = field->label.empty() ? std::string(key) : std::string(field->label);
  if (!field->label.empty() && !element.empty()) text += ", " + std::string(element);
  if (!ratio) text += " (" + std::string(unit) + ")";
  return text;
}

nlohmann::json schema_json() {
  nlohmann::json out = nlohmann::json::object();
  const auto plain = [](std::string text) {  // the doc's markdown, as plain text
    text.erase(std::remove(text.begin(), text.end(), '`'), text.end());
    return text;
  };
  for (const Section& s : case_sections()) {
    nlohmann::json keys = nlohmann::json::object();
    for (const Field& f : s.fields) {
      nlohmann::json k{{"type", type_doc(f)},
                       {"unit", std::string(f.unit.text)},
                       {"default", plain(default_doc(f))},
                       {"process", process_doc(f)},
                       {"rule", plain(rule_doc(f))}};
      if (!f.label.empty()) k["label"] = std::string(f.label);
      if (f.type == Type::kChoice) {
        nlohmann::json choices = nlohmann::json::array();
        for (std::string_view c : f.choices) choices.push_back(std::string(c));
        k["choices"] = std::move(choices);
      }
      keys[std::string(f.key)] = std::move(k);
    }
    const std::string name = s.name.empty() ? "(top level)" : std::string(s.name);
    out[s.plan ? name + " (plan)" : name] = {{"array", s.array}, {"keys", std::move(keys)}};
  }
  return out;
}

std::string key_table_markdown(const Section& s) {
  std::string md = s.process_column
                       ? "| key | type | unit | process | required / default | rule |\n"
                         "|---|---|---|---|---|---|\n"
                       : "| key | type | unit | required / default | rule |\n"
                         "|---|---|---|---|---|\n";
  for (const Field& f : s.fields) {
    md += "| `" + std::string(f.key) + "` | " + type_doc(f) + " | " + std::string(f.unit.text) +
          " | ";
    if (s.process_column) md += process_doc(f) + " | ";
    md += default_doc(f) + " | " + rule_doc(f) + " |\n";
  }
  return md;
}

}  // namespace cutdyn::io::detail
