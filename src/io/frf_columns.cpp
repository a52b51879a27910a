// The column formats of FRF files: CutPro-style text and CSV, read and written;
// docs/frf-files.md ("CutPro text", "CSV").
#include <array>
#include <cmath>

#include "frf_detail.hpp"

namespace cutdyn::io::detail {
namespace {

constexpr std::size_t kMaxLineProblems = 12;

// Collects line problems up to a limit; throws them at the end.
struct LineProblems {
  std::vector<std::string> list;
  std::size_t more = 0;
  void add(std::size_t line, const std::string& what) {
    if (list.size() < kMaxLineProblems)
      list.push_back(at_line(line, what));
    else
      ++more;
  }
  void throw_if_any(const std::string& source) {
    if (list.empty()) return;
    if (more > 0) list.push_back("... and " + std::to_string(more) + " more lines like these");
    throw InvalidInput(list, source);
  }
};

// The units a CutPro file states (on its header line or after the numbers of its first data
// line): the first one recognised of each kind; a second, different one is an error.
struct StatedUnits {
  std::optional<OrdinateUnit> ordinate;
  std::optional<double> frequency_scale;
  std::string frequency_name;
  std::size_t ordinate_line = 0;

  // Whether `word` names a unit (and takes it).
  bool take(std::string_view word, std::size_t line, const std::string& source) {
    if (const auto f = parse_frequency_unit(word)) {
      if (frequency_scale && *frequency_scale != *f)
        fail_at(source, line,
                "a second frequency unit " + excerpt(word) + " (" + frequency_name +
                    " was stated before)");
      frequency_scale = f;
      frequency_name = std::string(word);
      return true;
    }
    if (const auto u = parse_ordinate_unit(word)) {
      if (ordinate && (ordinate->scale != u->scale || ordinate->quantity != u->quantity))
        fail_at(source, line,
                "a second FRF unit " + excerpt(word) + " (" + ordinate->name +
                    " was stated on line " + std::to_string(ordinate_line) + ")");
      ordinate = u;
      ordinate_line = line;
      return true;
    }
    return false;
  }

  // A header word may carry its unit in brackets: "real[m/N]", "Frequency(Hz)".
  void take_from_header(std::string_view word, std::size_t line, const std::string& source) {
    const std::size_t open = word.find_first_of("[(");
    if (open != std::string_view::npos) {
      const std::size_t close = word.find_last_of("])");
      if (close != std::string_view::npos && close > open + 1) {
        if (take(word.substr(open + 1, close - open - 1), line, source)) return;
      }
    }
    take(word, line, source);
  }
};

const char* const kPartNames[3] = {"the frequency", "the real part", "the imaginary part"};

}  // namespace

FrfReadResult read_cutpro_text(std::string_view content, const std::string& source) {
  FrfReadResult result;
  result.format = FrfFormat::kCutPro;
  StatedUnits units;
  std::vector<RawPoint> points;
  LineProblems problems;
  bool data_started = false;
  for (const TextLine& line : split_lines(content)) {
    const std::string_view text = trim(line.text);
    if (text.empty() || text.front() == '%' || text.front() == '#' || text.front() == ';') continue;
    const std::vector<std::string_view> fields = split_blanks(text);
    if (!data_started && !parse_number(fields[0])) {
      for (std::string_view word : fields) units.take_from_header(word, line.number, source);
      continue;  // a header line of words before the data
    }
    const bool first = !data_started;
    data_started = true;
    std::array<double, 3> v{};
    std::size_t numbers = 0;
    bool bad = false;
    for (std::size_t i = 0; i < fields.size() && i < 3; ++i) {
      const auto x = parse_number(fields[i]);
      if (!x) {
        problems.add(line.number, excerpt(fields[i]) + " is not a number (" + kPartNames[i] + ")");
        bad = true;
        break;
      }
      v[i] = *x;
      ++numbers;
    }
    if (bad) continue;
    if (numbers < 3) {
      problems.add(line.number, std::to_string(numbers) + (numbers == 1 ? " value" : " values") +
                                    "; a data line has 3: frequency (Hz), real and imaginary part "
                                    "(m/N)");
      continue;
    }
    for (std::size_t i = 3; i < fields.size(); ++i) {
      if (first && !parse_number(fields[i])) {
        if (!units.take(fields[i], line.number, source))
          result.warnings.push_back(at_line(line.number, "the word " + excerpt(fields[i]) +
                                                             " after the numbers is not a unit "
                                                             "cutdyn knows; ignored"));
        continue;
      }
      problems.add(line.number, std::to_string(fields.size()) +
                                    " fields; a data line has 3: frequency (Hz), real and "
                                    "imaginary part (m/N)");
      break;
    }
    points.push_back({v[0], {v[1], v[2]}, line.number});
  }
  problems.throw_if_any(source);
  if (!data_started) throw InvalidInput({"no data line (frequency, real, imaginary)"}, source);
  const OrdinateUnit unit =
      units.ordinate.value_or(OrdinateUnit{FrfQuantity::kReceptance, 1.0, "m/N"});
  result.quantity = unit.quantity;
  result.units =
      (units.frequency_scale ? units.frequency_name : std::string("Hz")) + ", " + unit.name;
  result.frf = finish_table(points, unit, units.frequency_scale.value_or(1.0), source);
  return result;
}

// ---- CSV ------------------------------------------------------------------------------

namespace {

struct CsvPair {
  FrfQuantity quantity;
  const char* real;
  const char* imag;
  const char* unit;
};
constexpr CsvPair kCsvPairs[3] = {
    {FrfQuantity::kReceptance, "real_m_per_n", "imag_m_per_n", "m/N"},
    {FrfQuantity::kMobility, "real_m_per_s_per_n", "imag_m_per_s_per_n", "m/s/N"},
    {FrfQuantity::kAccelerance, "real_m_per_s2_per_n", "imag_m_per_s2_per_n", "m/s^2/N"}};
constexpr const char* kFrequencyColumn = "frequency_hz";

std::vector<std::string_view> split_commas(std::string_view line) {
  std::vector<std::string_view> fields;
  for (std::size_t at = 0;;) {
    const std::size_t comma = line.find(',', at);
    std::string_view f =
        trim(line.substr(at, comma == std::string_view::npos ? line.npos : comma - at));
    if (f.size() >= 2 && f.front() == '"' && f.back() == '"') f = trim(f.substr(1, f.size() - 2));
    fields.push_back(f);
    if (comma == std::string_view::npos) break;
    at = comma + 1;
  }
  return fields;
}

// Column indices of the header: frequency, real, imaginary; and the quantity.
struct CsvColumns {
  int index[3] = {-1, -1, -1};
  const CsvPair* pair = nullptr;
};

CsvColumns csv_columns(const TextLine& line, const std::string& source) {
  const std::vector<std::string_view> names = split_commas(line.text);
  bool letters = false;
  for (char c : line.text) letters = letters || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z');
  if (!letters || parse_number(names[0]))
    fail_at(source, line.number,
            "a CSV FRF file starts with a header naming its columns, e.g. "
            "frequency_hz,real_m_per_n,imag_m_per_n; this line has none (numbers with "
            "decimal commas also look like CSV: write decimal points)");
  const auto find = [&](const char* name) {
    int found = -1;
    for (std::size_t i = 0; i < names.size(); ++i) {
      if (lower(names[i]) != name) continue;
      if (found >= 0)
        fail_at(source, line.number, std::string("column ") + name + " appears twice");
      found = static_cast<int>(i);
    }
    return found;
  };
  CsvColumns c;
  c.index[0] = find(kFrequencyColumn);
  std::vector<std::string> missing;
  if (c.index[0] < 0) missing.push_back(kFrequencyColumn);
  std::string complete;
  for (const CsvPair& p : kCsvPairs) {
    const int re = find(p.real), im = find(p.imag);
    if (re < 0 && im < 0) continue;
    if (re < 0 || im < 0) {
      missing.push_back(re < 0 ? p.real : p.imag);
      continue;
    }
    if (c.pair)
      fail_at(source, line.number,
              std::string("columns of both ") + to_string(c.pair->quantity) + " and " +
                  to_string(p.quantity) + "; keep one pair of real and imaginary columns");
    c.pair = &p;
    c.index[1] = re;
    c.index[2] = im;
  }
  if (!c.pair && missing.size() == (c.index[0] < 0 ? 1u : 0u))
    missing.push_back(
        "real_m_per_n and imag_m_per_n (or the mobility pair real_m_per_s_per_n, "
        "imag_m_per_s_per_n, or the accelerance pair real_m_per_s2_per_n, "
        "imag_m_per_s2_per_n)");
  if (!missing.empty()) {
    std::string text = "missing column" + std::string(missing.size() > 1 ? "s " : " ");
    for (std::size_t i = 0; i < missing.size(); ++i) text += (i ? ", " : "") + missing[i];
    fail_at(source, line.number, text + " (the header is " + excerpt(trim(line.text)) + ")");
  }
  return c;
}

}  // namespace

FrfReadResult read_csv_text(std::string_view content, const std::string& source) {
  FrfReadResult result;
  result.format = FrfFormat::kCsv;
  std::optional<CsvColumns> columns;
  std::vector<RawPoint> points;
  LineProblems problems;
  for (const TextLine& line : split_lines(content)) {
    const std::string_view text = trim(line.text);
    if (text.empty() || text.front() == '#') continue;
    if (!columns) {
      columns = csv_columns(line, source);
      continue;
    }
    const std::vector<std::string_view> fields = split_commas(text);
    double v[3] = {0.0, 0.0, 0.0};
    bool bad = false;
    for (int k = 0; k < 3 && !bad; ++k) {
      const std::size_t i = static_cast<std::size_t>(columns->index[k]);
      const char* name =
          k == 0 ? kFrequencyColumn : (k == 1 ? columns->pair->real : columns->pair->imag);
      bad = true;
      if (i >= fields.size())
        problems.add(line.number, std::to_string(fields.size()) + " fields, no " + name +
                                      " (column " + std::to_string(i + 1) + " of the header)");
      else if (fields[i].empty())
        problems.add(line.number, std::string(name) + " is empty");
      else if (const auto x = parse_number(fields[i]); !x)
        problems.add(line.number,
                     std::string(name) + " = " + excerpt(fields[i]) + " is not a number");
      else {
        v[k] = *x;
        bad = false;
      }
    }
    if (!bad) points.push_back({v[0], {v[1], v[2]}, line.number});
  }
  problems.throw_if_any(source);
  if (!columns) throw InvalidInput({"no header line and no data"}, source);
  if (points.empty())
    throw InvalidInput({"no data line after the header (a CSV FRF needs at least 3 points)"},
                       source);
  const OrdinateUnit unit{columns->pair->quantity, 1.0, columns->pair->unit};
  result.quantity = unit.quantity;
  result.units = "Hz, " + unit.name;
  result.frf = finish_table(points, unit, 1.0, source);
  return result;
}

// ---- writers --------------------------------------------------------------------------

namespace {

std::string one_line(const std::string& text) {
  std::string out = text;
  for (char& c : out)
    if (c == '\n' || c == '\r') c = ' ';
  return out;
}

}  // namespace

std::string format_cutpro(const MeasuredFrf& frf, const FrfWriteOptions& options) {
  std::string out;
  if (!options.description.empty()) out += "% " + one_line(options.description) + "\n";
  out += "% receptance: frequency (Hz), real part (m/N), imaginary part (m/N)\n";
  for (std::size_t i = 0; i < frf.frequency_hz.size(); ++i) {
    append_shortest(out, frf.frequency_hz[i]);
    out += '\t';
    append_shortest(out, frf.receptance_m_per_n[i].real());
    out += '\t';
    append_shortest(out, frf.receptance_m_per_n[i].imag());
    out += '\n';
  }
  return out;
}

std::string format_csv(const MeasuredFrf& frf, const FrfWriteOptions& options) {
  std::string out;
  if (!options.description.empty()) out += "# " + one_line(options.description) + "\n";
  out += "frequency_hz,real_m_per_n,imag_m_per_n\n";
  for (std::size_t i = 0; i < frf.frequency_hz.size(); ++i) {
    append_shortest(out, frf.frequency_hz[i]);
    out += ',';
    append_shortest(out, frf.receptance_m_per_n[i].real());
    out += ',';
    append_shortest(out, frf.receptance_m_per_n[i].imag());
    out += '\n';
  }
  return out;
}

}  // namespace cutdyn::io::detail
