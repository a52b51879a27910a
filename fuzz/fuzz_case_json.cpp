// A case as JSON (the Python module's dicts, the explorer's request bodies): parse_case_json
// writes it as TOML and checks it with parse_case. Text that is not JSON never reaches it
// (its callers answer that themselves).
#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>

#include "cutdyn/io/case_file.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const nlohmann::json j =
      nlohmann::json::parse(cutdyn::fuzz::text_of(data, size), nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return 0;
  cutdyn::fuzz::expect_invalid_input_only([&] {
    const cutdyn::io::Case c = cutdyn::io::parse_case_json(j, "fuzz");
    (void)cutdyn::io::to_json(c).dump();
  });
  return 0;
}
