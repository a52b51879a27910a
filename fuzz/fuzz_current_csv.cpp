// The monitor's current log (time_s,axis,iu_a,iv_a,iw_a,speed_rad_s[,...]) through the public
// interface of CurrentCsvParser, fed in chunks as from a pipe. The first byte picks how: bits
// 0-5 the chunk size - 1 (1 to 64 bytes), bit 6 stop at the first bad line, bit 7 the extra
// column force_n (calibration step 2). The same text fed whole must give the same result (the
// interface: "feed it chunks of any size"): the same rows, bad lines, axes, comments and error.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "cutdyn/monitor/current_csv.hpp"
#include "fuzz_common.hpp"

namespace {

struct Outcome {
  std::vector<cutdyn::CurrentRow> rows;
  std::vector<cutdyn::CsvLineError> errors;
  std::vector<std::string> axes;
  std::vector<cutdyn::CsvComment> comments;
  bool completed = false;  // no stop at a bad line
  std::string thrown;      // the InvalidInput's problems, if one was thrown
};

Outcome parse(std::string_view text, std::size_t chunk, bool stop_at_error,
              const std::string& extra) {
  Outcome out;
  cutdyn::CurrentCsvParser parser("fuzz", extra);
  try {
    bool going = true;
    for (std::size_t at = 0; going && at < text.size(); at += chunk)
      going = parser.feed(text.substr(at, std::min(chunk, text.size() - at)), out.rows, out.errors,
                          stop_at_error);
    if (going) going = parser.finish(out.rows, out.errors, stop_at_error);
    out.completed = going;
  } catch (const cutdyn::InvalidInput& e) {
    for (const std::string& p : e.problems()) out.thrown += p + "\n";
    if (out.thrown.empty()) out.thrown = "(no problem)";
  }
  out.axes = parser.axes();
  out.comments = parser.comments();
  // What the parser promises of a good row: an axis it has named.
  for (const cutdyn::CurrentRow& r : out.rows)
    if (r.axis < 0 || static_cast<std::size_t>(r.axis) >= out.axes.size())
      cutdyn::fuzz::fail("a row's axis is not one of axes()");
  for (const std::string& axis : out.axes) (void)parser.recorded_measure(axis);
  return out;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

bool same_rows(const std::vector<cutdyn::CurrentRow>& a, const std::vector<cutdyn::CurrentRow>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const cutdyn::CurrentRow &x = a[i], &y = b[i];
    if (x.line != y.line || x.axis != y.axis || !same_bits(x.time_s, y.time_s) ||
        !same_bits(x.iu_a, y.iu_a) || !same_bits(x.iv_a, y.iv_a) || !same_bits(x.iw_a, y.iw_a) ||
        !same_bits(x.speed_rad_s, y.speed_rad_s) || !same_bits(x.extra, y.extra) ||
        !same_bits(x.rotor_angle_rad, y.rotor_angle_rad))
      return false;
  }
  return true;
}

bool same_errors(const std::vector<cutdyn::CsvLineError>& a,
                 const std::vector<cutdyn::CsvLineError>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].text() != b[i].text()) return false;
  return true;
}

bool same_comments(const std::vector<cutdyn::CsvComment>& a,
                   const std::vector<cutdyn::CsvComment>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].line != b[i].line || a[i].fields != b[i].fields) return false;
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::size_t chunk = (data[0] & 63u) + 1;
  const bool stop_at_error = (data[0] & 64u) != 0;
  const std::string extra = (data[0] & 128u) != 0 ? "force_n" : "";
  const std::string_view text = cutdyn::fuzz::text_of(data + 1, size - 1);
  const Outcome chunked = parse(text, chunk, stop_at_error, extra);
  const Outcome whole = parse(text, text.size() + 1, stop_at_error, extra);
  if (!same_rows(chunked.rows, whole.rows)) cutdyn::fuzz::fail("chunking changed the rows");
  if (!same_errors(chunked.errors, whole.errors))
    cutdyn::fuzz::fail("chunking changed the bad lines");
  if (chunked.axes != whole.axes || !same_comments(chunked.comments, whole.comments))
    cutdyn::fuzz::fail("chunking changed the axes or the comments");
  if (chunked.completed != whole.completed || chunked.thrown != whole.thrown)
    cutdyn::fuzz::fail("chunking changed where the input stops or its error");
  return 0;
}
