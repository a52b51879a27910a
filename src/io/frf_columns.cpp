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

// Words that name a column rather than a unit ("Freq Hz Real m/N Imag Real", the trailer
// CutPro writes after its first numbers; "Frequency Real Imaginary" headers).
bool is_column_label(std::string_view word) {
  const std::string w = lower(word);
  for (const char* label : {"f", "freq", "freq.", "frequency", "re", "real", "im", "imag",
                            "imag.", "imaginary", "part", "value", "values", "data", "coh",
                            "coh.", "coherence", "gamma^2", "γ²"})
    if (w == label) return true;
  return false;
}

// What an unknown word that stands where a unit stands (in brackets, or written as one,
// letters over letters) is, for the error: a dynamic stiffness (force per length), a speed,
// a phase or level, or a unit cutdyn does not know. Empty when the word does not look like a
// unit at all (a header's prose).
std::string unknown_unit_problem(std::string_view word, bool bracketed) {
  const std::string w = lower(trim(word));
  const auto letters_only = [](std::string_view t) {
    if (t.empty()) return false;
    for (char c : t)
      if (!((c >= 'a' && c <= 'z') || c == '^' || c == '*' || c == '(' || c == ')' ||
            (c >= '0' && c <= '9')))
        return false;
    return t.front() >= 'a' && t.front() <= 'z';
  };
  const std::size_t slash = w.find('/');
  const bool unit_like = bracketed || (slash != std::string::npos && letters_only(w.substr(0, slash)) &&
                                       letters_only(w.substr(slash + 1)));
  const std::string quoted = excerpt(trim(word));
  for (const char* speed : {"rpm", "cpm", "rev/min", "1/min", "r/min"})
    if (w == speed)
      return quoted + " is a speed, not a frequency unit of an FRF (Hz, kHz, rad/s or 1/s)";
  for (const char* phase : {"deg", "degree", "degrees", "rad", "db"})
    if (w == phase)
      return quoted + " is a phase or level unit: cutdyn reads real and imaginary parts, not "
                      "magnitude and phase";
  if (!unit_like) return {};
  if (slash != std::string::npos && parse_force_unit(w.substr(0, slash)) &&
      parse_response_unit(w.substr(slash + 1)))
    return quoted + " is a dynamic stiffness (force per displacement); cutdyn reads a response "
                    "per force (receptance m/N, mobility, accelerance): export the receptance";
  return quoted + " is not a unit cutdyn knows (a response m, mm, um, in, m/s, m/s^2 or g over "
                  "N, kN or lbf; frequencies Hz, kHz, rad/s, 1/s); state the file's units with "
                  "--units (cutdyn fit) or units = \"...\" ([[frf]])";
}

// The units a CutPro file states (on its header line or after the numbers of its first data
// line): the first one recognised of each kind; a second, different one is an error, and so
// is a word in a unit's place that is no unit cutdyn reads.
struct StatedUnits {
  std::optional<OrdinateUnit> ordinate;
  std::optional<double> frequency_scale;
  std::string frequency_name;
  std::size_t ordinate_line = 0;

  // Takes `word` if it names a unit; refuses it if it stands for a unit cutdyn does not read;
  // whether it was taken.
  bool take_or_refuse(std::string_view word, bool bracketed, std::size_t line,
                      const std::string& source) {
    if (take(word, line, source)) return true;
    if (const std::string problem = unknown_unit_problem(word, bracketed); !problem.empty())
      fail_at(source, line, problem);
    return false;
  }

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

  // A header word may carry its unit in brackets: "real[m/N]", "Frequency(Hz)"; after a
  // column's label ("re", "Frequency", ...) what is in the brackets must be a unit cutdyn
  // reads. A word of its own is taken if it is a unit, refused if it looks like one cutdyn
  // does not read, and otherwise (prose, column labels) passed over.
  void take_from_header(std::string_view word, std::size_t line, const std::string& source) {
    const std::size_t open = word.find_first_of("[(");
    if (open != std::string_view::npos && open > 0) {
      const std::size_t close = word.find_last_of("])");
      if (close != std::string_view::npos && close > open + 1) {
        take_or_refuse(word.substr(open + 1, close - open - 1),
                       is_column_label(word.substr(0, open)), line, source);
        return;
      }
    }
    if (is_column_label(word)) return;
    take_or_refuse(word, false, line, source);
  }
};

const char* const kPartNames[4] = {"the frequency", "the real part", "the imaginary part",
                                   "the coherence"};

}  // namespace

GivenUnits parse_given_units(std::string_view text, const std::string& source) {
  GivenUnits g;
  bool have_ordinate = false, have_frequency = false;
  std::vector<std::string> problems;
  std::string_view rest = text;
  while (true) {
    const std::size_t comma = rest.find(',');
    const std::string_view piece = trim(rest.substr(0, comma));
    if (const auto f = parse_frequency_unit(piece); f && !have_frequency) {
      g.frequency_scale = *f;
      g.frequency_name = std::string(piece);
      have_frequency = true;
    } else if (const auto u = parse_ordinate_unit(piece); u && !have_ordinate) {
      g.ordinate = *u;
      have_ordinate = true;
    } else {
      problems.push_back("units = " + excerpt(text) + ": " + excerpt(piece) +
                         " is not a frequency unit (Hz, kHz, rad/s, 1/s) or an FRF unit (m/N, "
                         "mm/N, (m/s)/N, g/N, ...) given once");
    }
    if (comma == std::string_view::npos) break;
    rest = rest.substr(comma + 1);
  }
  if (problems.empty() && !have_ordinate)
    problems.push_back("units = " + excerpt(text) +
                       ": no FRF unit (m/N, mm/N, (m/s)/N, g/N, ...); e.g. \"Hz, mm/N\"");
  if (!problems.empty()) throw InvalidInput(problems, source);
  return g;
}

FrfReadResult read_cutpro_text(std::string_view content, const std::string& source,
                               const std::optional<GivenUnits>& given) {
  FrfReadResult result;
  result.format = FrfFormat::kCutPro;
  StatedUnits units;
  std::vector<RawPoint> points;
  LineProblems problems;
  bool data_started = false;
  std::size_t columns = 3;  // 4 with a coherence column
  for (const TextLine& line : split_lines(content)) {
    const std::string_view text = trim(line.text);
    if (text.empty() || text.front() == '%' || text.front() == '#' || text.front() == ';') continue;
    const std::vector<std::string_view> fields = split_blanks(text);
    if (!data_started && !parse_number(fields[0])) {
      if (!given)
        for (std::string_view word : fields) units.take_from_header(word, line.number, source);
      continue;  // a header line of words before the data
    }
    const bool first = !data_started;
    data_started = true;
    // A fourth number on the first data line is the coherence γ² (0…1), and every line then
    // has it; words after the numbers are the trailer's labels and units.
    if (first) columns = fields.size() > 3 && parse_number(fields[3]) ? 4 : 3;
    std::array<double, 4> v{};
    std::size_t numbers = 0;
    bool bad = false;
    for (std::size_t i = 0; i < fields.size() && i < columns; ++i) {
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
    const char* expected =
        columns == 4 ? "4: frequency (Hz), real and imaginary part (m/N), coherence (as the first "
                       "data line)"
                     : "3: frequency (Hz), real and imaginary part (m/N)";
    if (numbers < columns) {
      problems.add(line.number, std::to_string(numbers) + (numbers == 1 ? " value" : " values") +
                                    "; a data line has " + std::string(expected));
      continue;
    }
    for (std::size_t i = columns; i < fields.size(); ++i) {
      if (first && !parse_number(fields[i])) {
        // The standard trailer's "Freq", "Real", ...; with units given, every word.
        if (given || is_column_label(fields[i])) continue;
        if (!units.take_or_refuse(fields[i], false, line.number, source))
          result.warnings.push_back(at_line(line.number, "the word " + excerpt(fields[i]) +
                                                             " after the numbers is not a unit "
                                                             "cutdyn knows; ignored"));
        continue;
      }
      problems.add(line.number,
                   std::to_string(fields.size()) + " fields; a data line has " +
                       std::string(expected));
      break;
    }
    RawPoint point{v[0], {v[1], v[2]}, line.number, std::nullopt};
    if (columns == 4) point.coherence = v[3];
    points.push_back(point);
  }
  problems.throw_if_any(source);
  if (!data_started) throw InvalidInput({"no data line (frequency, real, imaginary)"}, source);
  if (given) {
    units.ordinate = given->ordinate;
    units.frequency_scale = given->frequency_scale;
    units.frequency_name = given->frequency_name;
  }
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
constexpr const char* kCoherenceColumn = "coherence";  // optional: γ², 0…1

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
  int coherence = -1;  // its column, or -1
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
  c.coherence = find(kCoherenceColumn);
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
    if (bad) continue;
    RawPoint point{v[0], {v[1], v[2]}, line.number, std::nullopt};
    if (columns->coherence >= 0) {
      const auto i = static_cast<std::size_t>(columns->coherence);
      const auto x = i < fields.size() ? parse_number(fields[i]) : std::nullopt;
      if (i >= fields.size())
        problems.add(line.number, std::to_string(fields.size()) + " fields, no " +
                                      kCoherenceColumn + " (column " + std::to_string(i + 1) +
                                      " of the header)");
      else if (!x)
        problems.add(line.number, std::string(kCoherenceColumn) + " = " + excerpt(fields[i]) +
                                      " is not a number");
      else
        point.coherence = *x;
      if (!x) continue;
    }
    points.push_back(point);
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
  const bool coherence = !frf.coherence.empty();
  out += "% receptance: frequency (Hz), real part (m/N), imaginary part (m/N)";
  out += coherence ? ", coherence\n" : "\n";
  for (std::size_t i = 0; i < frf.frequency_hz.size(); ++i) {
    append_shortest(out, frf.frequency_hz[i]);
    out += '\t';
    append_shortest(out, frf.receptance_m_per_n[i].real());
    out += '\t';
    append_shortest(out, frf.receptance_m_per_n[i].imag());
    if (coherence) {
      out += '\t';
      append_shortest(out, frf.coherence[i]);
    }
    out += '\n';
  }
  return out;
}

std::string format_csv(const MeasuredFrf& frf, const FrfWriteOptions& options) {
  std::string out;
  if (!options.description.empty()) out += "# " + one_line(options.description) + "\n";
  const bool coherence = !frf.coherence.empty();
  out += coherence ? "frequency_hz,real_m_per_n,imag_m_per_n,coherence\n"
                   : "frequency_hz,real_m_per_n,imag_m_per_n\n";
  for (std::size_t i = 0; i < frf.frequency_hz.size(); ++i) {
    append_shortest(out, frf.frequency_hz[i]);
    out += ',';
    append_shortest(out, frf.receptance_m_per_n[i].real());
    out += ',';
    append_shortest(out, frf.receptance_m_per_n[i].imag());
    if (coherence) {
      out += ',';
      append_shortest(out, frf.coherence[i]);
    }
    out += '\n';
  }
  return out;
}

}  // namespace cutdyn::io::detail
