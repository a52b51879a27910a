// FRF files in every format (CutPro .frf, CSV, UFF 58/58b): parse_frf on the content. The first
// byte picks the options: bits 0-1 the format (detected, frf, csv, uff), bits 2-3 the UFF
// dataset (first FRF, 0, 1, 2), bits 4-5 the extension hint (none, .frf, .csv, .uff).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "cutdyn/io/frf_file.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const unsigned pick = data[0];
  cutdyn::FrfFileOptions options;
  constexpr cutdyn::FrfFormat kFormats[] = {cutdyn::FrfFormat::kCutPro, cutdyn::FrfFormat::kCsv,
                                            cutdyn::FrfFormat::kUff};
  if ((pick & 3u) != 0) options.format = kFormats[(pick & 3u) - 1];
  if (((pick >> 2) & 3u) != 0) options.dataset = static_cast<int>((pick >> 2) & 3u) - 1;
  constexpr std::string_view kExtensions[] = {"", ".frf", ".csv", ".uff"};
  const std::string_view extension = kExtensions[(pick >> 4) & 3u];
  cutdyn::fuzz::expect_invalid_input_only([&] {
    const cutdyn::FrfReadResult r =
        cutdyn::parse_frf(cutdyn::fuzz::text_of(data + 1, size - 1), "fuzz", options, extension);
    // The reader promises a valid receptance.
    if (!r.frf.validate().empty()) cutdyn::fuzz::fail("parse_frf returned an invalid FRF");
  });
  return 0;
}
