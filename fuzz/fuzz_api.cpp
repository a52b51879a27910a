// The explorer's HTTP API (`cutdyn serve`): Api::handle on the requests that take a body. The
// input is one request: the first byte picks the path (POST /api/case, /api/lobes, /api/check,
// /api/simulate), the text up to the first newline is the query (key=value&key=value, as the
// server hands it over, decoded), the rest is the body. The job is cancelled at its first
// progress report, so a run tests the request's checks, not the computation's length.
// Api::handle promises never to throw; a 500 ("server") answer is an exception the request's
// checks let through, and every JSON answer must be JSON.
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "cutdyn/io/case_file.hpp"
#include "cutdyn/server/api.hpp"
#include "fuzz_common.hpp"

namespace {

const cutdyn::server::Api& api() {
  static const cutdyn::server::Api instance(cutdyn::io::load_example("turning-ultrasonic"));
  return instance;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  constexpr const char* kPaths[] = {"/api/case", "/api/lobes", "/api/check", "/api/simulate"};
  cutdyn::server::Request request;
  request.method = "POST";
  request.path = kPaths[data[0] & 3u];
  std::string_view rest = cutdyn::fuzz::text_of(data + 1, size - 1);
  const std::size_t newline = rest.find('\n');
  std::string_view query = rest.substr(0, newline);
  rest = newline == std::string_view::npos ? std::string_view() : rest.substr(newline + 1);
  while (!query.empty()) {
    const std::size_t amp = query.find('&');
    const std::string_view item = query.substr(0, amp);
    const std::size_t eq = item.find('=');
    request.query[std::string(item.substr(0, eq))] =
        eq == std::string_view::npos ? std::string() : std::string(item.substr(eq + 1));
    query = amp == std::string_view::npos ? std::string_view() : query.substr(amp + 1);
  }
  request.body = std::string(rest);

  const std::atomic<bool> cancel{true};
  const cutdyn::server::Response response = api().handle(request, &cancel);
  if (response.status == 500) {
    std::fprintf(stderr, "%s\n", response.body.c_str());
    cutdyn::fuzz::fail("the API answered 500: an exception the request's checks let through");
  }
  if (response.content_type == "application/json" && !nlohmann::json::accept(response.body))
    cutdyn::fuzz::fail("the API's JSON answer is not JSON");
  return 0;
}
