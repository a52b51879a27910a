// The explorer's JSON API without sockets (cutdyn/server/api.hpp): every request answered,
// none throws; a cancelled job answers 409; the schema is the case file's.
#include "cutdyn/server/api.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "cutdyn/app/report_json.hpp"
#include "cutdyn/app/stability.hpp"
#include "cutdyn/core/error.hpp"

namespace cutdyn::server {
namespace {

using nlohmann::json;

Api api() { return Api(io::load_example("milling-insperger")); }

std::string case_body(const std::string& example = "milling-insperger") {
  return io::to_json(io::load_example(example)).dump();
}

TEST(ServerApi, LobesAreTheJobsReportOfTheSameCase) {
  const Response r = api().handle({"POST", "/api/lobes", {{"method", "zero-order"}}, case_body()});
  ASSERT_EQ(r.status, 200) << r.body;
  json got = json::parse(r.body);
  const io::Case c = io::parse_case_json(json::parse(case_body()), "body");
  app::LobesRequest request;
  request.method = "zero-order";
  json expected = app::to_json(c, app::run_lobes(c, request));
  got.erase("seconds");
  expected.erase("seconds");
  EXPECT_EQ(got, expected);
}

// Found by fuzz_api (docs/fuzzing.md): a number in the body that no double holds made the
// JSON reader throw out_of_range, not parse_error, and the API answered 500 ("server").
TEST(ServerApi, FuzzANumberNoDoubleHoldsIsABadBody) {
  for (const char* path : {"/api/case", "/api/lobes", "/api/check", "/api/simulate"}) {
    const Response r = api().handle(
        {"POST", path, {}, R"({"process": "milling", "lobes": {"rpm_max": 1e99999}})"});
    EXPECT_EQ(r.status, 400) << path << ": " << r.body;
    const json body = json::parse(r.body);
    EXPECT_EQ(body.at("where"), "body") << r.body;
    EXPECT_NE(body.at("error").get<std::string>().find("not JSON"), std::string::npos) << r.body;
  }
}

TEST(ServerApi, EveryBadRequestIsAnsweredNeverThrown) {
  const Api a = api();
  const std::vector<std::pair<Request, int>> cases = {
      {{"POST", "/api/lobes", {}, "{"}, 400},
      {{"POST", "/api/lobes", {}, "\xff\xfe"}, 400},
      {{"POST", "/api/lobes", {}, "[]"}, 400},
      {{"POST", "/api/lobes", {{"format", "xml"}}, case_body()}, 400},
      {{"POST", "/api/check", {{"rpm", "1e400"}, {"depth_mm", "1"}}, case_body()}, 400},
      {{"POST", "/api/check", {{"rpm", "9000"}}, case_body()}, 400},
      {{"POST", "/api/simulate", {{"points", "1"}}, case_body()}, 400},
      {{"PUT", "/api/lobes", {}, case_body()}, 404},
      {{"GET", "/api/case", {{"example", "nope"}}, ""}, 400},
      {{"GET", "/api/lobes", {}, ""}, 404},
  };
  for (const auto& [request, status] : cases) {
    Response r;
    EXPECT_NO_THROW(r = a.handle(request)) << request.path;
    EXPECT_EQ(r.status, status) << request.path << " " << request.body << ": " << r.body;
    const json body = json::parse(r.body);
    EXPECT_FALSE(body.at("error").get<std::string>().empty());
    EXPECT_FALSE(body.at("problems").empty());
  }
}

// ---- the files a request may name --------------------------------------------------------

const std::string kMeasured = std::string(CUTDYN_EXAMPLES_DIR) + "/frf/milling-measured.toml";

// The measured example with both [[frf]] tables naming `file`.
std::string frf_case_body(const std::string& file) {
  json j = io::to_json(io::load_case_file(kMeasured));
  j["frf"] = json::array(
      {json{{"direction", "x"}, {"file", file}}, json{{"direction", "y"}, {"file", file}}});
  return j.dump();
}

// data/tool.csv and outside/secret.csv (both a valid FRF), data/link.csv -> the secret, and
// data/inner -> data (a link that stays inside).
std::filesystem::path make_folders() {
  namespace fs = std::filesystem;
  const fs::path root = fs::path(::testing::TempDir()) / "cutdyn_api_files";
  fs::remove_all(root);
  fs::create_directories(root / "data");
  fs::create_directories(root / "outside");
  const fs::path frf = fs::path(CUTDYN_EXAMPLES_DIR) / "frf" / "tool_x.csv";
  fs::copy_file(frf, root / "data" / "tool.csv");
  fs::copy_file(frf, root / "outside" / "secret.csv");
  fs::create_symlink("../outside/secret.csv", root / "data" / "link.csv");
  fs::create_symlink(".", root / "data" / "inner");
  return root;
}

// The hostile names: absolute paths (existing or not, /proc), "..", links out of the folder.
std::vector<std::string> hostile_names(const std::filesystem::path& root) {
  return {"/proc/self/stat",
          "/proc/self/environ",
          "/etc/passwd",
          "/no/such/file.csv",
          (root / "outside" / "secret.csv").string(),
          (root / "data" / "tool.csv").string(),  // inside, but absolute
          "../outside/secret.csv",
          "inner/../../outside/secret.csv",
          "../outside/none.csv",
          "link.csv",
          "inner/link.csv"};
}

TEST(ServerApi, ARequestReadsNoPathOutsideTheDataFolderAndTellsNothingAboutIt) {
  const std::filesystem::path root = make_folders();
  for (const bool with_folder : {false, true}) {
    const Api a(io::load_example("milling-insperger"),
                with_folder ? root / "data" : std::filesystem::path());
    std::string first;
    for (const std::string& name : hostile_names(root)) {
      const Response r = a.handle({"POST", "/api/case", {}, frf_case_body(name)});
      ASSERT_EQ(r.status, 400) << name << ": " << r.body;
      const json body = json::parse(r.body);
      // One answer for all: the same problem once the name it quotes is taken out.
      std::string problem = body.at("problems").at(0).get<std::string>();
      if (const auto at = problem.find("\"" + name + "\""); at != std::string::npos)
        problem.erase(at, name.size() + 2);
      if (first.empty()) first = problem;
      EXPECT_EQ(problem, first) << name;
      EXPECT_NE(problem.find("not a file the server reads"), std::string::npos) << problem;
      for (const char* leak : {"cutdyn)", "root:", "no such", "not a number", "directory"})
        EXPECT_EQ(r.body.find(leak), std::string::npos) << name << ": " << r.body;
    }
  }
}

TEST(ServerApi, ARequestReadsTheDataFolderAndTheStartingCasesOwnFiles) {
  const std::filesystem::path root = make_folders();
  const Api a(io::load_example("milling-insperger"), root / "data");
  for (const char* name : {"tool.csv", "./tool.csv", "inner/tool.csv"}) {
    const Response r = a.handle({"POST", "/api/case", {}, frf_case_body(name)});
    EXPECT_EQ(r.status, 200) << name << ": " << r.body;
  }
  const Response missing = a.handle({"POST", "/api/case", {}, frf_case_body("none.csv")});
  EXPECT_EQ(missing.status, 400);
  EXPECT_NE(missing.body.find("no such file in the data folder"), std::string::npos)
      << missing.body;
  // The starting case's own files, by the names it gives them, with no data folder; and the
  // lobes of the case sent back are the starting case's.
  const io::Case start = io::load_case_file(kMeasured);
  const Api own(start);
  const std::string body = io::to_json(start).dump();
  const Response lobes = own.handle({"POST", "/api/lobes", {{"method", "zero-order"}}, body});
  ASSERT_EQ(lobes.status, 200) << lobes.body;
  app::LobesRequest request;
  request.method = "zero-order";
  json expected = app::to_json(start, app::run_lobes(start, request));
  json got = json::parse(lobes.body);
  EXPECT_EQ(got.at("points"), expected.at("points"));
  EXPECT_EQ(got.at("fitted_modes"), expected.at("fitted_modes"));
  // A file the starting case does not name is refused, even beside it.
  const Response beside = own.handle({"POST", "/api/case", {}, frf_case_body("tool_x.frf")});
  EXPECT_EQ(beside.status, 400) << beside.body;
}

TEST(ServerApi, ADataFolderThatIsNoFolderIsRefused) {
  EXPECT_THROW(Api(io::load_example("milling-insperger"), "/no/such/folder"), InvalidInput);
  EXPECT_THROW(Api(io::load_example("milling-insperger"), kMeasured), InvalidInput);
}

TEST(ServerApi, ACancelledJobAnswers409) {
  std::atomic<bool> cancel{true};
  const Response lobes = api().handle({"POST", "/api/lobes", {}, case_body()}, &cancel);
  EXPECT_EQ(lobes.status, 409) << lobes.body;
  const Response sim = api().handle(
      {"POST", "/api/simulate", {{"rpm", "9000"}, {"depth_mm", "0.05"}}, case_body()}, &cancel);
  EXPECT_EQ(sim.status, 409) << sim.body;
  cancel = false;
  EXPECT_EQ(api().handle({"POST", "/api/lobes", {}, case_body()}, &cancel).status, 200);
}

TEST(ServerApi, SchemaNamesEveryKeyWithItsUnitAndChoices) {
  const json schema = json::parse(api().handle({"GET", "/api/schema", {}, ""}).body);
  EXPECT_EQ(schema.at("modes").at("keys").at("natural_hz").at("unit"), "Hz");
  EXPECT_TRUE(schema.at("modes").at("array").get<bool>());
  const json methods = schema.at("lobes").at("keys").at("method").at("choices");
  EXPECT_NE(std::find(methods.begin(), methods.end(), "full-discretization"), methods.end());
  // Every key of a case the server echoes is in the schema.
  const json c = json::parse(case_body());
  for (const auto& [table, value] : c.items()) {
    if (!value.is_object()) continue;
    for (const auto& [key, v] : value.items())
      EXPECT_TRUE(schema.at(table).at("keys").contains(key)) << table << "." << key;
  }
}

TEST(ServerApi, SimulationCarriesThinnedTracesAndTheirSpectrum) {
  const Response r = api().handle({"POST",
                                   "/api/simulate",
                                   {{"rpm", "11000"}, {"depth_mm", "0.08"}, {"points", "500"}},
                                   case_body()});
  ASSERT_EQ(r.status, 200) << r.body;
  const json doc = json::parse(r.body);
  EXPECT_LE(doc.at("traces").at("time_s").size(), 500u);
  EXPECT_GT(doc.at("traces").at("time_s").size(), 250u);
  const json& s = doc.at("spectrum");
  ASSERT_EQ(s.at("frequency_hz").size(), s.at("x_um").size());
  // Chatter (0.08 mm at 11000 rpm is above the lobes): the spectrum peaks at the chatter
  // frequency the check predicts or one of its tooth-passing aliases (f ± k·tooth frequency,
  // the same Hopf vibration seen through the period), within a few bins.
  const json check = json::parse(
      api()
          .handle({"POST", "/api/check", {{"rpm", "11000"}, {"depth_mm", "0.08"}}, case_body()})
          .body);
  ASSERT_FALSE(check.at("stable").get<bool>());
  std::size_t peak = 1;
  for (std::size_t k = 1; k < s.at("x_um").size(); ++k)
    if (s.at("x_um")[k].get<double>() > s.at("x_um")[peak].get<double>()) peak = k;
  const double f = s.at("frequency_hz")[peak].get<double>();
  const double chatter = check.at("chatter_hz").get<double>();
  const double tooth = 2 * 11000.0 / 60.0;
  const double bin = s.at("frequency_hz")[1].get<double>();
  double nearest = 1e300;
  for (int k = -10; k <= 10; ++k) nearest = std::min(nearest, std::abs(f - (chatter + k * tooth)));
  EXPECT_LT(nearest, 3 * bin + 0.02 * chatter) << "peak " << f << " Hz, chatter " << chatter;
}

}  // namespace
}  // namespace cutdyn::server
