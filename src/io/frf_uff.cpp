// Universal File Format, dataset 58 (function at nodal DOF) and its binary variant 58b, read
// [Sdrc1999]; dataset 164 (units) applied. docs/frf-files.md ("Universal File Format").
//
// Dataset 58: records 1-5 ID lines; record 6 DOF identification (field 1 function type,
// 4 = FRF); record 7 data form (ordinate data type 5 = complex single, 6 = complex double;
// number of points; abscissa spacing 1 = even with minimum and increment, 0 = uneven);
// records 8-11 abscissa, ordinate numerator, ordinate denominator and z-axis: specific data
// type (8 displacement, 11 velocity, 12 acceleration, 9/13 force, 18 frequency), unit
// exponents and labels; record 12 the values (6E13.5 single, 4E20.12 double even,
// E13.5,2E20.12 double uneven) [Sdrc1999, dataset 58]. 58b: the same 11 records, then the
// values as raw bytes of the order and float format the id line gives [Sdrc1999, 58b].
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>

#include "frf_detail.hpp"

namespace cutdyn::io::detail {
namespace {

// Reads a text line by line while keeping the byte position (58b data is raw bytes).
struct Cursor {
  std::string_view content;
  std::size_t pos = 0;
  std::size_t line = 0;
  bool next(TextLine& out) {
    if (pos >= content.size()) return false;
    const std::size_t end = content.find('\n', pos);
    std::string_view text =
        content.substr(pos, end == std::string_view::npos ? content.npos : end - pos);
    if (!text.empty() && text.back() == '\r') text.remove_suffix(1);
    out = {text, ++line};
    pos = end == std::string_view::npos ? content.size() : end + 1;
    return true;
  }
};

// Record 8-11: specific data type, unit exponents, axis label and units label.
struct AxisRecord {
  int type = 0;
  std::string label, units;
  std::size_t line = 0;
};

struct Dataset58 {
  UffDatasetInfo info;
  std::vector<TextLine> records;  // records 1-11
  std::vector<TextLine> data;     // ASCII data lines
  std::string_view bytes;         // 58b data
  int byte_order = 1, float_format = 2;
  std::size_t id_line = 0;
};

struct Units164 {
  double length = 1.0, force = 1.0;  // file units per SI unit
  std::size_t line = 0;
  std::size_t position = 0;  // index of the dataset 58 it precedes
};

// A number that is an int: whole and at most 1e9 in size (NaN, infinity and 1e300 are not;
// converting them to int would be undefined).
std::optional<int> as_int(std::optional<double> x) {
  if (!x || !(std::abs(*x) <= 1e9) || *x != std::floor(*x)) return std::nullopt;
  return static_cast<int>(*x);
}

std::optional<int> int_field(std::string_view line, std::size_t at, std::size_t width) {
  if (at >= line.size()) return std::nullopt;
  return as_int(parse_number(trim(line.substr(at, width))));
}

std::string_view text_field(std::string_view line, std::size_t at, std::size_t width) {
  return at >= line.size() ? std::string_view{} : trim(line.substr(at, width));
}

// Numbers separated by blanks, or else in the fixed widths given (repeated over the line).
std::optional<std::vector<double>> line_numbers(std::string_view line,
                                                const std::vector<std::size_t>& widths) {
  std::vector<double> values;
  bool ok = true;
  for (std::string_view token : split_blanks(line)) {
    const auto x = parse_number(token);
    if (!x) {
      ok = false;
      break;
    }
    values.push_back(*x);
  }
  if (ok) return values;
  values.clear();
  for (std::size_t at = 0, k = 0; at < line.size(); at += widths[k % widths.size()], ++k) {
    const std::string_view field = trim(line.substr(at, widths[k % widths.size()]));
    if (field.empty()) continue;
    const auto x = parse_number(field);
    if (!x) return std::nullopt;
    values.push_back(*x);
  }
  return values;
}

AxisRecord axis_record(const TextLine& line) {
  AxisRecord r;
  r.line = line.number;
  const auto type = int_field(line.text, 0, 10);
  const bool fixed = type && int_field(line.text, 10, 5) && int_field(line.text, 15, 5) &&
                     int_field(line.text, 20, 5);
  if (fixed) {
    r.type = *type;
    r.label = std::string(text_field(line.text, 26, 20));
    r.units = std::string(text_field(line.text, 47, 20));
    return r;
  }
  const auto tokens = split_blanks(line.text);
  if (!tokens.empty()) r.type = as_int(parse_number(tokens[0])).value_or(0);
  if (tokens.size() > 4) r.label = std::string(tokens[4]);
  if (tokens.size() > 5) r.units = std::string(tokens[5]);
  return r;
}

const char* data_type_name(int type) {
  switch (type) {
    case 0:
      return "unknown";
    case 1:
      return "general";
    case 2:
      return "stress";
    case 3:
      return "strain";
    case 5:
      return "temperature";
    case 6:
      return "heat flux";
    case 8:
      return "displacement";
    case 9:
      return "reaction force";
    case 11:
      return "velocity";
    case 12:
      return "acceleration";
    case 13:
      return "excitation force";
    case 15:
      return "pressure";
    case 16:
      return "mass";
    case 17:
      return "time";
    case 18:
      return "frequency";
    case 19:
      return "rpm";
    case 20:
      return "order";
    default:
      return "a code cutdyn does not know";
  }
}

const char* function_type_name(int type) {
  switch (type) {
    case 0:
      return "general or unknown";
    case 1:
      return "time response";
    case 2:
      return "auto spectrum";
    case 3:
      return "cross spectrum";
    case 4:
      return "frequency response function";
    case 5:
      return "transmissibility";
    case 6:
      return "coherence";
    case 9:
      return "power spectral density";
    case 12:
      return "spectrum";
    default:
      return "not an FRF";
  }
}

bool is_delimiter(std::string_view line) { return trim(line) == "-1"; }

// Parses the id line of a binary dataset ("58b  1  2  11  4096  0 ..."): byte order, float
// format, ASCII lines, bytes.
std::array<long long, 4> binary_id(const TextLine& id, const std::string& source) {
  std::string_view rest = trim(id.text);
  rest.remove_prefix(rest.find('b') + 1);
  const auto tokens = split_blanks(rest);
  std::array<long long, 4> v{};
  for (std::size_t i = 0; i < 4; ++i) {
    const auto x = i < tokens.size() ? parse_number(tokens[i]) : std::nullopt;
    if (!x || *x < 0 || *x != std::floor(*x) || *x > 1e15)
      fail_at(source, id.number,
              "the binary dataset's id line " + excerpt(trim(id.text)) +
                  " does not give byte order, float format, ASCII lines and byte count");
    v[i] = static_cast<long long>(*x);
  }
  return v;
}

// Reads the lines of the dataset after its id line up to its closing -1; for a binary
// dataset the ASCII lines, the bytes, then the -1.
void read_body(Cursor& c, const TextLine& id, bool binary, std::size_t start_line,
               std::vector<TextLine>& lines, std::string_view* bytes, const std::string& source,
               int* byte_order, int* float_format) {
  TextLine line;
  if (binary) {
    const auto v = binary_id(id, source);
    *byte_order = static_cast<int>(v[0]);
    *float_format = static_cast<int>(v[1]);
    for (long long k = 0; k < v[2]; ++k) {
      if (!c.next(line))
        fail_at(source, id.number,
                "the file ends within the dataset's " + std::to_string(v[2]) + " ASCII lines");
      lines.push_back(line);
    }
    const std::size_t n = static_cast<std::size_t>(v[3]);
    if (c.content.size() - c.pos < n)
      fail_at(source, id.number,
              "the id line announces " + std::to_string(n) +
                  " bytes of binary data, the file has " +
                  std::to_string(c.content.size() - c.pos) + " left");
    *bytes = c.content.substr(c.pos, n);
    c.pos += n;
    if (!c.next(line) || !is_delimiter(line.text))
      fail_at(source, id.number,
              "the binary data is not followed by a -1 line (is the byte count " +
                  std::to_string(n) + " of the id line right?)");
    return;
  }
  while (c.next(line)) {
    if (is_delimiter(line.text)) return;
    lines.push_back(line);
  }
  fail_at(source, start_line, "the dataset starting here has no closing -1 line");
}

UffDatasetInfo dataset_info(const std::vector<TextLine>& r, const std::string& source,
                            std::size_t start) {
  UffDatasetInfo info;
  info.line = start;
  if (r.size() < 11)
    fail_at(source, start,
            "a dataset 58 has 11 header records; this one ends after " + std::to_string(r.size()));
  info.description = std::string(trim(r[0].text));
  const std::string_view rec6 = r[5].text;
  auto type = int_field(rec6, 0, 5);
  if (!type) {
    const auto tokens = split_blanks(rec6);
    if (!tokens.empty()) type = as_int(parse_number(tokens[0]));
  }
  if (!type) fail_at(source, r[5].number, "record 6 does not start with a function type");
  info.function_type = *type;
  info.response_node = int_field(rec6, 41, 10).value_or(0);
  info.response_direction = int_field(rec6, 51, 4).value_or(0);
  info.reference_node = int_field(rec6, 66, 10).value_or(0);
  info.reference_direction = int_field(rec6, 76, 4).value_or(0);
  return info;
}

Units164 read_units164(const std::vector<TextLine>& lines, const std::string& source,
                       std::size_t start) {
  std::vector<double> numbers;
  std::size_t line = start;
  for (std::size_t k = 1; k < lines.size() && numbers.size() < 2; ++k) {
    for (std::string_view t : split_blanks(lines[k].text))
      if (const auto x = parse_number(t)) numbers.push_back(*x);
    line = lines[k].number;
  }
  if (lines.empty() || numbers.size() < 2 || !(numbers[0] > 0.0) || !(numbers[1] > 0.0) ||
      !std::isfinite(numbers[0]) || !std::isfinite(numbers[1]))
    fail_at(source, line, "dataset 164 (units) does not give positive length and force factors");
  return {numbers[0], numbers[1], start, 0};
}

// Every dataset of the file: the 58s kept, the units of each 164 kept, the rest skipped.
void scan(std::string_view content, const std::string& source, std::vector<Dataset58>& found,
          std::vector<Units164>& units, std::vector<std::string>& others) {
  Cursor c{content};
  TextLine line;
  while (c.next(line)) {
    if (trim(line.text).empty()) continue;
    if (const std::size_t b = first_binary_byte(line.text); b != std::string_view::npos)
      fail_at(source, line.number,
              "not text (a control byte where a -1 line should start a dataset)");
    if (!is_delimiter(line.text))
      fail_at(source, line.number,
              "expected a -1 line starting a dataset, found " + excerpt(trim(line.text)));
    const std::size_t start = line.number;
    TextLine id;
    if (!c.next(id))
      fail_at(source, start, "the file ends after the -1 (a dataset number must follow)");
    const auto tokens = split_blanks(id.text);
    const std::string name = tokens.empty() ? std::string() : std::string(tokens[0]);
    const bool binary = !name.empty() && name.back() == 'b';
    Dataset58 d;
    d.id_line = id.number;
    read_body(c, id, binary, start, d.records, &d.bytes, source, &d.byte_order, &d.float_format);
    if (name == "58" || name == "58b") {
      d.info = dataset_info(d.records, source, start);
      d.info.index = static_cast<int>(found.size());
      d.info.binary = binary;
      d.data.assign(d.records.begin() + 11, d.records.end());
      d.records.resize(11);
      found.push_back(std::move(d));
    } else if (name == "164") {
      units.push_back(read_units164(d.records, source, start));
      units.back().position = found.size();
    } else {
      others.push_back(name.empty() ? std::string("(blank)") : name);
    }
  }
}

// ---- the values of the dataset read ----------------------------------------------------

// Record 7: ordinate data type, points, spacing, abscissa minimum and increment.
struct DataForm {
  int type = 0;
  std::size_t points = 0;
  bool even = false;
  double minimum = 0.0, increment = 0.0;
  std::size_t line = 0;
};

// `real_allowed`: a real ordinate (data type 2 or 4) is read too (the coherence's).
DataForm data_form(const TextLine& rec7, const std::string& source, bool real_allowed = false) {
  auto v = line_numbers(rec7.text, {10, 10, 10, 13, 13, 13});
  if (!v || v->size() < 3)
    fail_at(source, rec7.number,
            "record 7 (data form) does not hold ordinate data type, number "
            "of points and abscissa spacing: " +
                excerpt(trim(rec7.text)));
  DataForm f;
  f.line = rec7.number;
  const std::optional<int> type = as_int((*v)[0]);
  if (!type)
    fail_at(source, rec7.number,
            "record 7: ordinate data type " + format_value((*v)[0]) +
                " must be 5 (complex single) or 6 (complex double)");
  f.type = *type;
  const double n = (*v)[1];
  if (!(n >= 0.0 && n < 1e9 && n == std::floor(n)))
    fail_at(source, rec7.number,
            "record 7: number of points " + format_value(n) + " is not a count");
  f.points = static_cast<std::size_t>(n);
  if ((*v)[2] != 0.0 && (*v)[2] != 1.0)
    fail_at(
        source, rec7.number,
        "record 7: abscissa spacing " + format_value((*v)[2]) + " must be 0 (uneven) or 1 (even)");
  f.even = (*v)[2] == 1.0;
  if ((f.type == 2 || f.type == 4) && !real_allowed)
    fail_at(source, rec7.number,
            "record 7: the ordinate is real (data type " + std::to_string(f.type) +
                "); an FRF is complex (5 or 6)");
  if (f.type != 5 && f.type != 6 && !(real_allowed && (f.type == 2 || f.type == 4)))
    fail_at(source, rec7.number,
            "record 7: ordinate data type " + std::to_string(f.type) + " must be " +
                (real_allowed ? "2 or 4 (real single or double) or " : "") +
                "5 (complex single) or 6 (complex double)");
  if (f.even) {
    if (v->size() < 5)
      fail_at(source, rec7.number,
              "record 7: even spacing needs the abscissa minimum and increment");
    f.minimum = (*v)[3];
    f.increment = (*v)[4];
    if (!std::isfinite(f.minimum) || !(f.increment > 0.0) || !std::isfinite(f.increment))
      fail_at(source, rec7.number,
              "record 7: abscissa minimum " + format_value(f.minimum) + " and increment " +
                  format_value(f.increment) + ": the increment must be positive, both finite");
  }
  return f;
}

bool is_complex(const DataForm& form) { return form.type == 5 || form.type == 6; }
bool is_single(const DataForm& form) { return form.type == 2 || form.type == 5; }
// Numbers per point: the abscissa (uneven spacing) and one (real) or two (complex) ordinates.
std::size_t values_per_point(const DataForm& form) {
  return (form.even ? 0 : 1) + (is_complex(form) ? 2 : 1);
}

// ASCII values, with the line of each: single precision 6E13.5 per line; double precision
// 4E20.12 (even), or per point E13.5 and the ordinates in E20.12 (uneven) [Sdrc1999, 58].
void ascii_values(const Dataset58& d, const DataForm& form, const std::string& source,
                  std::vector<double>& values, std::vector<std::size_t>& lines) {
  const std::vector<std::size_t> widths =
      is_single(form) ? std::vector<std::size_t>{13}
      : form.even     ? std::vector<std::size_t>{20}
      : is_complex(form) ? std::vector<std::size_t>{13, 20, 20}
                         : std::vector<std::size_t>{13, 20};
  for (const TextLine& line : d.data) {
    if (const std::size_t b = first_binary_byte(line.text); b != std::string_view::npos)
      fail_at(source, line.number,
              "not text (control byte at column " + std::to_string(b + 1) + ")");
    const auto v = line_numbers(line.text, widths);
    if (!v) fail_at(source, line.number, excerpt(trim(line.text)) + " is not a line of numbers");
    values.insert(values.end(), v->begin(), v->end());
    lines.insert(lines.end(), v->size(), line.number);
  }
}

// 58b values: floats or doubles (an uneven double dataset may store its abscissa as float).
void binary_values(const Dataset58& d, const DataForm& form, const std::string& source,
                   std::vector<double>& values) {
  if (d.byte_order != 1 && d.byte_order != 2)
    fail_at(source, d.id_line,
            "58b byte order " + std::to_string(d.byte_order) +
                " must be 1 (little endian) or 2 (big endian)");
  if (d.float_format != 2)
    fail_at(source, d.id_line,
            "58b floating-point format " + std::to_string(d.float_format) +
                " is not read (only 2, IEEE 754; 1 is DEC VMS, 3 IBM 370)");
  const std::size_t per = values_per_point(form), n = form.points;
  const std::size_t size = is_single(form) ? 4 : 8;
  const std::size_t float_abscissa_bytes = (4 + 8 * (per - 1)) * n;
  const bool float_abscissa =
      !is_single(form) && !form.even && d.bytes.size() == float_abscissa_bytes;
  const std::size_t expected = float_abscissa ? float_abscissa_bytes : per * n * size;
  if (d.bytes.size() != expected)
    fail_at(source, d.id_line,
            std::to_string(n) + " points of data type " + std::to_string(form.type) +
                (form.even ? " (even)" : " (uneven)") + " take " + std::to_string(expected) +
                " bytes; the id line gives " + std::to_string(d.bytes.size()));
  const auto get = [&](std::size_t at, std::size_t width) {
    std::uint64_t bits = 0;
    for (std::size_t k = 0; k < width; ++k) {
      const std::size_t byte = d.byte_order == 1 ? at + k : at + width - 1 - k;
      bits |= static_cast<std::uint64_t>(static_cast<unsigned char>(d.bytes[byte])) << (8 * k);
    }
    return width == 4 ? static_cast<double>(std::bit_cast<float>(static_cast<std::uint32_t>(bits)))
                      : std::bit_cast<double>(bits);
  };
  for (std::size_t at = 0; at < d.bytes.size();) {
    const std::size_t width = (float_abscissa && values.size() % per == 0) ? 4 : size;
    values.push_back(get(at, width));
    at += width;
  }
}

std::string type_text(int type) {
  return std::string(data_type_name(type)) + " (specific data type " + std::to_string(type) + ")";
}

// The ordinate's quantity and unit from records 9 and 10, dataset 164 and the labels.
OrdinateUnit ordinate_unit(const AxisRecord& num, const AxisRecord& den, const Units164* units,
                           const std::string& source, std::vector<std::string>& warnings) {
  std::optional<FrfQuantity> by_code;
  if (num.type == 8) by_code = FrfQuantity::kReceptance;
  if (num.type == 11) by_code = FrfQuantity::kMobility;
  if (num.type == 12) by_code = FrfQuantity::kAccelerance;
  if (!by_code && num.type != 0 && num.type != 1)
    fail_at(source, num.line,
            "record 9: the ordinate is " + type_text(num.type) +
                "; an FRF for cutdyn is displacement (8), velocity (11) or "
                "acceleration (12) per force");
  if (den.type != 0 && den.type != 1 && den.type != 9 && den.type != 13)
    fail_at(source, den.line,
            "record 10: the ordinate denominator is " + type_text(den.type) +
                ", not a force (9 or 13)");
  const auto none = [](const std::string& s) { return s.empty() || lower(s) == "none"; };
  std::optional<OrdinateUnit> by_label = parse_ordinate_unit(num.units);
  if (!by_label && !none(num.units)) {
    by_label = parse_response_unit(num.units);
    const auto force = none(den.units) ? std::optional<double>(1.0) : parse_force_unit(den.units);
    if (by_label && force) {
      by_label->scale /= *force;
      by_label->name += "/" + (none(den.units) ? std::string("N") : den.units);
    } else {
      by_label.reset();
    }
  }
  if (!by_label && !none(num.units))
    warnings.push_back(at_line(num.line, "the units label " + excerpt(num.units) +
                                             (none(den.units) ? "" : " per " + excerpt(den.units)) +
                                             " is not one cutdyn knows; ignored"));
  if (by_code && by_label && by_label->quantity != *by_code)
    fail_at(source, num.line,
            "record 9 says " + type_text(num.type) + " but its units label " + excerpt(num.units) +
                " is a " + to_string(by_label->quantity) + " unit");
  if (by_label) return *by_label;
  const FrfQuantity q = by_code.value_or(FrfQuantity::kReceptance);
  const char* si[] = {"m/N", "m/s/N", "m/s^2/N"};
  OrdinateUnit unit{q, 1.0, si[static_cast<int>(q)]};
  if (!by_code) {
    warnings.push_back(at_line(num.line,
                               "the ordinate's quantity is not stated (record 9 specific "
                               "data type " +
                                   std::to_string(num.type) +
                                   ", no units label): read as receptance in m/N"));
  } else if (units) {
    unit.scale = units->force / units->length;  // SI = file value / factor [Sdrc1999, 164]
    unit.name += " (dataset 164 on line " + std::to_string(units->line) + ")";
  } else {
    warnings.push_back(at_line(num.line, std::string("no units label and no dataset 164: the ") +
                                             to_string(q) + " is read in SI units (" + unit.name +
                                             ")"));
  }
  return unit;
}

double abscissa_scale(const AxisRecord& rec8, const std::string& source,
                      std::vector<std::string>& warnings, std::string& name) {
  if (rec8.type != 0 && rec8.type != 1 && rec8.type != 18)
    fail_at(source, rec8.line,
            "record 8: the abscissa is " + type_text(rec8.type) + ", not frequency (18)");
  name = "Hz";
  if (rec8.units.empty() || lower(rec8.units) == "none") return 1.0;
  if (const auto s = parse_frequency_unit(rec8.units)) {
    name = rec8.units;
    return *s;
  }
  warnings.push_back(at_line(rec8.line, "the abscissa units label " + excerpt(rec8.units) +
                                            " is not one cutdyn knows; read as Hz"));
  return 1.0;
}

std::vector<RawPoint> points_of(const Dataset58& d, const DataForm& form,
                                const std::string& source) {
  std::vector<double> values;
  std::vector<std::size_t> lines;
  if (d.info.binary)
    binary_values(d, form, source, values);
  else
    ascii_values(d, form, source, values, lines);
  const std::size_t per = values_per_point(form);
  if (values.size() != per * form.points)
    fail_at(source, form.line,
            "record 7 announces " + std::to_string(form.points) + " points (" +
                std::to_string(per * form.points) + " values), the data hold " +
                std::to_string(values.size()) + " values");
  std::vector<RawPoint> points(form.points);
  for (std::size_t i = 0; i < form.points; ++i) {
    const double* v = values.data() + per * i;
    RawPoint& p = points[i];
    p.frequency = form.even ? form.minimum + static_cast<double>(i) * form.increment : v[0];
    const double* y = form.even ? v : v + 1;
    p.value = std::complex<double>(y[0], is_complex(form) ? y[1] : 0.0);
    p.line = d.info.binary ? d.id_line : lines[per * i];
  }
  return points;
}

const Dataset58& choose(const std::vector<Dataset58>& found, const std::vector<std::string>& others,
                        const FrfFileOptions& options, const std::string& source,
                        std::vector<std::string>& warnings) {
  if (found.empty()) {
    std::string seen;
    for (const std::string& o : others) seen += (seen.empty() ? "" : ", ") + o;
    throw InvalidInput({"no dataset 58 (function at nodal DOF) in the file" +
                        (seen.empty() ? std::string() : "; its datasets are " + seen)},
                       source);
  }
  const auto describe = [](const Dataset58& d) {
    return "dataset 58 index " + std::to_string(d.info.index) + " (line " +
           std::to_string(d.info.line) + ", function type " + std::to_string(d.info.function_type) +
           ", " + function_type_name(d.info.function_type) + ")";
  };
  if (options.dataset) {
    const int k = *options.dataset;
    if (k < 0 || k >= static_cast<int>(found.size()))
      throw InvalidInput(
          {"dataset = " + std::to_string(k) + ": the file has " + std::to_string(found.size()) +
           " datasets 58 (indices 0 to " + std::to_string(found.size() - 1) + ")"},
          source);
    const Dataset58& d = found[static_cast<std::size_t>(k)];
    if (d.info.function_type != 4)
      fail_at(source, d.records[5].number,
              describe(d) + " is not a frequency response function (4)");
    return d;
  }
  const Dataset58* first = nullptr;
  int frfs = 0;
  for (const Dataset58& d : found) {
    if (d.info.function_type != 4) continue;
    ++frfs;
    if (!first) first = &d;
  }
  if (!first) {
    std::vector<std::string> problems{
        "no dataset 58 is a frequency response function (function type 4):"};
    for (const Dataset58& d : found) problems.push_back(describe(d));
    throw InvalidInput(problems, source);
  }
  if (frfs > 1)
    warnings.push_back("the file holds " + std::to_string(frfs) + " FRFs; read the first, " +
                       describe(*first) + " " + excerpt(first->info.description) +
                       "; choose another by its dataset index");
  return *first;
}

// The coherence of the FRF `d` (docs/frf-files.md, "Coherence"): the first dataset 58 of
// function type 6 with the same response and reference DOF; its values are set on `points`
// when it has the same frequencies, and a warning says why it is not used otherwise.
void attach_coherence(const std::vector<Dataset58>& found, const Dataset58& d,
                      double frequency_scale, std::vector<RawPoint>& points,
                      const std::string& source, std::vector<std::string>& warnings) {
  const auto same_dof = [&](const UffDatasetInfo& c) {
    return c.response_node == d.info.response_node &&
           c.response_direction == d.info.response_direction &&
           c.reference_node == d.info.reference_node &&
           c.reference_direction == d.info.reference_direction;
  };
  const auto it = std::find_if(found.begin(), found.end(), [&](const Dataset58& c) {
    return c.info.function_type == 6 && same_dof(c.info);
  });
  if (it == found.end()) return;
  const Dataset58& c = *it;
  const std::string name = "the coherence (dataset 58 index " + std::to_string(c.info.index) +
                           ", line " + std::to_string(c.info.line) + ")";
  // A coherence cutdyn cannot read does not make the FRF unreadable: it is left out, said.
  std::vector<RawPoint> values;
  double scale = 1.0;
  try {
    const DataForm form = data_form(c.records[6], source, /*real_allowed=*/true);
    std::vector<std::string> ignored;
    std::string abscissa_name;
    scale = abscissa_scale(axis_record(c.records[7]), source, ignored, abscissa_name);
    values = points_of(c, form, source);
  } catch (const InvalidInput& e) {
    warnings.push_back(name + " is not read (" +
                       (e.problems().empty() ? std::string("malformed") : e.problems().front()) +
                       "): not used");
    return;
  }
  bool same = values.size() == points.size();
  for (std::size_t i = 0; same && i < values.size(); ++i) {
    const double a = values[i].frequency * scale, b = points[i].frequency * frequency_scale;
    same = std::abs(a - b) <= 1e-6 * std::max(std::abs(b), 1.0);
  }
  if (!same) {
    warnings.push_back(name + " has " + std::to_string(values.size()) +
                       " points at other frequencies than the FRF's " +
                       std::to_string(points.size()) + ": not used");
    return;
  }
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double gamma2 = values[i].value.real();
    if (!(gamma2 >= 0.0 && gamma2 <= 1.0))
      fail_at(source, values[i].line,
              name + ": " + format_value(gamma2) + " at " +
                  format_value(values[i].frequency * scale) + " Hz is not 0 to 1");
    points[i].coherence = gamma2;
  }
}

}  // namespace

FrfReadResult read_uff_text(std::string_view content, const std::string& source,
                            const FrfFileOptions& options) {
  std::vector<Dataset58> found;
  std::vector<Units164> units;
  std::vector<std::string> others;
  scan(content, source, found, units, others);
  FrfReadResult result;
  result.format = FrfFormat::kUff;
  const Dataset58& d = choose(found, others, options, source, result.warnings);
  for (const Dataset58& x : found) result.uff_datasets.push_back(x.info);
  result.description = d.info.description;
  const Units164* unit164 = nullptr;
  for (const Units164& u : units)
    if (u.position <= static_cast<std::size_t>(d.info.index)) unit164 = &u;
  const DataForm form = data_form(d.records[6], source);
  std::string abscissa_name;
  const double fscale =
      abscissa_scale(axis_record(d.records[7]), source, result.warnings, abscissa_name);
  const OrdinateUnit unit = ordinate_unit(axis_record(d.records[8]), axis_record(d.records[9]),
                                          unit164, source, result.warnings);
  result.quantity = unit.quantity;
  result.units = abscissa_name + ", " + unit.name;
  std::vector<RawPoint> points = points_of(d, form, source);
  attach_coherence(found, d, fscale, points, source, result.warnings);
  result.frf = finish_table(points, unit, fscale, source);
  return result;
}

}  // namespace cutdyn::io::detail
