// No output of a command replaces one of its inputs: every command × every output option ×
// every input it reads (the case, the files the case names, logs, calibrations, bands, force
// and FRF files) × every spelling of the input (its path, another path to it, a symbolic link,
// a hard link; for --plot, a link its .svg, .dat or .gp would write through). Each run is
// refused with exit 2 before any work, naming the input, and the input stays byte-identical.
// Then the same commands with a folder, a missing file and one output named twice: exit 2.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cutdyn/io/case_file.hpp"
#include "support/cli_runner.hpp"
#include "support/temp_dir.hpp"

namespace cutdyn::cli {
namespace {

namespace fs = std::filesystem;
using testing::run_cutdyn;

struct Command {
  std::vector<std::string> args;     // the command and its inputs
  std::vector<std::string> inputs;   // the files it reads (names in the folder)
  std::vector<std::string> outputs;  // its output options
};

class InputsProtected : public testing::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    const fs::path examples(CUTDYN_EXAMPLES_DIR);
    for (const char* f : {"tool_x.csv", "tool_y.csv"})
      fs::copy_file(examples / "frf" / f, dir_ / f);
    fs::copy_file(examples / "frf" / "milling-measured.toml", dir_ / "measured.toml");
    fs::copy_file(examples / "forces" / "milling-insperger-mean-forces.csv", dir_ / "forces.csv");
    for (const auto& [name, example] :
         {std::pair{"milling.toml", "milling-insperger"}, std::pair{"drive.toml", "ermolaev2020"},
          std::pair{"plan.toml", "bore-plan"}, std::pair{"force.toml", "ultrasonic-force"}})
      std::ofstream(dir_ / name) << *io::example_text(example);
    // The monitor's files are refused before they are read: any content stands for them.
    for (const char* name : {"idle.csv", "loaded.csv", "cut.csv", "ref.csv"})
      std::ofstream(dir_ / name) << "time_s,axis,iu_a,iv_a,iw_a,speed_rad_s\n";
    std::ofstream(dir_ / "calib.json") << "{}\n";
    std::ofstream(dir_ / "band.json") << "{}\n";
  }

  std::string p(const std::string& name) const { return (dir_ / name).string(); }

  std::vector<Command> commands() const {
    return {
        {{"lobes", p("measured.toml")},
         {"measured.toml", "tool_x.csv", "tool_y.csv"},
         {"--out", "--json", "--plot"}},
        {{"check", p("measured.toml"), "--rpm", "9000", "--depth-mm", "0.1"},
         {"measured.toml", "tool_x.csv", "tool_y.csv"},
         {"--json"}},
        {{"simulate", p("measured.toml")},
         {"measured.toml", "tool_x.csv", "tool_y.csv"},
         {"--out", "--json", "--plot"}},
        {{"force", p("force.toml")}, {"force.toml"}, {"--json", "--plot"}},
        {{"plan", p("plan.toml")}, {"plan.toml"}, {"--json", "--plot"}},
        {{"drive", p("drive.toml")}, {"drive.toml"}, {"--out", "--json", "--plot", "--currents"}},
        {{"identify", p("milling.toml"), p("forces.csv")},
         {"milling.toml", "forces.csv"},
         {"--out", "--json", "--plot"}},
        {{"fit", p("tool_x.csv")}, {"tool_x.csv"}, {"--out", "--json", "--plot"}},
        {{"sweep", p("measured.toml")}, {"measured.toml", "tool_x.csv", "tool_y.csv"}, {"--out"}},
        {{"monitor", "calibrate", "--idle", p("idle.csv"), "--loaded", p("loaded.csv"), "--base",
          p("calib.json")},
         {"idle.csv", "loaded.csv", "calib.json"},
         {"--out"}},
        {{"monitor", "estimate", p("cut.csv"), "--calib", p("calib.json"), "--band",
          p("band.json")},
         {"cut.csv", "calib.json", "band.json"},
         {"--out", "--alarms", "--json"}},
        {{"monitor", "teach", p("ref.csv"), "--calib", p("calib.json")},
         {"ref.csv", "calib.json"},
         {"--out"}},
    };
  }

  // The ways an output option can name `input`: (the target, a file to make first: a link).
  std::vector<std::string> spellings(const std::string& flag, const std::string& input) {
    std::vector<std::string> targets;
    const auto symlink = [&](const std::string& name) {
      fs::create_symlink(input, dir_ / name);
      return p(name);
    };
    const auto hard_link = [&](const std::string& name) {
      fs::create_hard_link(dir_ / input, dir_ / name);
      return p(name);
    };
    const std::string tag = std::to_string(made_++);
    if (flag == "--plot") {
      symlink("s" + tag + ".svg");
      targets.push_back(p("s" + tag + ".svg"));
      hard_link("h" + tag + ".dat");
      targets.push_back(p("h" + tag + ".svg"));
      symlink("g" + tag + ".gp");
      targets.push_back(p("g" + tag + ".svg"));
      return targets;
    }
    targets.push_back(p(input));
    targets.push_back((dir_ / "." / ".." / dir_.filename() / input).string());
    targets.push_back(symlink("s" + tag + "-" + input));
    targets.push_back(hard_link("h" + tag + "-" + input));
    return targets;
  }

  int made_ = 0;
};

TEST_F(InputsProtected, NoOutputReplacesAnInputOfItsCommand) {
  int runs = 0;
  for (const Command& c : commands()) {
    for (const std::string& input : c.inputs) {
      const std::string content = testing::read_file(dir_ / input);
      for (const std::string& flag : c.outputs) {
        for (const std::string& target : spellings(flag, input)) {
          std::vector<std::string> args = c.args;
          args.push_back(flag);
          args.push_back(target);
          const auto before = testing::listing(dir_);
          const auto r = run_cutdyn(args);
          const std::string what = args[0] + " " + flag + " " + target + " (" + input + ")";
          EXPECT_EQ(r.code, 2) << what << "\n" << r.err;
          EXPECT_NE(r.err.find("is an input of the command"), std::string::npos) << what << "\n"
                                                                                 << r.err;
          EXPECT_EQ(testing::read_file(dir_ / input), content) << what;
          EXPECT_EQ(testing::listing(dir_), before) << what;  // nothing written
          ++runs;
        }
      }
    }
  }
  EXPECT_GT(runs, 150);
}

TEST_F(InputsProtected, AFolderAMissingFileOrAnOutputNamedTwiceIsBadInput) {
  fs::create_directory(dir_ / "folder");
  for (const Command& c : commands()) {
    // Every input in turn a folder, then a file that does not exist.
    for (const std::string& input : c.inputs) {
      for (const std::string& stand_in : {p("folder"), p("missing.csv")}) {
        std::vector<std::string> args = c.args;
        for (std::string& a : args)
          if (a == p(input)) a = stand_in;
        if (args == c.args) continue;  // a file the case names, not an argument
        args.push_back(c.outputs[0]);
        args.push_back(p("out.x"));
        const auto r = run_cutdyn(args);
        EXPECT_EQ(r.code, 2) << args[0] << " " << input << " as " << stand_in << "\n" << r.err;
        EXPECT_FALSE(fs::exists(dir_ / "out.x"));
      }
    }
    // An output that is a folder.
    for (const std::string& flag : c.outputs) {
      if (flag == "--plot") continue;  // (a folder has no figure extension: refused as such)
      std::vector<std::string> args = c.args;
      args.push_back(flag);
      args.push_back(p("folder"));
      const auto r = run_cutdyn(args);
      EXPECT_EQ(r.code, 2) << args[0] << " " << flag << " folder\n" << r.err;
      EXPECT_NE(r.err.find("is a folder"), std::string::npos) << r.err;
    }
    // One file named by two outputs.
    if (c.outputs.size() >= 2) {
      std::vector<std::string> args = c.args;
      const std::string a = c.outputs[0] == "--plot" ? p("same.svg") : p("same.out");
      const std::string b = c.outputs[1] == "--plot" ? p("same.svg") : p("same.out");
      for (const auto& [flag, target] : {std::pair{c.outputs[0], a}, std::pair{c.outputs[1], b}}) {
        args.push_back(flag);
        args.push_back(target);
      }
      if (a == b) {
        const auto r = run_cutdyn(args);
        EXPECT_EQ(r.code, 2) << args[0] << " twice\n" << r.err;
        EXPECT_NE(r.err.find("name the same file"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(dir_ / "same.out"));
      }
    }
  }
  // The pairs the walk above does not make: --currents and --out, and a figure's data file.
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"drive", "--out", p("x.csv"), "--currents", p("x.csv")},
        std::vector<std::string>{"lobes", "--out", p("f.dat"), "--plot", p("f.svg")}}) {
    const auto r = run_cutdyn(args);
    EXPECT_EQ(r.code, 2) << args[0] << "\n" << r.err;  // (was 1, after the work, for drive)
    EXPECT_NE(r.err.find("name the same file"), std::string::npos) << r.err;
  }
}

}  // namespace
}  // namespace cutdyn::cli
