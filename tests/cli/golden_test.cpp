// Golden outputs: every command on the built-in examples, its text and the files it writes,
// against the outputs kept in tests/golden/. A restructuring of the command line or the job
// layer must leave them unchanged (or change them on purpose: rerun with
// CUTDYN_UPDATE_GOLDEN=1 and review the diff). Numbers are compared to 1e-9 relative (plus
// 1e-12 absolute), everything else exactly; wall-clock times are masked.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "support/cli_runner.hpp"
#include "support/temp_dir.hpp"

namespace cutdyn::cli {
namespace {

namespace fs = std::filesystem;

struct Golden {
  std::string name;
  std::vector<std::string> args;  // "{dir}" is replaced by the test's temporary folder
  std::vector<std::string> files;  // written by the command, compared too
};

const std::vector<Golden>& goldens() {
  static const std::vector<Golden> all = {
      {"lobes-turning-ultrasonic", {"lobes", "--out", "{dir}/l.csv", "--json", "{dir}/l.json"},
       {"l.csv", "l.json"}},
      {"lobes-turning-conventional-target",
       {"lobes", "turning-conventional", "--target-depth-mm", "10", "--json", "{dir}/l.json"},
       {"l.json"}},
      {"lobes-turning-ultrasonic-speed", {"lobes", "turning-ultrasonic-speed"}, {}},
      {"lobes-milling-insperger", {"lobes", "milling-insperger", "--out", "{dir}/l.csv"}, {"l.csv"}},
      {"lobes-milling-variable-pitch", {"lobes", "milling-variable-pitch"}, {}},
      {"lobes-oxley", {"lobes", "oxley-aisi1045"}, {}},
      {"check-turning", {"check", "turning-ultrasonic", "--rpm", "1400", "--depth-mm", "10",
                         "--json", "{dir}/c.json"}, {"c.json"}},
      {"check-milling", {"check", "milling-insperger", "--rpm", "10000", "--depth-mm", "0.05"}, {}},
      {"simulate-turning", {"simulate", "turning-ultrasonic", "--duration-s", "0.5", "--json",
                            "{dir}/s.json"}, {"s.json"}},
      {"simulate-milling", {"simulate", "milling-insperger", "--json", "{dir}/s.json"}, {"s.json"}},
      {"simulate-ermolaev", {"simulate", "ermolaev2020"}, {}},
      {"plan", {"plan", "--json", "{dir}/p.json"}, {"p.json"}},
      {"force-ultrasonic", {"force", "ultrasonic-force"}, {}},
      {"force-aa5083", {"force", "ultrasonic-force-aa5083"}, {}},
      {"force-oxley", {"force", "oxley-aisi1045"}, {}},
      {"drive-ermolaev", {"drive", "ermolaev2020", "--json", "{dir}/d.json"}, {"d.json"}},
  };
  return all;
}

// Text with the folder replaced and wall-clock times masked ("0.24 s" in a lobes header,
// "seconds": … in JSON).
std::string normalise(std::string text, const std::string& dir) {
  std::string replaced;
  for (std::size_t from = 0;;) {
    const std::size_t at = text.find(dir, from);
    replaced.append(text, from, at == std::string::npos ? std::string::npos : at - from);
    if (at == std::string::npos) break;
    replaced += "{dir}";
    from = at + dir.size();
  }
  text = replaced;
  text = std::regex_replace(text, std::regex(R"(, [0-9.]+ s\n)"), ", <time> s\n");
  text = std::regex_replace(text, std::regex(R"("seconds": [0-9.eE+-]+)"), "\"seconds\": <time>");
  return text;
}

// Splits into numbers and the text between them.
std::vector<std::string> tokens(const std::string& text) {
  static const std::regex number(R"([-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?)");
  std::vector<std::string> out;
  std::size_t last = 0;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), number); it != std::sregex_iterator();
       ++it) {
    out.push_back(text.substr(last, static_cast<std::size_t>(it->position()) - last));
    std::string token(1, '#');
    token += it->str();
    out.push_back(std::move(token));
    last = static_cast<std::size_t>(it->position() + it->length());
  }
  out.push_back(text.substr(last));
  return out;
}

// "" when equal within the tolerance, else where they first differ.
std::string compare(const std::string& expected, const std::string& actual) {
  const auto a = tokens(expected), b = tokens(actual);
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    if (a[i] == b[i]) continue;
    if (a[i][0] == '#' && b[i][0] == '#') {
      const double x = std::strtod(a[i].c_str() + 1, nullptr), y = std::strtod(b[i].c_str() + 1, nullptr);
      if (std::abs(x - y) <= 1e-9 * std::max(std::abs(x), std::abs(y)) + 1e-12) continue;
    }
    std::string context;
    for (std::size_t j = i >= 3 ? i - 3 : 0; j < std::min(a.size(), i + 4); ++j) context += a[j];
    return "token " + std::to_string(i) + ": expected \"" + a[i] + "\", got \"" + b[i] +
           "\" near: " + context;
  }
  return a.size() == b.size() ? "" : "different lengths";
}

using testing::read_file;

class GoldenOutputs : public ::testing::TestWithParam<Golden> {};

TEST_P(GoldenOutputs, AreUnchanged) {
  const Golden& g = GetParam();
  const fs::path dir_ = fs::temp_directory_path() /
                        ("cutdyn-golden-" + std::to_string(::getpid()) + "-" + g.name);
  fs::remove_all(dir_);
  fs::create_directories(dir_);
  const std::string dir = dir_.string();
  std::vector<std::string> args;
  for (std::string a : g.args) {
    if (const auto at = a.find("{dir}"); at != std::string::npos) a.replace(at, 5, dir);
    args.push_back(a);
  }
  const auto r = testing::run_cutdyn(args);
  ASSERT_EQ(r.code, 0) << r.err;
  std::vector<std::pair<std::string, std::string>> outputs = {{g.name + ".txt", r.out}};
  for (const std::string& f : g.files) outputs.push_back({g.name + "." + f, read_file(dir_ / f)});
  const fs::path golden_dir = fs::path(CUTDYN_SOURCE_DIR) / "tests" / "golden";
  const bool update = std::getenv("CUTDYN_UPDATE_GOLDEN") != nullptr;
  for (const auto& [file, content] : outputs) {
    const std::string actual = normalise(content, dir);
    if (update) {
      std::ofstream(golden_dir / file, std::ios::binary) << actual;
      continue;
    }
    ASSERT_TRUE(fs::exists(golden_dir / file)) << file << ": no golden output (CUTDYN_UPDATE_GOLDEN=1)";
    EXPECT_EQ(compare(read_file(golden_dir / file), actual), "") << file;
  }
  fs::remove_all(dir_);
}

INSTANTIATE_TEST_SUITE_P(Examples, GoldenOutputs, ::testing::ValuesIn(goldens()),
                         [](const ::testing::TestParamInfo<Golden>& param_info) {
                           std::string n = param_info.param.name;
                           for (char& ch : n)
                             if (ch == '-') ch = '_';
                           return n;
                         });

TEST(GoldenCompare, NumbersWithinTheToleranceAndTextExactly) {
  EXPECT_EQ(compare("depth 1.0000000000 mm", "depth 1.0000000001 mm"), "");
  EXPECT_NE(compare("depth 1.00000 mm", "depth 1.00001 mm"), "");
  EXPECT_NE(compare("depth 1 mm STABLE", "depth 1 mm UNSTABLE"), "");
  EXPECT_NE(compare("a 1 b", "a 1 b 2"), "");
  EXPECT_EQ(normalise("x, 0.24 s\n\"seconds\": 1.5e-3,", "/t"), "x, <time> s\n\"seconds\": <time>,");
}

}  // namespace
}  // namespace cutdyn::cli
