// `cutdyn sweep`: the lobes of every variant in one long CSV — each variant's rows are what
// `cutdyn lobes --out` writes for the same case; a failing variant is one row with its error and
// the rest complete; --resume finishes a stopped sweep to the same file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/cli_runner.hpp"
#include "support/temp_dir.hpp"

namespace cutdyn::testing {
namespace {

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

class SweepCli : public TempDirTest {
 protected:
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  // `cutdyn lobes --out` rows of the example with some of its key lines replaced.
  std::vector<std::string> lobes_rows(const std::vector<std::pair<std::string, std::string>>& set) {
    std::string text = run_cutdyn({"example", "milling-insperger"}).out;
    for (const auto& [key, line] : set) {
      const auto at = text.find("\n" + key + " = ");
      EXPECT_NE(at, std::string::npos) << key;
      text.replace(at + 1, text.find('\n', at + 1) - at - 1, line);
    }
    std::ofstream(path("v.toml")) << text;
    const auto r =
        run_cutdyn({"lobes", path("v.toml"), "--method", "zero-order", "--out", path("v.csv")});
    EXPECT_EQ(r.code, 0) << r.err;
    auto rows = lines_of(read_file(path("v.csv")));
    rows.erase(rows.begin());
    return rows;
  }
};

TEST_F(SweepCli, EachVariantIsTheLobesOfItsCase) {
  const auto r = run_cutdyn({"sweep", "milling-insperger", "--vary", "tool.teeth=2:1:3", "--vary",
                             "cutting.kt_n_per_mm2=500:300:800", "--method", "zero-order", "--out",
                             path("s.csv")});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto lines = lines_of(read_file(path("s.csv")));
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines[0],
            "tool.teeth,cutting.kt_n_per_mm2,spindle_rpm,critical_depth_mm,chatter_hz,lobe,"
            "bifurcation,beyond_limit,error");
  // The variant teeth = 3, Kt = 500: lobes --out of that case.
  std::vector<std::string> expected;
  for (const std::string& row :
       lobes_rows({{"teeth", "teeth = 3"}, {"kt_n_per_mm2", "kt_n_per_mm2 = 500"}}))
    expected.push_back(row);
  std::vector<std::string> got;
  for (const std::string& line : lines)
    if (line.rfind("3,500,", 0) == 0) got.push_back(line.substr(6, line.size() - 7));
  EXPECT_EQ(got, expected);
  // Four variants in order, no error.
  std::vector<std::string> leads;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const std::string lead = lines[i].substr(0, lines[i].find(',', lines[i].find(',') + 1));
    if (leads.empty() || leads.back() != lead) leads.push_back(lead);
    EXPECT_EQ(lines[i].back(), ',') << lines[i];
  }
  EXPECT_EQ(leads, (std::vector<std::string>{"2,500", "2,800", "3,500", "3,800"}));
  EXPECT_FALSE(std::filesystem::exists(path("s.csv.partial")));
}

TEST_F(SweepCli, AFailingVariantIsReportedAndTheRestComplete) {
  const auto r =
      run_cutdyn({"sweep", "milling-insperger", "--vary", "modes[0].damping_ratio=-0.01:0.02:0.03",
                  "--method", "zero-order", "--out", path("s.csv")});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("1 variants failed"), std::string::npos) << r.err;
  const auto lines = lines_of(read_file(path("s.csv")));
  ASSERT_GT(lines.size(), 3u);
  EXPECT_EQ(lines[1].rfind("-0.01,,,,,,,", 0), 0u) << lines[1];
  EXPECT_NE(lines[1].find("damping_ratio"), std::string::npos) << lines[1];
  int good = 0;
  for (std::size_t i = 2; i < lines.size(); ++i) good += lines[i].rfind("0.01,", 0) == 0;
  EXPECT_GT(good, 100);
  EXPECT_EQ(lines.back().rfind("0.03,", 0), 0u);
}

TEST_F(SweepCli, ResumeFinishesAStoppedSweepToTheSameFile) {
  const std::vector<std::string> sweep{
      "sweep",    "milling-insperger", "--vary", "modes[0].damping_ratio=0.01:0.01:0.04",
      "--method", "zero-order",        "--out"};
  auto args = sweep;
  args.push_back(path("full.csv"));
  ASSERT_EQ(run_cutdyn(args).code, 0);
  const std::string full = read_file(path("full.csv"));
  // A stopped run: its partial file holds two variants and a third cut in the middle of a row.
  const auto lines = lines_of(full);
  std::string stopped;
  std::size_t i = 0;
  for (; i < lines.size() && lines[i].rfind("0.03,", 0) != 0; ++i) stopped += lines[i] + "\n";
  stopped += lines[i] + "\n" + lines[i + 1].substr(0, 9);
  std::ofstream(path("s.csv.partial"), std::ios::binary) << stopped;
  args = sweep;
  args.push_back(path("s.csv"));
  args.push_back("--resume");
  const auto r = run_cutdyn(args);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("(2 from the stopped run)"), std::string::npos) << r.out;
  EXPECT_EQ(read_file(path("s.csv")), full);
  // Resumed again, a finished file stays the same.
  ASSERT_EQ(run_cutdyn(args).code, 0);
  EXPECT_EQ(read_file(path("s.csv")), full);
  // Another sweep's file is refused.
  std::ofstream(path("o.csv.partial")) << "a,b\n1,2\n";
  args = sweep;
  args.push_back(path("o.csv"));
  args.push_back("--resume");
  const auto refused = run_cutdyn(args);
  EXPECT_EQ(refused.code, 2);
  EXPECT_NE(refused.err.find("not this sweep's file"), std::string::npos) << refused.err;
}

TEST_F(SweepCli, ManyCaseFilesAndBadRequests) {
  std::ofstream(path("a.toml")) << run_cutdyn({"example", "milling-insperger"}).out;
  std::ofstream(path("b.toml")) << run_cutdyn({"example", "milling-variable-pitch"}).out;
  auto r = run_cutdyn(
      {"sweep", path("a.toml"), path("b.toml"), "--method", "zero-order", "--out", path("s.csv")});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto lines = lines_of(read_file(path("s.csv")));
  EXPECT_EQ(lines[0].rfind("case,spindle_rpm,", 0), 0u);
  EXPECT_EQ(lines.back().rfind(path("b.toml") + ",", 0), 0u);
  for (const std::vector<std::string>& bad :
       {std::vector<std::string>{"sweep", "--vary", "tool.teeth=2:1:3", "--vary",
                                 "tool.teeth=4:1:5", "--out", path("x.csv")},
        {"sweep", "--vary", "tool.nope=1:1:2", "--out", path("x.csv")},
        {"sweep", "--vary", "tool.teeth=2:0:3", "--out", path("x.csv")},
        {"sweep", "--vary", "lobes.rpm_min=1:1:200000", "--vary", "tool.teeth=1:1:10", "--out",
         path("x.csv")},
        {"sweep", "--out", path("nowhere/x.csv")}}) {
    r = run_cutdyn(bad);
    EXPECT_EQ(r.code, 2) << bad[2] << ": " << r.err;
    EXPECT_FALSE(std::filesystem::exists(path("x.csv")));
  }
}

}  // namespace
}  // namespace cutdyn::testing
