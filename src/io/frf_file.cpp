// FRF files: the format detected, the file read or written, the conversions to receptance;
// docs/frf-files.md.
#include "cutdyn/io/frf_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <numbers>
#include <system_error>

#include "cutdyn/io/inputs.hpp"
#include "frf_detail.hpp"

namespace cutdyn {

const char* to_string(FrfFormat format) {
  switch (format) {
    case FrfFormat::kCutPro:
      return "frf";
    case FrfFormat::kCsv:
      return "csv";
    case FrfFormat::kUff:
      return "uff";
  }
  return "frf";
}

std::optional<FrfFormat> parse_frf_format(std::string_view name) {
  if (name == "frf") return FrfFormat::kCutPro;
  if (name == "csv") return FrfFormat::kCsv;
  if (name == "uff" || name == "unv") return FrfFormat::kUff;
  return std::nullopt;
}

const char* to_string(FrfQuantity quantity) {
  switch (quantity) {
    case FrfQuantity::kReceptance:
      return "receptance";
    case FrfQuantity::kMobility:
      return "mobility";
    case FrfQuantity::kAccelerance:
      return "accelerance";
  }
  return "receptance";
}

double negative_imaginary_share(const MeasuredFrf& g) {
  double negative = 0.0, all = 0.0;
  for (std::size_t k = 0; k < g.frequency_hz.size(); ++k) {
    if (!(g.frequency_hz[k] > 0.0)) continue;
    const double im = g.receptance_m_per_n[k].imag();
    all += im * im;
    if (im < 0.0) negative += im * im;
  }
  return all > 0.0 ? negative / all : 1.0;
}

double peak_quadrature(const MeasuredFrf& g) {
  const auto& v = g.receptance_m_per_n;
  std::vector<std::size_t> peaks;
  double top = 0.0;
  for (std::size_t k = 1; k + 1 < v.size(); ++k) {
    const double m = std::abs(v[k]);
    if (m > 0.0 && m >= std::abs(v[k - 1]) && m >= std::abs(v[k + 1])) {
      peaks.push_back(k);
      top = std::max(top, m);
    }
  }
  double sum = 0.0, weight = 0.0;
  for (std::size_t k : peaks) {
    const double m = std::abs(v[k]);
    if (m < 0.3 * top) continue;
    sum += m * m * (-v[k].imag() / m);
    weight += m * m;
  }
  return weight > 0.0 ? sum / weight : 1.0;
}

namespace {

constexpr double kLeastNegativeShare = 0.75;  // of Im G, by its square
constexpr double kLeastPeakQuadrature = 0.5;  // −Im G/|G| at the peaks: within 60° of −90°

bool plausible(const MeasuredFrf& g) {
  return negative_imaginary_share(g) >= kLeastNegativeShare &&
         peak_quadrature(g) >= kLeastPeakQuadrature;
}

}  // namespace

std::string direct_receptance_problem(const MeasuredFrf& receptance, FrfQuantity stored) {
  if (plausible(receptance)) return {};
  const double share = negative_imaginary_share(receptance);
  const double quadrature = peak_quadrature(receptance);
  // The values as the file stored them, read as each quantity in turn.
  const auto share_as = [&](FrfQuantity q) {
    MeasuredFrf t;
    for (std::size_t k = 0; k < receptance.frequency_hz.size(); ++k) {
      const double f = receptance.frequency_hz[k];
      if (!(f > 0.0)) continue;
      const double w = 2.0 * std::numbers::pi * f;
      std::complex<double> value = receptance.receptance_m_per_n[k];  // undo the conversion
      if (stored == FrfQuantity::kMobility) value *= std::complex<double>(0.0, w);
      if (stored == FrfQuantity::kAccelerance) value *= -w * w;
      t.frequency_hz.push_back(f);
      t.receptance_m_per_n.push_back(to_receptance(q, value, f));
    }
    return plausible(t);
  };
  std::string problem =
      "as a direct receptance its imaginary part is positive over " +
      format_value(std::round(1000.0 * (1.0 - share)) / 10.0) +
      " % of the response (by its square) and its phase at the resonance peaks is " +
      format_value(std::round(std::asin(std::clamp(-quadrature, -1.0, 1.0)) * 1800.0 /
                              std::numbers::pi) /
                   10.0) +
      "° on average; a passive structure's direct receptance has Im G ≤ 0 at every frequency "
      "and lags the force by about 90° at its peaks";
  for (FrfQuantity q :
       {FrfQuantity::kReceptance, FrfQuantity::kMobility, FrfQuantity::kAccelerance}) {
    if (q == stored || !share_as(q)) continue;
    return problem + ". The values behave like " +
           (q == FrfQuantity::kAccelerance ? "an " : "a ") + to_string(q) + " (" +
           (q == FrfQuantity::kReceptance ? "displacement" : q == FrfQuantity::kMobility
                                                                  ? "velocity"
                                                                  : "acceleration") +
           " per force) stored as " + (stored == FrfQuantity::kAccelerance ? "an " : "a ") +
           to_string(stored) + ": state the units (a unit such as " +
           (q == FrfQuantity::kReceptance ? "m/N" : q == FrfQuantity::kMobility ? "(m/s)/N"
                                                                                : "(m/s^2)/N") +
           " in the header, units = \"...\" or --units, or the CSV columns of that quantity)";
  }
  return problem + " (a cross receptance belongs in direction = \"xy\"; or the table is mostly "
                   "noise)";
}

std::complex<double> to_receptance(FrfQuantity quantity, std::complex<double> value, double f_hz) {
  const double omega = 2.0 * std::numbers::pi * f_hz;
  switch (quantity) {
    case FrfQuantity::kReceptance:
      return value;
    case FrfQuantity::kMobility:  // Y = iω G, so G = Y/(iω)
      return value / std::complex<double>(0.0, omega);
    case FrfQuantity::kAccelerance:  // A = −ω² G, so G = A/(−ω²)
      return value / (-omega * omega);
  }
  return value;
}

namespace {

using io::detail::TextLine;

std::string binary_byte(char c) {
  return fmt::format("not a text file (byte 0x{:02x}, a control character); is it binary?",
                     static_cast<unsigned char>(c));
}

bool uff_extension(std::string_view extension) {
  const std::string e = io::detail::lower(extension);
  return e == ".uff" || e == ".unv" || e == ".uf";
}

// The format of `content` (BOM already removed); throws for an empty or non-text content.
FrfFormat detect(std::string_view content, const std::string& source, std::string_view extension) {
  const TextLine* first = nullptr;
  const std::vector<TextLine> lines = io::detail::split_lines(content);
  for (const TextLine& l : lines) {
    if (!io::detail::trim(l.text).empty()) {
      first = &l;
      break;
    }
  }
  if (!first)
    throw InvalidInput({content.empty() ? "the file is empty" : "the file holds only blank lines"},
                       source);
  if (io::detail::trim(first->text) == "-1") return FrfFormat::kUff;
  if (const std::size_t b = io::detail::first_binary_byte(content); b != std::string_view::npos) {
    const std::size_t line =
        static_cast<std::size_t>(
            std::count(content.begin(), content.begin() + static_cast<std::ptrdiff_t>(b), '\n')) +
        1;
    throw InvalidInput({io::detail::at_line(line, binary_byte(content[b]))}, source);
  }
  if (uff_extension(extension))
    io::detail::fail_at(source, first->number,
                        "a universal file starts with a -1 line; this one starts with " +
                            io::detail::excerpt(io::detail::trim(first->text)));
  for (const TextLine& l : lines) {
    const std::string_view t = io::detail::trim(l.text);
    if (t.empty() || t.front() == '%' || t.front() == '#' || t.front() == ';') continue;
    return t.find(',') != std::string_view::npos ? FrfFormat::kCsv : FrfFormat::kCutPro;
  }
  return FrfFormat::kCutPro;  // comments only: the text reader says there is no data
}

}  // namespace

FrfReadResult parse_frf(std::string_view content, const std::string& source,
                        const FrfFileOptions& options, std::string_view extension) {
  if (content.starts_with("\xef\xbb\xbf")) content.remove_prefix(3);  // UTF-8 byte order mark
  const FrfFormat format = options.format ? *options.format : detect(content, source, extension);
  if (options.units && format != FrfFormat::kCutPro)
    throw InvalidInput({"units = " + io::detail::excerpt(*options.units) + ": this is a " +
                        to_string(format) +
                        " file, which states its own units (a CSV in its column names, a "
                        "universal file in its records); units are given only for CutPro text"},
                       source);
  FrfReadResult result;
  switch (format) {
    case FrfFormat::kCutPro:
      result = io::detail::read_cutpro_text(
          content, source,
          options.units ? std::optional(io::detail::parse_given_units(*options.units, source))
                        : std::nullopt);
      break;
    case FrfFormat::kCsv:
      result = io::detail::read_csv_text(content, source);
      break;
    case FrfFormat::kUff:
      result = io::detail::read_uff_text(content, source, options);
      break;
  }
  if (options.dataset && format != FrfFormat::kUff)
    result.warnings.push_back("dataset = " + std::to_string(*options.dataset) +
                              " chooses among the datasets of a universal file; this is a " +
                              to_string(format) + " file, ignored");
  return result;
}

FrfReadResult read_frf_file(const std::filesystem::path& file, const FrfFileOptions& options) {
  namespace fs = std::filesystem;
  const std::string where = file.string();
  std::error_code ec;
  const fs::file_status status = fs::status(file, ec);
  if (!fs::exists(status)) throw InvalidInput({"no such file"}, where);
  if (fs::is_directory(status)) throw InvalidInput({"is a directory, not an FRF file"}, where);
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InvalidInput({"cannot be opened for reading"}, where);
  const std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw InvalidInput({"could not be read to its end"}, where);
  io::note_input(file);
  return parse_frf(content, where, options, file.extension().string());
}

MeasuredFrf read_frf(const std::filesystem::path& file, FrfFileOptions options) {
  return read_frf_file(file, options).frf;
}

FrfText format_frf(const MeasuredFrf& frf, FrfFormat format, const FrfWriteOptions& options) {
  if (const auto problems = frf.validate(); !problems.empty()) throw InvalidInput(problems);
  switch (format) {
    case FrfFormat::kCutPro:
      return {io::detail::format_cutpro(frf, options), {}};
    case FrfFormat::kCsv:
      return {io::detail::format_csv(frf, options), {}};
    case FrfFormat::kUff:
      return io::detail::format_uff(frf, options);
  }
  return {};
}

std::vector<std::string> write_frf(const std::filesystem::path& file, const MeasuredFrf& frf,
                                   FrfFormat format, const FrfWriteOptions& options) {
  const std::string where = file.string();
  FrfText text;
  try {
    text = format_frf(frf, format, options);
  } catch (const InvalidInput& e) {
    throw InvalidInput(e.problems(), where);
  }
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  if (!out) throw InvalidInput({"cannot be opened for writing"}, where);
  out.write(text.text.data(), static_cast<std::streamsize>(text.text.size()));
  out.close();
  if (!out) throw InvalidInput({"could not be written to its end"}, where);
  return text.warnings;
}

}  // namespace cutdyn
