// A case file (TOML): parse_case checks every key; the accepted case is written as JSON too
// (what --json and the explorer show).
#include <cstddef>
#include <cstdint>

#include "cutdyn/io/case_file.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  cutdyn::fuzz::expect_invalid_input_only([&] {
    const cutdyn::io::Case c = cutdyn::io::parse_case(cutdyn::fuzz::text_of(data, size), "fuzz");
    (void)cutdyn::io::to_json(c).dump();
  });
  return 0;
}
