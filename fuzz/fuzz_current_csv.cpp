// The monitor's current log (time_s,axis,iu_a,iv_a,iw_a,speed_rad_s[,...]) through the public
// interface of CurrentCsvParser, fed in chunks as from a pipe. The first byte picks how: bits
// 0-5 the chunk size - 1 (1 to 64 bytes), bit 6 stop at the first bad line, bit 7 the extra
// column force_n (calibration step 2).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "cutdyn/monitor/current_csv.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::size_t chunk = (data[0] & 63u) + 1;
  const bool stop_at_error = (data[0] & 64u) != 0;
  const std::string extra = (data[0] & 128u) != 0 ? "force_n" : "";
  const std::string_view text = cutdyn::fuzz::text_of(data + 1, size - 1);
  cutdyn::fuzz::expect_invalid_input_only([&] {
    cutdyn::CurrentCsvParser parser("fuzz", extra);
    std::vector<cutdyn::CurrentRow> rows;
    std::vector<cutdyn::CsvLineError> errors;
    bool going = true;
    for (std::size_t at = 0; going && at < text.size(); at += chunk)
      going = parser.feed(text.substr(at, std::min(chunk, text.size() - at)), rows, errors,
                          stop_at_error);
    if (going) parser.finish(rows, errors, stop_at_error);
    // What the parser promises of a good row: an axis it has named.
    for (const cutdyn::CurrentRow& r : rows)
      if (r.axis < 0 || static_cast<std::size_t>(r.axis) >= parser.axes().size())
        cutdyn::fuzz::fail("a row's axis is not one of axes()");
    for (const std::string& axis : parser.axes()) (void)parser.recorded_measure(axis);
    for (const cutdyn::CsvLineError& e : errors) (void)e.text();
  });
  return 0;
}
