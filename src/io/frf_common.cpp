// Lines, numbers, unit names and the table checks shared by the FRF readers; docs/frf-files.md.
#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <numbers>

#include "frf_detail.hpp"

namespace cutdyn::io::detail {

std::vector<TextLine> split_lines(std::string_view content) {
  std::vector<TextLine> lines;
  std::size_t number = 0;
  for (std::size_t at = 0; at < content.size();) {
    const std::size_t end = content.find('\n', at);
    std::string_view line =
        content.substr(at, end == std::string_view::npos ? std::string_view::npos : end - at);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back({line, ++number});
    if (end == std::string_view::npos) break;
    at = end + 1;
  }
  return lines;
}

std::string_view trim(std::string_view s) {
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f'; };
  while (!s.empty() && blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && blank(s.back())) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split_blanks(std::string_view s) {
  std::vector<std::string_view> fields;
  std::size_t at = 0;
  while (at < s.size()) {
    while (at < s.size() && (s[at] == ' ' || s[at] == '\t' || s[at] == '\r')) ++at;
    if (at >= s.size()) break;
    std::size_t end = at;
    while (end < s.size() && s[end] != ' ' && s[end] != '\t' && s[end] != '\r') ++end;
    fields.push_back(s.substr(at, end - at));
    at = end;
  }
  return fields;
}

std::optional<double> parse_number(std::string_view token) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  if (token.empty() || token.front() == '+') return std::nullopt;
  std::string text(token);
  for (char& c : text)  // Fortran's double-precision exponent: 1.5D+03
    if (c == 'D' || c == 'd') c = 'E';
  double value = 0.0;
  const char* end = text.data() + text.size();
  const auto [stop, ec] = std::from_chars(text.data(), end, value);
  if (stop != end) return std::nullopt;
  if (ec == std::errc::result_out_of_range) {
    // Underflow reads as 0, overflow as infinity (refused later as not finite).
    const bool tiny = text.find("e-") != std::string::npos || text.find("E-") != std::string::npos;
    return tiny ? 0.0 : (text.front() == '-' ? -HUGE_VAL : HUGE_VAL);
  }
  if (ec != std::errc{}) return std::nullopt;
  return value;
}

std::string excerpt(std::string_view s) {
  std::string text(s.substr(0, 40));
  if (s.size() > 40) text += "...";
  return "\"" + text + "\"";
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return out;
}

std::size_t first_binary_byte(std::string_view s) {
  for (std::size_t i = 0; i < s.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if ((c < 0x20 && c != '\t' && c != '\n' && c != '\r' && c != '\f') || c == 0x7f) return i;
  }
  return std::string_view::npos;
}

std::string at_line(std::size_t line, std::string_view what) {
  return "line " + std::to_string(line) + ": " + std::string(what);
}

void fail_at(const std::string& source, std::size_t line, std::string what) {
  throw InvalidInput({at_line(line, what)}, source);
}

void append_shortest(std::string& out, double value) {
  fmt::format_to(std::back_inserter(out), "{}", value);
}

// ---- units ----------------------------------------------------------------------------

namespace {

// Lower case, no blanks, "µ"/"μ" as "u", "**" and "^" dropped before the exponent, "²" as 2.
std::string normalised_unit(std::string_view text) {
  std::string s = lower(trim(text));
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const std::string_view rest = std::string_view(s).substr(i);
    if (rest.starts_with("\xc2\xb5") || rest.starts_with("\xce\xbc")) {  // µ (micro), μ (mu)
      out += 'u';
      ++i;
    } else if (rest.starts_with("\xc2\xb2")) {  // ²
      out += '2';
      ++i;
    } else if (rest.starts_with("**")) {
      ++i;
    } else if (s[i] != ' ' && s[i] != '^' && s[i] != '[' && s[i] != ']') {
      out += s[i];
    }
  }
  if (out.size() >= 2 && out.front() == '(' && out.back() == ')')
    out = out.substr(1, out.size() - 2);
  return out;
}

std::optional<double> length_unit(std::string_view s) {
  if (s == "m") return 1.0;
  if (s == "mm") return 1e-3;
  if (s == "um" || s == "micron" || s == "microns") return 1e-6;
  if (s == "in" || s == "inch") return 0.0254;
  return std::nullopt;
}

}  // namespace

std::optional<OrdinateUnit> parse_response_unit(std::string_view text) {
  const std::string s = normalised_unit(text);
  if (s == "g") return OrdinateUnit{FrfQuantity::kAccelerance, 9.80665, "g"};
  if (auto l = length_unit(s))
    return OrdinateUnit{FrfQuantity::kReceptance, *l, std::string(trim(text))};
  const std::size_t slash = s.find('/');
  if (slash == std::string::npos) return std::nullopt;
  const auto l = length_unit(s.substr(0, slash));
  const std::string time = s.substr(slash + 1);
  if (!l) return std::nullopt;
  if (time == "s") return OrdinateUnit{FrfQuantity::kMobility, *l, std::string(trim(text))};
  if (time == "s2") return OrdinateUnit{FrfQuantity::kAccelerance, *l, std::string(trim(text))};
  return std::nullopt;
}

std::optional<double> parse_force_unit(std::string_view text) {
  const std::string s = normalised_unit(text);
  if (s == "n") return 1.0;
  if (s == "kn") return 1e3;
  if (s == "lbf" || s == "lb") return 4.4482216152605;  // the pound-force, exactly
  return std::nullopt;
}

std::optional<OrdinateUnit> parse_ordinate_unit(std::string_view text) {
  const std::string s = normalised_unit(text);
  const std::size_t slash = s.rfind('/');
  if (slash == std::string::npos) return std::nullopt;
  const auto force = parse_force_unit(s.substr(slash + 1));
  auto response = parse_response_unit(s.substr(0, slash));
  if (!force || !response) return std::nullopt;
  response->scale /= *force;
  response->name = std::string(trim(text));
  return response;
}

std::optional<double> parse_frequency_unit(std::string_view text) {
  const std::string s = normalised_unit(text);
  if (s == "hz" || s == "1/s") return 1.0;
  if (s == "khz") return 1e3;
  if (s == "rad/s") return 0.5 / std::numbers::pi;
  return std::nullopt;
}

// ---- the table ------------------------------------------------------------------------

MeasuredFrf finish_table(const std::vector<RawPoint>& points, const OrdinateUnit& unit,
                         double frequency_scale, const std::string& source) {
  constexpr std::size_t kMaxProblems = 12;
  Validator v;
  std::size_t more = 0;
  const auto problem = [&](std::size_t line, const std::string& what) {
    if (v.problems().size() < kMaxProblems)
      v.add(at_line(line, what));
    else
      ++more;
  };
  MeasuredFrf out;
  out.frequency_hz.reserve(points.size());
  out.receptance_m_per_n.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const RawPoint& p = points[i];
    const double f = p.frequency * frequency_scale;
    if (!std::isfinite(p.frequency)) {
      problem(p.line, "frequency " + format_value(p.frequency) + " is not a finite number");
    } else if (f < 0.0) {
      problem(p.line, "frequency " + format_value(f) + " Hz is negative");
    } else if (i > 0 && std::isfinite(points[i - 1].frequency) &&
               !(p.frequency > points[i - 1].frequency)) {
      problem(p.line, "frequency " + format_value(f) + " Hz is not greater than the one before (" +
                          format_value(points[i - 1].frequency * frequency_scale) + " Hz)");
    }
    if (!std::isfinite(p.value.real()) || !std::isfinite(p.value.imag())) {
      problem(p.line, std::string("the ") + to_string(unit.quantity) + " (" +
                          format_value(p.value.real()) + ", " + format_value(p.value.imag()) +
                          ") is not a finite number");
      continue;
    }
    if (unit.quantity != FrfQuantity::kReceptance && f == 0.0) {
      problem(p.line, std::string("the ") + to_string(unit.quantity) +
                          " at 0 Hz cannot be converted to receptance (" +
                          (unit.quantity == FrfQuantity::kMobility ? "G = Y/(iω)" : "G = A/(−ω²)") +
                          " needs ω > 0); leave that point out");
      continue;
    }
    if (p.coherence) {
      const double c = *p.coherence;
      if (!(c >= 0.0 && c <= 1.0)) {
        problem(p.line, "coherence " + format_value(c) +
                            " is not 0 to 1 (the ordinary coherence γ², not a percentage or dB)");
        continue;
      }
      out.coherence.push_back(c);
    }
    out.frequency_hz.push_back(f);
    out.receptance_m_per_n.push_back(to_receptance(unit.quantity, p.value * unit.scale, f));
  }
  if (more > 0) v.add("... and " + std::to_string(more) + " more problems like these");
  if (v.ok() && points.size() < 3) {
    v.add(std::to_string(points.size()) + (points.size() == 1 ? " data point" : " data points") +
          ": an FRF needs at least 3");
  }
  v.throw_if_any(source);
  // Conversion can still overflow (an enormous accelerance at a tiny frequency).
  if (const auto problems = out.validate(); !problems.empty()) throw InvalidInput(problems, source);
  return out;
}

}  // namespace cutdyn::io::detail
