#include "cutdyn/io/output.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "cutdyn/core/error.hpp"
#include "cutdyn/io/inputs.hpp"
#include "support/temp_dir.hpp"

namespace cutdyn::io {
namespace {
namespace fs = std::filesystem;

using testing::read_file;

void write_file(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

using testing::listing;

class OutputTransactionTest : public testing::TempDirTest {};

// ---- format_number ----------------------------------------------------------------------

TEST(OutputFormatNumber, ShortestRoundTrip) {
  EXPECT_EQ(format_number(0.1), "0.1");
  EXPECT_EQ(format_number(2.26e8), "2.26e+08");
  EXPECT_EQ(format_number(500.0), "500");
  EXPECT_EQ(format_number(-0.0), "-0");
  EXPECT_EQ(format_number(1e-7), "1e-07");
  const double third = 1.0 / 3.0;
  EXPECT_EQ(std::stod(format_number(third)), third);
  EXPECT_EQ(format_number(third), "0.3333333333333333");
}

// ---- CsvWriter ----------------------------------------------------------------------------

TEST(CsvWriter, WritesHeaderAndRowsExactly) {
  std::ostringstream out;
  CsvWriter csv(out, {"spindle_rpm", "critical_depth_mm", "lobe", "note"});
  csv.row({500.0, 0.1, 3LL, std::string("plain")});
  csv.row({1250.5, 2.26e8, -12LL, std::string("a,b")});
  csv.row({5000.0, 1.0 / 3.0, 0LL, std::string("say \"hi\"")});
  csv.row({1e-7, -0.0, 9007199254740993LL, std::string("two\nlines")});
  EXPECT_EQ(out.str(),
            "spindle_rpm,critical_depth_mm,lobe,note\n"
            "500,0.1,3,plain\n"
            "1250.5,2.26e+08,-12,\"a,b\"\n"
            "5000,0.3333333333333333,0,\"say \"\"hi\"\"\"\n"
            "1e-07,-0,9007199254740993,\"two\nlines\"\n");
}

TEST(CsvWriter, QuotesHeaderCellsToo) {
  std::ostringstream out;
  CsvWriter csv(out, {"force, N", "x"});
  EXPECT_EQ(out.str(), "\"force, N\",x\n");
}

TEST(CsvWriter, NonFiniteThrowsNamingTheColumnAndWritesNothing) {
  for (double bad :
       {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
        -std::numeric_limits<double>::infinity()}) {
    std::ostringstream out;
    CsvWriter csv(out, {"spindle_rpm", "critical_depth_mm"});
    try {
      csv.row({500.0, bad});
      FAIL() << "expected std::logic_error for " << bad;
    } catch (const std::logic_error& e) {
      EXPECT_NE(std::string(e.what()).find("critical_depth_mm"), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).find("spindle_rpm"), std::string::npos) << e.what();
    }
    EXPECT_EQ(out.str(), "spindle_rpm,critical_depth_mm\n");  // no partial row
  }
}

TEST(CsvWriter, RowWidthMustMatchHeader) {
  std::ostringstream out;
  CsvWriter csv(out, {"a", "b"});
  EXPECT_THROW(csv.row({1.0}), std::logic_error);
  EXPECT_THROW(csv.row({1.0, 2.0, 3.0}), std::logic_error);
  EXPECT_EQ(out.str(), "a,b\n");
}

// ---- write_json ---------------------------------------------------------------------------

TEST(JsonWrite, TwoSpaceIndentAndFinalNewline) {
  std::ostringstream out;
  write_json(out, nlohmann::json{{"method", "closed-form"}, {"rpm", {500, 0.1}}});
  EXPECT_EQ(out.str(),
            "{\n"
            "  \"method\": \"closed-form\",\n"
            "  \"rpm\": [\n"
            "    500,\n"
            "    0.1\n"
            "  ]\n"
            "}\n");
}

TEST(JsonWrite, RejectsNaNGivingItsPointer) {
  nlohmann::json value;
  value["method"] = "fd";
  value["lobes"] = nlohmann::json::array();
  value["lobes"].push_back({{"depth_mm", 1.5}});
  value["lobes"].push_back({{"depth_mm", std::nan("")}});
  std::ostringstream out;
  try {
    write_json(out, value);
    FAIL() << "expected std::logic_error";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("/lobes/1/depth_mm"), std::string::npos) << e.what();
  }
  EXPECT_EQ(out.str(), "");  // nothing written
}

TEST(JsonWrite, RejectsInfinityWithEscapedPointer) {
  nlohmann::json value;
  value["a/b"]["c~d"] = std::numeric_limits<double>::infinity();
  std::ostringstream out;
  try {
    write_json(out, value);
    FAIL() << "expected std::logic_error";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("/a~1b/c~0d"), std::string::npos) << e.what();
  }
  EXPECT_THROW(write_json(out, nlohmann::json(std::nan(""))), std::logic_error);
}

// ---- OutputTransaction --------------------------------------------------------------------

TEST_F(OutputTransactionTest, FilesAppearOnlyAfterCommit) {
  OutputTransaction outputs;
  outputs.open(dir_ / "lobes.csv") << "spindle_rpm,critical_depth_mm\n500,1.5\n";
  outputs.open(dir_ / "lobes.json") << "{}\n";

  // Before commit: only hidden temporaries beside the targets.
  const std::vector<std::string> before = listing(dir_);
  ASSERT_EQ(before.size(), 2u);
  for (const std::string& name : before) {
    EXPECT_TRUE(name.rfind(".lobes.csv.cutdyn-tmp-", 0) == 0 ||
                name.rfind(".lobes.json.cutdyn-tmp-", 0) == 0)
        << name;
  }

  outputs.commit();
  EXPECT_EQ(listing(dir_), (std::vector<std::string>{"lobes.csv", "lobes.json"}));
  EXPECT_EQ(read_file(dir_ / "lobes.csv"), "spindle_rpm,critical_depth_mm\n500,1.5\n");
  EXPECT_EQ(read_file(dir_ / "lobes.json"), "{}\n");
}

TEST_F(OutputTransactionTest, DestroyedWithoutCommitLeavesFolderExactlyAsBefore) {
  write_file(dir_ / "lobes.csv", "stale\n");
  write_file(dir_ / "other.txt", "keep\n");
  const std::vector<std::string> before = listing(dir_);
  {
    OutputTransaction outputs;
    outputs.open(dir_ / "lobes.csv") << "new contents\n";
    outputs.open(dir_ / "new.json") << "{}\n";
    const fs::path scratch = outputs.scratch_dir(dir_ / "figure.png");
    EXPECT_EQ(scratch.parent_path(), dir_);
    write_file(scratch / "figure.png", "png bytes");
    write_file(scratch / "gnuplot.stderr", "");
    outputs.adopt(scratch / "figure.png", dir_ / "figure.png");
    EXPECT_GT(listing(dir_).size(), before.size());
    // an error is thrown here in real use: no commit
  }
  EXPECT_EQ(listing(dir_), before);
  EXPECT_EQ(read_file(dir_ / "lobes.csv"), "stale\n");
}

TEST_F(OutputTransactionTest, CommitReplacesAnExistingFile) {
  write_file(dir_ / "lobes.csv", "stale\n");
  OutputTransaction outputs;
  outputs.open(dir_ / "lobes.csv") << "fresh\n";
  EXPECT_EQ(read_file(dir_ / "lobes.csv"), "stale\n");
  outputs.commit();
  EXPECT_EQ(read_file(dir_ / "lobes.csv"), "fresh\n");
  EXPECT_EQ(listing(dir_), std::vector<std::string>{"lobes.csv"});
}

TEST_F(OutputTransactionTest, AdoptedFilesAndScratchFolder) {
  OutputTransaction outputs;
  const fs::path scratch = outputs.scratch_dir(dir_ / "f.png");
  EXPECT_TRUE(fs::is_directory(scratch));
  EXPECT_TRUE(fs::is_empty(scratch));
  EXPECT_EQ(scratch.filename().string().rfind(".f.png.cutdyn-tmp-", 0), 0u) << scratch;
  const fs::path second = outputs.scratch_dir(dir_ / "f.png");
  EXPECT_NE(second, scratch);  // fresh every time

  write_file(scratch / "f.png", "image");
  write_file(scratch / "log.txt", "not adopted");
  outputs.adopt(scratch / "f.png", dir_ / "f.png");
  outputs.commit();
  EXPECT_EQ(listing(dir_), std::vector<std::string>{"f.png"});  // scratch folders gone
  EXPECT_EQ(read_file(dir_ / "f.png"), "image");
}

TEST_F(OutputTransactionTest, MissingAdoptedFileFailsCommitAndRenamesNothing) {
  {
    OutputTransaction outputs;
    outputs.open(dir_ / "a.csv") << "a\n";
    outputs.adopt(dir_ / "does-not-exist", dir_ / "b.png");
    EXPECT_THROW(outputs.commit(), std::runtime_error);
  }
  EXPECT_TRUE(listing(dir_).empty());
}

TEST_F(OutputTransactionTest, OpenInMissingFolderThrowsNamingThePath) {
  const fs::path target = dir_ / "no-such-folder" / "lobes.csv";
  OutputTransaction outputs;
  try {
    outputs.open(target);
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("cannot write " + target.string() + ": ", 0), 0u) << message;
    EXPECT_NE(message.find("does not exist"), std::string::npos) << message;
  }
  EXPECT_THROW(outputs.scratch_dir(target), std::runtime_error);
  EXPECT_TRUE(listing(dir_).empty());
}

TEST_F(OutputTransactionTest, OpenInUnwritableFolderThrowsNamingThePath) {
  // Root writes through permission bits, so as root use /proc, where nobody can create files.
  const bool root = ::geteuid() == 0;
  const fs::path locked = root ? fs::path("/proc") : dir_ / "locked";
  if (!root) {
    fs::create_directory(locked);
    fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
  }
  OutputTransaction outputs;
  try {
    outputs.open(locked / "lobes.csv");
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    const std::string prefix = "cannot write " + (locked / "lobes.csv").string() + ": ";
    EXPECT_EQ(std::string(e.what()).substr(0, prefix.size()), prefix) << e.what();
    if (!root) {
      EXPECT_EQ(std::string(e.what()), prefix + "Permission denied");
    }
  }
  EXPECT_FALSE(fs::exists(locked / "lobes.csv"));
  if (!root) {
    fs::permissions(locked, fs::perms::owner_all);
    EXPECT_TRUE(listing(locked).empty());  // no temporary left either
  }
}

TEST_F(OutputTransactionTest, OpenOnAFolderThrows) {
  fs::create_directory(dir_ / "sub");
  OutputTransaction outputs;
  EXPECT_THROW(outputs.open(dir_ / "sub"), std::runtime_error);
}

TEST_F(OutputTransactionTest, SameTargetTwiceIsBadInput) {
  OutputTransaction outputs;
  outputs.open(dir_ / "lobes.csv");
  EXPECT_THROW(outputs.open(dir_ / "lobes.csv"), InvalidInput);
  EXPECT_THROW(outputs.open(dir_ / "." / "lobes.csv"), InvalidInput);
  EXPECT_THROW(outputs.adopt(dir_ / "x", dir_ / "lobes.csv"), InvalidInput);
}

// An InputScope's files are refused as outputs, by identity: the path, another spelling, a
// symbolic link, a hard link; a file outside the scope, and any file without a scope, is not.
TEST_F(OutputTransactionTest, AnInputOfTheScopeIsNeverAnOutput) {
  std::ofstream(dir_ / "other.toml") << "x\n";
  {
    OutputTransaction outputs;
    outputs.open(dir_ / "case.toml") << "no scope: written\n";
    outputs.commit();
  }
  std::ofstream(dir_ / "case.toml") << "process = \"milling\"\n";
  std::filesystem::create_symlink(dir_ / "case.toml", dir_ / "link.toml");
  std::filesystem::create_hard_link(dir_ / "case.toml", dir_ / "hard.toml");
  InputScope scope;
  note_input(dir_ / "case.toml");
  note_input(dir_ / "missing.toml");  // (not a file: nothing noted)
  for (const std::filesystem::path& target :
       {dir_ / "case.toml", dir_ / "." / "case.toml", dir_ / "link.toml", dir_ / "hard.toml"}) {
    OutputTransaction outputs;
    try {
      outputs.open(target);
      ADD_FAILURE() << target << " was opened";
    } catch (const InvalidInput& e) {
      EXPECT_NE(e.problems().at(0).find("is an input of the command (" +
                                        (dir_ / "case.toml").string() + ")"),
                std::string::npos)
          << e.problems().at(0);
    }
    EXPECT_THROW(outputs.adopt(dir_ / "t", target), InvalidInput);
  }
  OutputTransaction outputs;
  outputs.open(dir_ / "other.toml") << "y\n";
  outputs.open(dir_ / "missing.toml") << "z\n";
  outputs.commit();
  EXPECT_EQ(read_file(dir_ / "case.toml"), "process = \"milling\"\n");
  EXPECT_EQ(input_overwrite_problem(dir_ / "hard.toml", "--out").rfind("--out = ", 0), 0u);
  EXPECT_EQ(input_overwrite_problem("-", "--out"), "");
}

TEST_F(OutputTransactionTest, UseAfterCommitIsALogicError) {
  OutputTransaction outputs;
  outputs.open(dir_ / "a.csv") << "a\n";
  outputs.commit();
  EXPECT_THROW(outputs.open(dir_ / "b.csv"), std::logic_error);
  EXPECT_THROW(outputs.commit(), std::logic_error);
  EXPECT_EQ(listing(dir_), std::vector<std::string>{"a.csv"});
}

TEST_F(OutputTransactionTest, CsvThroughATransactionLeavesNoFileWhenARowIsBad) {
  {
    OutputTransaction outputs;
    CsvWriter csv(outputs.open(dir_ / "lobes.csv"), {"spindle_rpm", "critical_depth_mm"});
    csv.row({500.0, 1.5});
    EXPECT_THROW(csv.row({600.0, std::nan("")}), std::logic_error);
  }
  EXPECT_TRUE(listing(dir_).empty());
}

}  // namespace
}  // namespace cutdyn::io

namespace cutdyn::io {
namespace {

// "-", symbolic links, FIFOs and devices are written through, not replaced (the atomic
// rename would have turned a link into a file and, run as root, /dev/null into one).
class WriteThroughTest : public testing::TempDirTest {
 protected:
  void TearDown() override {
    OutputTransaction::set_standard_output(nullptr);
    testing::TempDirTest::TearDown();
  }
};

TEST_F(WriteThroughTest, DevStdoutAndDevStderrAreTheStreamsSet) {
  // /dev/stdout on a pipe resolves to "pipe:[…]", which no one can open by name: the
  // program's own streams are used instead, as for "-".
  std::ostringstream out, err;
  OutputTransaction::set_standard_output(&out);
  OutputTransaction::set_standard_error(&err);
  OutputTransaction t;
  t.open("/dev/stdout") << "o\n";
  t.open("/dev/stderr") << "e\n";
  EXPECT_EQ(out.str(), "");
  t.commit();
  OutputTransaction::set_standard_error(nullptr);
  EXPECT_EQ(out.str(), "o\n");
  EXPECT_EQ(err.str(), "e\n");
  for (const char* name : {"-", "/dev/stdout", "/dev/fd/1", "/proc/self/fd/1"})
    EXPECT_EQ(standard_stream(name), 1) << name;
  for (const char* name : {"/dev/stderr", "/dev/fd/2", "/proc/self/fd/2"})
    EXPECT_EQ(standard_stream(name), 2) << name;
  for (const char* name : {"out.csv", "/dev/null", "/dev/fd/3", "-x"})
    EXPECT_EQ(standard_stream(name), 0) << name;
}

TEST_F(WriteThroughTest, DashIsStandardOutputAfterCommitOnly) {
  std::ostringstream standard_output;
  OutputTransaction::set_standard_output(&standard_output);
  {
    OutputTransaction t;
    t.open("-") << "a,b\n1,2\n";
    EXPECT_EQ(standard_output.str(), "");  // nothing before commit
  }  // rolled back: still nothing
  EXPECT_EQ(standard_output.str(), "");
  OutputTransaction t;
  t.open("-") << "a,b\n1,2\n";
  t.open(dir_ / "x.csv") << "x\n";
  EXPECT_THROW(t.open("-"), InvalidInput);            // one "-" per transaction
  EXPECT_THROW(t.open("/dev/stdout"), InvalidInput);  // (the same stream)
  t.commit();
  EXPECT_EQ(standard_output.str(), "a,b\n1,2\n");
  EXPECT_EQ(read_file(dir_ / "x.csv"), "x\n");
  EXPECT_EQ(listing(dir_), (std::vector<std::string>{"x.csv"}));
  // Without a standard output (a library caller), "-" is refused by name.
  OutputTransaction::set_standard_output(nullptr);
  OutputTransaction u;
  try {
    u.open("-");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "cannot write -: standard output is not available here");
  }
}

TEST_F(WriteThroughTest, ASymbolicLinkStaysALinkAndItsFileGetsTheContent) {
  std::ofstream(dir_ / "real.csv") << "old\n";
  fs::create_symlink(dir_ / "real.csv", dir_ / "link.csv");
  OutputTransaction t;
  t.open(dir_ / "link.csv") << "new\n";
  t.commit();
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir_ / "link.csv")));
  EXPECT_EQ(read_file(dir_ / "real.csv"), "new\n");
  EXPECT_EQ(listing(dir_), (std::vector<std::string>{"link.csv", "real.csv"}));
  // A link to a file that does not exist yet: the file is created, the link kept.
  fs::create_symlink(dir_ / "later.csv", dir_ / "dangling.csv");
  OutputTransaction u;
  u.open(dir_ / "dangling.csv") << "made\n";
  u.commit();
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir_ / "dangling.csv")));
  EXPECT_EQ(read_file(dir_ / "later.csv"), "made\n");
}

TEST_F(WriteThroughTest, AFifoIsWrittenAndADeviceIsNotReplaced) {
  const fs::path fifo = dir_ / "pipe";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string received;
  std::thread reader([&] { received = read_file(fifo); });
  {
    OutputTransaction t;
    t.open(fifo) << "through the pipe\n";
    t.commit();
  }
  reader.join();
  EXPECT_EQ(received, "through the pipe\n");
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_EQ(listing(dir_), (std::vector<std::string>{"pipe"}));
  OutputTransaction t;
  t.open("/dev/null") << "discarded\n";
  t.commit();
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
}

}  // namespace
}  // namespace cutdyn::io
