// FRF files: the format detected, the file read or written, the conversions to receptance;
// docs/frf-files.md.
#include "cutdyn/io/frf_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <numbers>
#include <system_error>

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
  FrfReadResult result;
  switch (format) {
    case FrfFormat::kCutPro:
      result = io::detail::read_cutpro_text(content, source);
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
