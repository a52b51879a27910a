// Universal File Format dataset 58 / 58b written from a receptance table [Sdrc1999];
// docs/frf-files.md ("Universal File Format", "Writing").
#include <fmt/format.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "frf_detail.hpp"

namespace cutdyn::io::detail {
namespace {

// A number as the E13.5 field of record 7 and of a single-precision or uneven abscissa
// stores it (6 significant digits), read back.
double as_e13(double x) { return *parse_number(trim(fmt::format("{:13.5E}", x))); }

// Whether f is evenly spaced once its minimum and increment are stored as E13.5 (to 1e-9 of
// the increment); those two numbers.
bool evenly_spaced(const std::vector<double>& f, double& minimum, double& increment) {
  const std::size_t n = f.size();
  minimum = as_e13(f.front());
  increment = as_e13((f.back() - f.front()) / static_cast<double>(n - 1));
  if (!(increment > 0.0)) return false;
  for (std::size_t i = 0; i < n; ++i)
    if (std::abs(minimum + static_cast<double>(i) * increment - f[i]) > 1e-9 * increment)
      return false;
  return true;
}

void append_binary(std::string& out, double x, bool single) {
  const std::uint64_t bits = single ? std::bit_cast<std::uint32_t>(static_cast<float>(x))
                                    : std::bit_cast<std::uint64_t>(x);
  for (int k = 0; k < (single ? 4 : 8); ++k) out += static_cast<char>((bits >> (8 * k)) & 0xffu);
}

// Record 12 as text: per line 6 E13.5 (single), 4 E20.12 (double, even), or per point the
// abscissa as E13.5 and the ordinates as E20.12 (double, uneven).
void append_ascii_values(std::string& out, const std::vector<double>& values, bool single,
                         bool even, bool complex) {
  // Per point: the abscissa (uneven) and one or two ordinates; double precision uneven puts
  // one complex point or two real points on a line [Sdrc1999, 58].
  const std::size_t per_point = (even ? 0 : 1) + (complex ? 2 : 1);
  const std::size_t per_line = single ? 6 : (even ? 4 : (complex ? 3 : 4));
  for (std::size_t i = 0; i < values.size(); ++i) {
    const bool abscissa = !even && i % per_point == 0;
    if (single || abscissa)
      fmt::format_to(std::back_inserter(out), "{:13.5E}", values[i]);
    else
      fmt::format_to(std::back_inserter(out), "{:20.12E}", values[i]);
    if ((i + 1) % per_line == 0 || i + 1 == values.size()) out += '\n';
  }
}

// What differs between the FRF's dataset and its coherence's.
struct Function {
  int type;       // record 6: 4 FRF, 6 coherence
  bool complex;   // record 7's data type: complex (5, 6) or real (2, 4)
  const char* id; // ID line 1 suffix
};

void append_header(std::string& out, const MeasuredFrf& frf, const FrfWriteOptions& o, bool even,
                   double minimum, double increment, std::size_t bytes, const Function& fn) {
  out += "    -1\n";
  if (o.uff_binary)
    out += fmt::format("{:>6}b{:6}{:6}{:12}{:12}{:6}{:6}{:12}{:12}\n", 58, 1, 2, 11, bytes, 0, 0, 0,
                       0);
  else
    out += "    58\n";
  std::string id = o.description.empty() ? std::string(fn.type == 4 ? "NONE" : "Coherence")
                                         : o.description.substr(0, 80 - std::strlen(fn.id)) + fn.id;
  for (char& c : id)
    if (c == '\n' || c == '\r') c = ' ';
  out += id + "\nNONE\nNONE\nNONE\nNONE\n";
  // Record 6: the function, single point excitation, response and reference DOF.
  out += fmt::format("{:5}{:10}{:5}{:10} {:<10}{:10}{:4} {:<10}{:10}{:4}\n", fn.type, 1, 0, 0, "NONE",
                     o.uff_response_node, o.uff_response_direction, "NONE", o.uff_reference_node,
                     o.uff_reference_direction);
  // Record 7: data form.
  const int data_type = (fn.complex ? 5 : 2) + (o.uff_single_precision ? 0 : (fn.complex ? 1 : 2));
  out += fmt::format("{:10}{:10}{:10}{:13.5E}{:13.5E}{:13.5E}\n", data_type,
                     frf.frequency_hz.size(), even ? 1 : 0, even ? minimum : 0.0,
                     even ? increment : 0.0, 0.0);
  // Records 8-11: frequency in Hz; displacement in m over force in N (the coherence: a
  // number); no z axis.
  out += fmt::format("{:10}{:5}{:5}{:5} {:<20} {}\n", 18, 0, 0, 0, "Frequency", "Hz");
  if (fn.type == 4) {
    out += fmt::format("{:10}{:5}{:5}{:5} {:<20} {}\n", 8, 1, 0, 0, "Displacement", "m");
    out += fmt::format("{:10}{:5}{:5}{:5} {:<20} {}\n", 13, 0, 1, 0, "Force", "N");
  } else {
    out += fmt::format("{:10}{:5}{:5}{:5} {:<20} {}\n", 0, 0, 0, 0, "Coherence", "NONE");
    out += fmt::format("{:10}{:5}{:5}{:5} {:<20} {}\n", 0, 0, 0, 0, "NONE", "NONE");
  }
  out += fmt::format("{:10}{:5}{:5}{:5} {:<20} {}\n", 0, 0, 0, 0, "NONE", "NONE");
}

}  // namespace

FrfText format_uff(const MeasuredFrf& frf, const FrfWriteOptions& options) {
  FrfText result;
  Validator v("options");
  for (const auto& [field, direction] :
       {std::pair{"uff_response_direction", options.uff_response_direction},
        std::pair{"uff_reference_direction", options.uff_reference_direction}})
    v.require(direction >= -6 && direction <= 6, field, direction, "",
              "must be a UFF direction from -6 to 6 (1 = +X, 2 = +Y, 3 = +Z)");
  for (const auto& [field, node] : {std::pair{"uff_response_node", options.uff_response_node},
                                    std::pair{"uff_reference_node", options.uff_reference_node}})
    v.require(node >= 0, field, node, "", "must be a node number, at least 0");
  v.throw_if_any();
  const std::vector<double>& f = frf.frequency_hz;
  double minimum = 0.0, increment = 0.0;
  const bool spaced = evenly_spaced(f, minimum, increment);
  if (options.uff_spacing == UffSpacing::kEven && !spaced)
    throw InvalidInput(
        {"frequency_hz: not evenly spaced once the first frequency and the increment "
         "are stored with 6 significant digits (E13.5); write the UFF with uneven "
         "spacing"});
  const bool even = options.uff_spacing == UffSpacing::kEven ||
                    (options.uff_spacing == UffSpacing::kAutomatic && spaced);
  const bool single = options.uff_single_precision;
  // The abscissa (uneven spacing) and the ordinates of each point.
  const auto values_of = [&](bool complex, double& moved) {
    std::vector<double> values;
    values.reserve(f.size() * 3);
    double previous = 0.0;
    for (std::size_t i = 0; i < f.size(); ++i) {
      if (!even) {
        // The abscissa is single precision in ASCII (E13.5); a 58b stores it in the
        // ordinate's precision.
        const double x = options.uff_binary
                             ? (single ? static_cast<double>(static_cast<float>(f[i])) : f[i])
                             : as_e13(f[i]);
        if (i > 0 && !(x > previous))
          throw InvalidInput({"frequency_hz[" + std::to_string(i) + "] = " + format_value(f[i]) +
                              " Hz: equal to the one before once stored with the UFF abscissa's "
                              "precision; write another format"});
        moved = std::max(moved, std::abs(x - f[i]));
        previous = x;
        values.push_back(f[i]);
      }
      if (complex) {
        values.push_back(frf.receptance_m_per_n[i].real());
        values.push_back(frf.receptance_m_per_n[i].imag());
      } else {
        values.push_back(frf.coherence[i]);
      }
    }
    return values;
  };
  double moved = 0.0;
  const auto append_dataset = [&](const Function& fn) {
    const std::vector<double> values = values_of(fn.complex, moved);
    const std::size_t bytes = values.size() * (single ? 4 : 8);
    append_header(result.text, frf, options, even, minimum, increment, bytes, fn);
    if (options.uff_binary) {
      for (double x : values) append_binary(result.text, x, single);
    } else {
      append_ascii_values(result.text, values, single, even, fn.complex);
    }
    result.text += "    -1\n";
  };
  append_dataset({4, true, ""});
  if (!frf.coherence.empty()) append_dataset({6, false, " (coherence)"});
  if (even) {
    for (std::size_t i = 0; i < f.size(); ++i)
      moved = std::max(moved, std::abs(minimum + static_cast<double>(i) * increment - f[i]));
  }
  if (moved > 1e-12 * f.back())
    result.warnings.push_back(
        "the UFF abscissa holds 6 significant digits: frequencies moved by up to " +
        format_value(moved) + " Hz");
  return result;
}

}  // namespace cutdyn::io::detail
