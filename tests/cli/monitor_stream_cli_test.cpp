// `cutdyn monitor estimate` on streams that misbehave (docs/models/monitor.md §4.4, §6): in
// process through cli::run for what a file can hold (binary data, NUL bytes, line ends of every
// kind, values the estimator cannot take), and as a real process for what only a pipe does (a
// writer that pauses, a non-blocking pipe, a reader that closes the output, a line of 64 MiB
// and its memory). Every process is waited for with a time limit and killed past it.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cli/app.hpp"
#include "support/cli_runner.hpp"
#include "support/temp_dir.hpp"

namespace cutdyn::cli {
namespace {

using Clock = std::chrono::steady_clock;

const std::string kHeader = "time_s,axis,iu_a,iv_a,iw_a,speed_rad_s\n";

// Line k of a steady log of axis x at 1 kHz.
std::string sample(int k) {
  return std::to_string(k) + "e-3,x," + std::to_string(20 + k % 7) + ",-10,-10,50\n";
}

std::string steady_log(int lines) {
  std::string text = kHeader;
  for (int k = 0; k < lines; ++k) text += sample(k);
  return text;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// ---- in process -----------------------------------------------------------------------------

class MonitorStreamCli : public testing::TempDirTest {
 protected:
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name), std::ios::binary) << text;
    return path(name);
  }
  testing::CliResult estimate(const std::string& file, std::vector<std::string> more = {}) {
    std::vector<std::string> args = {"monitor", "estimate", "--calib", "zheng2012", path(file)};
    args.insert(args.end(), more.begin(), more.end());
    return testing::run_cutdyn(args);
  }
  void pause_and_resume(bool nonblocking);
};

TEST_F(MonitorStreamCli, LineEndsOfEveryKindGiveTheSameEstimate) {
  const std::string lf = steady_log(300);
  const testing::CliResult base = estimate(write("lf.csv", lf));
  ASSERT_EQ(base.code, 0) << base.err;
  ASSERT_EQ(lines_of(base.out).size(), 301u);
  std::string crlf, cr, mixed;
  int k = 0;
  for (const char c : lf) {
    if (c != '\n') {
      crlf += c, cr += c, mixed += c;
      continue;
    }
    crlf += "\r\n";
    cr += '\r';
    mixed += k % 3 == 0 ? "\n" : k % 3 == 1 ? "\r\n" : "\r";
    ++k;
  }
  for (const auto& [name, text] :
       {std::pair{"crlf.csv", crlf}, std::pair{"cr.csv", cr}, std::pair{"mixed.csv", mixed}}) {
    const testing::CliResult r = estimate(write(name, text));
    EXPECT_EQ(r.code, 0) << name << ": " << r.err;
    EXPECT_EQ(r.out, base.out) << name;  // the estimate is written with LF, whatever came in
  }
}

TEST_F(MonitorStreamCli, NulBytesStopTheRunNamingTheLineAndLeaveNoFile) {
  std::string text = steady_log(10);
  text.insert(text.find("5e-3,x,") + 7, std::string(1, '\0'));  // line 7, byte 8
  write("nul.csv", text);
  const testing::CliResult stop = estimate("nul.csv", {"--out", path("est.csv")});
  EXPECT_EQ(stop.code, 2);
  EXPECT_NE(stop.err.find("cutdyn: error: " + path("nul.csv") +
                          ": line 7: a NUL byte at byte 8 of the line: binary data, not text"),
            std::string::npos)
      << stop.err;
  EXPECT_FALSE(std::filesystem::exists(path("est.csv")));
  EXPECT_EQ(testing::listing(dir_), std::vector<std::string>{"nul.csv"});
  const testing::CliResult skip = estimate("nul.csv", {"--on-bad-line", "skip"});
  EXPECT_EQ(skip.code, 0) << skip.err;
  EXPECT_EQ(lines_of(skip.out).size(), 10u);  // header + 9 of 10
  EXPECT_NE(skip.err.find("skipped 1 bad line"), std::string::npos) << skip.err;
}

TEST_F(MonitorStreamCli, ABinaryBlobIsCountedAndTheSummaryIsValidJson) {
  std::mt19937 rng(2);
  std::string blob(200'000, '\0');
  for (char& c : blob) c = static_cast<char>(rng() & 0xff);
  std::string text = steady_log(100) + blob + "\n";
  for (int k = 100; k < 200; ++k) text += sample(k);
  write("blob.csv", text);
  const testing::CliResult r =
      estimate("blob.csv", {"--on-bad-line", "skip", "--json", path("est.json")});
  ASSERT_EQ(r.code, 0) << r.err.substr(0, 2000);
  const std::vector<std::string> out = lines_of(r.out);
  ASSERT_EQ(out.size(), 201u);  // every good line, before and after the blob
  EXPECT_EQ(out[101].rfind("0.1,x,", 0), 0u) << out[101];
  // The count, and the first five named.
  const auto at = r.err.find(": skipped ");
  ASSERT_NE(at, std::string::npos) << r.err;
  EXPECT_GT(std::stoi(r.err.substr(at + 10)), 1000);  // about 1 line end in 128 random bytes
  std::size_t named = 0;
  for (std::size_t k = 0; (k = r.err.find("(skipped)\n", k)) != std::string::npos; ++k) ++named;
  EXPECT_EQ(named, 5u) << r.err;
  // Whatever the bytes, the messages are text: the JSON summary parses.
  EXPECT_NO_THROW({
    const nlohmann::json summary = nlohmann::json::parse(testing::read_file(path("est.json")));
    EXPECT_EQ(summary.at("samples"), 200);
  });
  EXPECT_EQ(r.err.find('\0'), std::string::npos);
}

TEST_F(MonitorStreamCli, ValuesTheEstimatorCannotTakeAreBadLinesNeverInfinities) {
  // Finite in the log, but their squares overflow: no inf or nan in the output; the axis
  // starts afresh after the line and the estimates go on.
  std::string text = steady_log(50);
  text += "0.05,x,1e200,-5e199,-5e199,50\n";
  for (int k = 51; k < 100; ++k) text += sample(k);
  write("huge.csv", text);
  const testing::CliResult stop = estimate("huge.csv");
  EXPECT_EQ(stop.code, 2);
  EXPECT_NE(stop.err.find("line 52: the estimate of axis x is not finite"), std::string::npos)
      << stop.err;
  EXPECT_EQ(lines_of(stop.out).size(), 51u);  // the lines before it were written
  const testing::CliResult skip = estimate("huge.csv", {"--on-bad-line", "skip"});
  ASSERT_EQ(skip.code, 0) << skip.err;
  EXPECT_EQ(lines_of(skip.out).size(), 100u);
  EXPECT_EQ(skip.out.find("inf"), std::string::npos);
  EXPECT_EQ(skip.out.find("nan"), std::string::npos);
  // After the restart the axis is estimated as if its log began at line 53: the same lines as
  // those of a log that starts there.
  std::string restart = kHeader;
  for (int k = 51; k < 100; ++k) restart += sample(k);
  const testing::CliResult fresh = estimate(write("fresh.csv", restart));
  ASSERT_EQ(fresh.code, 0);
  const std::vector<std::string> a = lines_of(skip.out), b = lines_of(fresh.out);
  EXPECT_EQ(std::vector<std::string>(a.begin() + 51, a.end()),
            std::vector<std::string>(b.begin() + 1, b.end()));
}

// ---- as a process -----------------------------------------------------------------------------

struct Pipe {
  int read = -1, write = -1;
  Pipe() {
    int fd[2];
    if (pipe2(fd, O_CLOEXEC) == 0) read = fd[0], write = fd[1];
  }
  ~Pipe() { close_read(), close_write(); }
  void close_read() {
    if (read >= 0) ::close(read);
    read = -1;
  }
  void close_write() {
    if (write >= 0) ::close(write);
    write = -1;
  }
};

struct Spawn {
  bool ignore_sigpipe = false;  // the disposition the process inherits
  bool nonblocking_input = false;
};

// `cutdyn monitor estimate --calib zheng2012 - <more>` with the given descriptors as its
// standard input, output and error (the test's own descriptors are close-on-exec).
pid_t start(int in, int out, int err, const std::vector<std::string>& more, Spawn how = {}) {
  std::vector<std::string> args = {"cutdyn", "monitor", "estimate", "--calib", "zheng2012", "-"};
  args.insert(args.end(), more.begin(), more.end());
  std::vector<char*> argv;  // made before the fork: the child only calls what is safe there
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid != 0) return pid;
  dup2(in, 0);
  dup2(out, 1);
  dup2(err, 2);
  signal(SIGPIPE, how.ignore_sigpipe ? SIG_IGN : SIG_DFL);
  if (how.nonblocking_input) fcntl(0, F_SETFL, fcntl(0, F_GETFL) | O_NONBLOCK);
  execv(CUTDYN_BINARY, argv.data());
  _exit(127);
}

struct Exit {
  bool in_time = false;
  int status = 0;
  rusage usage{};
};

// Waits for `pid` up to `limit_s`, then kills it.
Exit wait_for(pid_t pid, double limit_s) {
  Exit e;
  const auto until = Clock::now() + std::chrono::duration<double>(limit_s);
  while (Clock::now() < until) {
    if (wait4(pid, &e.status, WNOHANG, &e.usage) == pid) {
      e.in_time = true;
      return e;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  kill(pid, SIGKILL);
  wait4(pid, &e.status, 0, &e.usage);
  return e;
}

bool exited_with(const Exit& e, int code) {
  return e.in_time && WIFEXITED(e.status) && WEXITSTATUS(e.status) == code;
}

std::string describe(const Exit& e) {
  if (!e.in_time) return "killed after the time limit";
  if (WIFSIGNALED(e.status))
    return std::string("ended by signal ") + strsignal(WTERMSIG(e.status)) +
           (WCOREDUMP(e.status) ? " (core dumped)" : "");
  return "exit status " + std::to_string(WEXITSTATUS(e.status));
}

// Reads from `fd` until it holds `lines` line ends (or its end, or the time limit).
bool read_lines(int fd, std::string& text, std::size_t lines, double limit_s) {
  const auto until = Clock::now() + std::chrono::duration<double>(limit_s);
  char buffer[65536];
  while (static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) < lines) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(until - Clock::now());
    pollfd p{fd, POLLIN, 0};
    if (left.count() <= 0 || poll(&p, 1, static_cast<int>(left.count())) <= 0) return false;
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n <= 0) return false;
    text.append(buffer, static_cast<std::size_t>(n));
  }
  return true;
}

// Reads from `fd` to its end (false at the time limit).
bool read_to_end(int fd, std::string& text, double limit_s) {
  read_lines(fd, text, static_cast<std::size_t>(-1), limit_s);
  pollfd p{fd, POLLIN, 0};
  return poll(&p, 1, 0) == 1 && ::read(fd, &p, 1) == 0;
}

// Writes all of `text` to `fd` (false if the reader went away or at the time limit).
bool write_all(int fd, std::string_view text, double limit_s) {
  const auto until = Clock::now() + std::chrono::duration<double>(limit_s);
  while (!text.empty()) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(until - Clock::now());
    pollfd p{fd, POLLOUT, 0};
    if (left.count() <= 0 || poll(&p, 1, static_cast<int>(left.count())) <= 0) return false;
    const ssize_t n = ::write(fd, text.data(), text.size());
    if (n <= 0) return false;
    text.remove_prefix(static_cast<std::size_t>(n));
  }
  return true;
}

// SIGPIPE ignored in this test process while it writes to a child that may have gone.
struct IgnoreSigpipe {
  struct sigaction old {};
  IgnoreSigpipe() {
    struct sigaction ignore {};
    ignore.sa_handler = SIG_IGN;
    sigaction(SIGPIPE, &ignore, &old);
  }
  ~IgnoreSigpipe() { sigaction(SIGPIPE, &old, nullptr); }
};

int open_file(const std::string& file, int flags) {
  return ::open(file.c_str(), flags | O_CLOEXEC, 0644);
}

// No error on stderr.
void expect_no_error(const std::string& err) {
  EXPECT_EQ(err.find("cutdyn: error"), std::string::npos) << err;
}

// Only warnings on stderr (the literature calibration's unknown uncertainty): no error, no
// message about the pipe, no summary.
void expect_only_warnings(const std::string& err) {
  for (const std::string& line : lines_of(err))
    EXPECT_EQ(line.rfind("cutdyn: warning: ", 0), 0u) << err;
}

TEST_F(MonitorStreamCli, AReaderThatClosesTheOutputEndsTheRunQuietly) {
  // `cutdyn monitor estimate ... | head -1`: the first line read, the pipe closed; the run ends
  // at its next write with status 141 (kExitOutputClosed), no message, no signal, no core —
  // whether SIGPIPE was inherited as the default or as ignored.
  write("big.csv", steady_log(300'000));  // 13 MB of estimate: far more than a pipe holds
  for (const bool ignored : {false, true}) {
    Pipe out;
    const int in = open_file(path("big.csv"), O_RDONLY);
    const int err = open_file(path("err.txt"), O_WRONLY | O_CREAT | O_TRUNC);
    const pid_t pid = start(in, out.write, err, {}, {ignored, false});
    ::close(in);
    ::close(err);
    out.close_write();
    std::string text;
    EXPECT_TRUE(read_lines(out.read, text, 1, 10.0));
    out.close_read();
    const Exit e = wait_for(pid, 15.0);
    EXPECT_TRUE(exited_with(e, kExitOutputClosed))
        << describe(e) << ", SIGPIPE ignored " << ignored;
    EXPECT_EQ(text.substr(0, text.find('\n')),
              "time_s,axis,force_n,force_sigma_n,speed_rad_s,"
              "accel_rad_s2");
    expect_only_warnings(testing::read_file(path("err.txt")));
  }
}

TEST_F(MonitorStreamCli, AReaderThatClosesTheOutputEndsALiveStream) {
  // The same on a live input that never ends by itself: the run ends at the write after the
  // reader went away, and its input is closed (the writer sees EPIPE).
  IgnoreSigpipe guard;
  Pipe in, out;
  const int err = open_file(path("err.txt"), O_WRONLY | O_CREAT | O_TRUNC);
  const pid_t pid = start(in.read, out.write, err, {});
  ::close(err);
  in.close_read();
  out.close_write();
  ASSERT_TRUE(write_all(in.write, kHeader + sample(0) + sample(1), 5.0));
  std::string text;
  EXPECT_TRUE(read_lines(out.read, text, 2, 10.0)) << text;
  out.close_read();
  bool writer_saw_the_end = false;
  const auto until = Clock::now() + std::chrono::seconds(10);
  for (int k = 2; Clock::now() < until; ++k) {
    if (!write_all(in.write, sample(k), 1.0)) {
      writer_saw_the_end = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  EXPECT_TRUE(writer_saw_the_end);
  const Exit e = wait_for(pid, 10.0);
  EXPECT_TRUE(exited_with(e, kExitOutputClosed)) << describe(e);
  expect_only_warnings(testing::read_file(path("err.txt")));
}

// A writer that stops in the middle of a line for 1.5 s, then goes on: every line before the
// pause is answered during it, and the whole output is the file's, byte for byte.
void MonitorStreamCli::pause_and_resume(bool nonblocking) {
  const std::string text = steady_log(200);
  const std::size_t cut = text.find(sample(100)) + 7;  // within line 102
  IgnoreSigpipe guard;
  Pipe in, out;
  const int err = open_file(path("err.txt"), O_WRONLY | O_CREAT | O_TRUNC);
  const pid_t pid = start(in.read, out.write, err, {}, {false, nonblocking});
  ::close(err);
  in.close_read();
  out.close_write();
  ASSERT_TRUE(write_all(in.write, std::string_view(text).substr(0, cut), 5.0));
  std::string received;
  EXPECT_TRUE(read_lines(out.read, received, 101, 10.0)) << "not answered before the pause";
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  int status = 0;
  EXPECT_EQ(waitpid(pid, &status, WNOHANG), 0) << "the run ended during the pause";
  pollfd p{out.read, POLLIN, 0};
  EXPECT_EQ(poll(&p, 1, 0), 0) << "output for a line not yet complete";
  EXPECT_TRUE(write_all(in.write, std::string_view(text).substr(cut), 5.0));
  in.close_write();
  EXPECT_TRUE(read_to_end(out.read, received, 10.0));
  const Exit e = wait_for(pid, 10.0);
  EXPECT_TRUE(exited_with(e, 0)) << describe(e) << ": " << testing::read_file(path("err.txt"));
  expect_no_error(testing::read_file(path("err.txt")));
  const testing::CliResult file = estimate(write("same.csv", text));
  ASSERT_EQ(file.code, 0);
  EXPECT_EQ(received, file.out);
  EXPECT_EQ(lines_of(received).size(), 201u);
}

TEST_F(MonitorStreamCli, AStreamThatPausesIsAnsweredBeforeAndAfterThePause) {
  pause_and_resume(false);
}

TEST_F(MonitorStreamCli, ANonBlockingInputThatPausesIsWaitedFor) {
  // A writer may hand over its pipe non-blocking: a read then finds nothing during a pause
  // (EAGAIN), which is a pause, not an error nor the end.
  pause_and_resume(true);
}

// The largest resident size of a run that reads `text` then `lines` MiB of one line then
// `rest`, written to its standard input.
struct LongLineRun {
  Exit exit;
  std::string out, err;
};

LongLineRun run_long_line(const std::string& dir, const std::string& text, int mib,
                          const std::string& rest, const std::vector<std::string>& more) {
  IgnoreSigpipe guard;
  Pipe in;
  const int out = open_file(dir + "/out.txt", O_WRONLY | O_CREAT | O_TRUNC);
  const int err = open_file(dir + "/err.txt", O_WRONLY | O_CREAT | O_TRUNC);
  const pid_t pid = start(in.read, out, err, more);
  ::close(out);
  ::close(err);
  in.close_read();
  bool writing = write_all(in.write, text, 5.0);
  const std::string mebibyte(1 << 20, '7');
  for (int k = 0; writing && k < mib; ++k) writing = write_all(in.write, mebibyte, 5.0);
  if (writing) write_all(in.write, rest, 5.0);
  in.close_write();
  LongLineRun r;
  r.exit = wait_for(pid, 15.0);
  r.out = testing::read_file(dir + "/out.txt");
  r.err = testing::read_file(dir + "/err.txt");
  return r;
}

TEST_F(MonitorStreamCli, ALineOf64MebibytesIsSkippedInBoundedMemory) {
  // The parser holds at most 1 MiB of a line (kMaxCurrentLineBytes): a run through a line of
  // 64 MiB stays within a few MiB of a run of a short log. Reading it all in would add 64 MiB
  // at least.
  const LongLineRun small = run_long_line(dir_.string(), steady_log(3), 0, "", {});
  ASSERT_TRUE(exited_with(small.exit, 0)) << describe(small.exit) << small.err;
  const std::string text = steady_log(3) + "3e-3,x,20,-10,-10,";
  const std::string rest = "\n" + sample(4) + sample(5);
  const LongLineRun big = run_long_line(dir_.string(), text, 64, rest, {"--on-bad-line", "skip"});
  ASSERT_TRUE(exited_with(big.exit, 0)) << describe(big.exit) << big.err;
  EXPECT_EQ(lines_of(big.out).size(), 6u);  // header + 3 + 2
  EXPECT_NE(big.err.find("standard input: line 5: the line is 67108882 bytes long, longer than "
                         "the limit of 1048576 bytes (1 MiB) (skipped)"),
            std::string::npos)
      << big.err;
  EXPECT_NE(big.err.find("standard input: skipped 1 bad line"), std::string::npos) << big.err;
  const long grew_kib = big.exit.usage.ru_maxrss - small.exit.usage.ru_maxrss;
  EXPECT_LT(grew_kib, 8 * 1024) << "resident size " << small.exit.usage.ru_maxrss << " KiB, then "
                                << big.exit.usage.ru_maxrss << " KiB with the long line";
}

TEST_F(MonitorStreamCli, ALineThatNeverEndsStopsTheRunAtTheLimit) {
  // stop (the default): refused once past 1 MiB, not when (or if) it ends; exit 2.
  const LongLineRun r = run_long_line(dir_.string(), steady_log(3) + "3e-3,x,", 256, "\n", {});
  EXPECT_TRUE(exited_with(r.exit, 2)) << describe(r.exit) << r.err;
  EXPECT_NE(r.err.find("cutdyn: error: standard input: line 5: the line is longer than the limit "
                       "of 1048576 bytes (1 MiB): "),
            std::string::npos)
      << r.err;
  EXPECT_EQ(lines_of(r.out).size(), 4u);  // the lines before it
}

}  // namespace
}  // namespace cutdyn::cli
