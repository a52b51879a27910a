#include "cutdyn/io/output.hpp"

#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <mutex>
#include <random>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "cutdyn/core/error.hpp"
#include "cutdyn/io/inputs.hpp"

namespace cutdyn::io {
namespace fs = std::filesystem;

namespace {

// Hidden names beside the target, so a rename is atomic (same folder, same file system)
// and leftovers of a killed run are easy to find: `.<name>.cutdyn-tmp-<random>`.
constexpr const char* kTemporaryTag = ".cutdyn-tmp-";
constexpr int kNameAttempts = 100;

std::string random_suffix() {
  thread_local std::mt19937_64 engine = [] {
    std::random_device device;
    std::seed_seq seed{
        static_cast<std::uint64_t>(device()), static_cast<std::uint64_t>(device()),
        static_cast<std::uint64_t>(::getpid()),
        static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count())};
    return std::mt19937_64(seed);
  }();
  static constexpr char kDigits[] = "0123456789abcdefghijklmnopqrstuvwxyz";
  std::uniform_int_distribution<std::size_t> pick(0, sizeof kDigits - 2);
  std::string suffix(12, '0');
  for (char& c : suffix) c = kDigits[pick(engine)];
  return suffix;
}

// ---- Temporaries removed by a fatal signal ----------------------------------------------
// SIGTERM, SIGINT or SIGHUP ends the process without unwinding, so no rollback runs. The
// temporaries that exist are listed here in fixed buffers with atomic states, which is all a
// signal handler may read; it unlinks the files, removes the (then empty) scratch folders,
// and lets the signal end the process as it would have. The targets are untouched either way:
// they are only ever replaced by a rename.
constexpr int kMaxLive = 128;
enum LiveState : int { kFree = 0, kFilling = 1, kFile = 2, kFolder = 3 };
struct LiveTemporary {
  std::atomic<int> state{kFree};
  char path[PATH_MAX] = {};
};
LiveTemporary live_temporaries[kMaxLive];

// Empties a scratch folder (the files a plotting program wrote there) and removes it, with
// system calls only: getdents64 into a buffer on the stack, unlinkat, rmdir.
void remove_folder_in_handler(const char* path) {
  const int fd = ::open(path, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0) {
    alignas(8) char buffer[4096];
    for (;;) {
      const long got = ::syscall(SYS_getdents64, fd, buffer, sizeof buffer);
      if (got <= 0) break;
      for (long at = 0; at < got;) {
        // struct linux_dirent64: ino (8), off (8), reclen (2), type (1), name.
        unsigned short length = 0;
        std::memcpy(&length, buffer + at + 16, sizeof length);
        const char* name = buffer + at + 19;
        if (!(name[0] == '.' && (name[1] == '\0' || (name[1] == '.' && name[2] == '\0'))))
          ::unlinkat(fd, name, 0);
        at += length;
      }
    }
    ::close(fd);
  }
  ::rmdir(path);
}

extern "C" void remove_temporaries_and_stop(int signal_number) {
  for (LiveTemporary& t : live_temporaries)
    if (t.state.load(std::memory_order_acquire) == kFile) ::unlink(t.path);
  for (LiveTemporary& t : live_temporaries)
    if (t.state.load(std::memory_order_acquire) == kFolder) remove_folder_in_handler(t.path);
  ::signal(signal_number, SIG_DFL);
  ::raise(signal_number);
}

// The handler goes only where the signal would end the process anyway (SIG_DFL): a program
// that handles a signal itself (Python's SIGINT, `cutdyn serve`) keeps its handling.
void install_signal_cleanup() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (int signal_number : {SIGTERM, SIGINT, SIGHUP}) {
      struct sigaction current {};
      if (::sigaction(signal_number, nullptr, &current) != 0) continue;
      if (current.sa_handler != SIG_DFL) continue;
      struct sigaction cleanup {};
      cleanup.sa_handler = remove_temporaries_and_stop;
      sigemptyset(&cleanup.sa_mask);
      ::sigaction(signal_number, &cleanup, nullptr);
    }
  });
}

void track(const fs::path& path, LiveState kind) {
  install_signal_cleanup();
  const std::string& text = path.native();
  if (text.size() >= PATH_MAX) return;  // not removed if killed: a hidden leftover, no more
  for (LiveTemporary& t : live_temporaries) {
    int expected = kFree;
    if (t.state.compare_exchange_strong(expected, kFilling, std::memory_order_acq_rel)) {
      std::memcpy(t.path, text.c_str(), text.size() + 1);
      t.state.store(kind, std::memory_order_release);
      return;
    }
  }
}

void untrack(const fs::path& path) {
  for (LiveTemporary& t : live_temporaries) {
    const int state = t.state.load(std::memory_order_acquire);
    if ((state == kFile || state == kFolder) && path.native() == t.path) {
      t.state.store(kFree, std::memory_order_release);
      return;
    }
  }
}

std::string errno_text(int error) { return std::generic_category().message(error); }

[[noreturn]] void throw_cannot_write(const fs::path& target, const std::string& reason) {
  throw std::runtime_error("cannot write " + target.string() + ": " + reason);
}

// The folder that will hold `target`; throws naming `target` if it is unusable.
fs::path folder_of(const fs::path& target) {
  if (target.empty() || !target.has_filename()) throw_cannot_write(target, "not a file name");
  fs::path folder = target.parent_path();
  if (folder.empty()) folder = ".";
  std::error_code ec;
  const fs::file_status status = fs::status(folder, ec);
  if (!fs::exists(status))
    throw_cannot_write(target, "folder " + folder.string() + " does not exist");
  if (!fs::is_directory(status)) throw_cannot_write(target, folder.string() + " is not a folder");
  if (fs::is_directory(fs::status(target, ec))) throw_cannot_write(target, "it is a folder");
  return folder;
}

fs::path temporary_name(const fs::path& folder, const fs::path& target) {
  // Appended piecewise: `"." + std::string` trips GCC 12's false -Wrestrict (PR 105329).
  std::string name(1, '.');
  name += target.filename().string();
  name += kTemporaryTag;
  name += random_suffix();
  return folder / name;
}

// The identity of a target, to catch the same file opened twice under two spellings.
fs::path identity(const fs::path& target) {
  std::error_code ec;
  fs::path absolute = fs::absolute(target, ec);
  return (ec ? target : absolute).lexically_normal();
}

// Forces the data of a finished file to disk before it is renamed into place, so that a
// crash cannot leave an empty file under the final name.
void sync_file(const fs::path& file) {
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

void escape_pointer_token(std::string& pointer, const std::string& key) {
  pointer += '/';
  for (char c : key) {
    if (c == '~') {
      pointer += "~0";
    } else if (c == '/') {
      pointer += "~1";
    } else {
      pointer += c;
    }
  }
}

// Depth-first search for a non-finite number; returns its JSON pointer in `pointer`.
bool find_non_finite(const nlohmann::json& value, std::string& pointer, double& bad) {
  if (value.is_number_float()) {
    const double number = value.get<double>();
    if (std::isfinite(number)) return false;
    bad = number;
    return true;
  }
  const std::size_t length = pointer.size();
  if (value.is_object()) {
    for (auto it = value.begin(); it != value.end(); ++it) {
      escape_pointer_token(pointer, it.key());
      if (find_non_finite(it.value(), pointer, bad)) return true;
      pointer.resize(length);
    }
  } else if (value.is_array()) {
    for (std::size_t i = 0; i < value.size(); ++i) {
      pointer += '/' + std::to_string(i);
      if (find_non_finite(value[i], pointer, bad)) return true;
      pointer.resize(length);
    }
  }
  return false;
}

std::string format_integer(long long value) {
  char buffer[32];
  auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, end);
}

// RFC 4180: a field holding a comma, a quote or a line break is quoted, quotes doubled.
void write_text(std::ostream& out, const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) {
    out << text;
    return;
  }
  out << '"';
  for (char c : text) {
    if (c == '"') out << '"';
    out << c;
  }
  out << '"';
}

thread_local std::ostream* standard_output = nullptr;
thread_local std::ostream* standard_error = nullptr;

// The identities of the standard streams among the targets of a transaction.
const fs::path kStandardOutputId = "-";
const fs::path kStandardErrorId = "<standard error>";

// An existing target that is neither a regular file nor a folder (after following links): a
// FIFO, a device or a socket, written through rather than replaced.
bool is_special(const fs::path& target) {
  std::error_code ec;
  const fs::file_status status = fs::status(target, ec);
  return !ec && fs::exists(status) && !fs::is_regular_file(status) && !fs::is_directory(status);
}

// The file a chain of symbolic links ends at (itself if not a link; a dangling link's target).
fs::path resolve_links(fs::path path) {
  std::error_code ec;
  for (int hop = 0; hop < 40 && fs::is_symlink(fs::symlink_status(path, ec)); ++hop) {
    const fs::path next = fs::read_symlink(path, ec);
    if (ec) break;
    path = (next.is_absolute() ? next : path.parent_path() / next).lexically_normal();
  }
  return path;
}

}  // namespace

// ---- OutputTransaction ----------------------------------------------------------------

OutputTransaction::~OutputTransaction() {
  if (!committed_) rollback();
}

void OutputTransaction::set_standard_output(std::ostream* out) { standard_output = out; }

void OutputTransaction::set_standard_error(std::ostream* err) { standard_error = err; }

int standard_stream(const fs::path& target) {
  const std::string& t = target.native();
  if (t == "-" || t == "/dev/stdout" || t == "/dev/fd/1" || t == "/proc/self/fd/1") return 1;
  if (t == "/dev/stderr" || t == "/dev/fd/2" || t == "/proc/self/fd/2") return 2;
  return 0;
}

// Refuses a second output to the same target, and an output that would replace an input of
// the command (cutdyn/io/inputs.hpp); both are mistakes of the command line.
void OutputTransaction::check_target(const fs::path& requested, const fs::path& id) const {
  for (const Entry& entry : entries_)
    if (entry.target == id)
      throw InvalidInput({requested.string() + ": named by two outputs of the command"},
                         "command line");
  if (const std::string problem = input_overwrite_problem(requested); !problem.empty())
    throw InvalidInput({problem}, "command line");
}

std::ostream& OutputTransaction::open(const fs::path& requested) {
  if (committed_) throw std::logic_error("OutputTransaction: open after commit");
  // "-" (or /dev/stdout): standard output; /dev/stderr: standard error, when the program set
  // them; a symbolic link: the file it points to.
  const int stream_number = standard_stream(requested);
  if (requested == "-" && !standard_output)
    throw_cannot_write(requested, "standard output is not available here");
  const bool to_stream =
      (stream_number == 1 && standard_output) || (stream_number == 2 && standard_error);
  const fs::path target = to_stream ? requested : resolve_links(requested);
  const fs::path id = !to_stream           ? identity(target)
                      : stream_number == 1 ? kStandardOutputId
                                           : kStandardErrorId;
  check_target(requested, id);
  if (to_stream || is_special(target)) {
    auto held = std::make_unique<std::ostringstream>();
    std::ostream& out = *held;
    entries_.push_back(Entry{{}, id, nullptr, std::move(held)});
    return out;
  }
  const fs::path folder = folder_of(target);

  // O_EXCL reserves a name nobody else holds; 0666 lets the umask set the permissions an
  // ordinary output file would get (mkstemp would make it private). The name is listed for
  // the signal handler before the file exists: a signal between the two would otherwise leave
  // the file behind (seen once in some hundred kills), while unlinking a name not yet made
  // does nothing.
  fs::path temporary;
  for (int attempt = 0;; ++attempt) {
    temporary = temporary_name(folder, target);
    track(temporary, kFile);
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      ::close(fd);
      break;
    }
    const int error = errno;
    untrack(temporary);  // (not ours: someone else's file of that name)
    if (error != EEXIST || attempt + 1 >= kNameAttempts)
      throw_cannot_write(target, errno_text(error));
  }

  auto stream = std::make_unique<std::ofstream>(temporary, std::ios::out | std::ios::trunc);
  if (!stream->is_open()) {
    const int error = errno;
    std::error_code ec;
    fs::remove(temporary, ec);
    untrack(temporary);
    throw_cannot_write(target, error != 0 ? errno_text(error) : "cannot open a temporary file");
  }
  std::ostream& out = *stream;
  entries_.push_back(Entry{temporary, id, std::move(stream), nullptr});
  return out;
}

void OutputTransaction::adopt(const fs::path& temporary, const fs::path& target) {
  if (committed_) throw std::logic_error("OutputTransaction: adopt after commit");
  const fs::path id = identity(target);
  check_target(target, id);
  track(temporary, kFile);
  entries_.push_back(Entry{temporary, id, nullptr, nullptr});
}

fs::path OutputTransaction::scratch_dir(const fs::path& target) {
  if (committed_) throw std::logic_error("OutputTransaction: scratch_dir after commit");
  const fs::path folder = folder_of(target);
  for (int attempt = 0;; ++attempt) {
    fs::path dir = temporary_name(folder, target);
    track(dir, kFolder);  // before it exists, as the files in open()
    if (::mkdir(dir.c_str(), 0777) == 0) {
      scratch_dirs_.push_back(dir);
      return dir;
    }
    const int error = errno;
    untrack(dir);  // (not ours)
    if (error != EEXIST || attempt + 1 >= kNameAttempts)
      throw_cannot_write(target, errno_text(error));
  }
}

void OutputTransaction::commit() {
  if (committed_) throw std::logic_error("OutputTransaction: committed twice");

  // 1. Finish every file; any failure so far means nothing is renamed.
  for (Entry& entry : entries_) {
    if (entry.held) {
      if (entry.held->fail()) throw_cannot_write(entry.target, "write failed");
      continue;
    }
    if (entry.temporary.empty()) continue;  // renamed by an earlier, failed commit
    if (entry.stream) {
      if (entry.stream->is_open()) {
        entry.stream->flush();
        entry.stream->close();
      }
      if (entry.stream->fail()) throw_cannot_write(entry.target, "write failed");
    } else {
      std::error_code ec;
      if (!fs::is_regular_file(entry.temporary, ec)) {
        throw_cannot_write(entry.target,
                           "its temporary " + entry.temporary.string() + " is missing");
      }
    }
  }
  for (const Entry& entry : entries_) {
    if (!entry.temporary.empty()) sync_file(entry.temporary);
  }

  // 2. Rename each into place (atomic per file: same folder); write the held ones through.
  for (Entry& entry : entries_) {
    if (entry.held) {
      const std::string content = entry.held->str();
      entry.held.reset();
      if (entry.target == kStandardOutputId || entry.target == kStandardErrorId) {
        const bool out = entry.target == kStandardOutputId;
        std::ostream& stream = out ? *standard_output : *standard_error;
        stream.write(content.data(), static_cast<std::streamsize>(content.size()));
        stream.flush();
        if (!stream)
          throw_cannot_write(entry.target, out ? "write to standard output failed"
                                               : "write to standard error failed");
      } else {
        std::ofstream through(entry.target, std::ios::out | std::ios::binary);
        through.write(content.data(), static_cast<std::streamsize>(content.size()));
        through.close();
        if (!through) throw_cannot_write(entry.target, "write failed");
      }
      continue;
    }
    if (entry.temporary.empty()) continue;
    std::error_code ec;
    fs::rename(entry.temporary, entry.target, ec);
    if (ec) throw_cannot_write(entry.target, ec.message());
    untrack(entry.temporary);
    entry.temporary.clear();
  }

  // 3. Scratch folders hold only leftovers now (logs, files not adopted).
  for (const fs::path& dir : scratch_dirs_) {
    std::error_code ec;
    fs::remove_all(dir, ec);
    untrack(dir);
  }
  scratch_dirs_.clear();
  committed_ = true;
}

void OutputTransaction::rollback() noexcept {
  for (Entry& entry : entries_) {
    if (entry.stream && entry.stream->is_open()) entry.stream->close();
    if (!entry.temporary.empty()) {
      std::error_code ec;
      fs::remove(entry.temporary, ec);
      untrack(entry.temporary);
    }
  }
  entries_.clear();
  for (const fs::path& dir : scratch_dirs_) {
    std::error_code ec;
    fs::remove_all(dir, ec);
    untrack(dir);
  }
  scratch_dirs_.clear();
}

// ---- CSV ------------------------------------------------------------------------------

CsvWriter::CsvWriter(std::ostream& out, std::vector<std::string> columns)
    : out_(out), columns_(std::move(columns)) {
  if (columns_.empty()) throw std::logic_error("CsvWriter: no columns");
  for (std::size_t i = 0; i < columns_.size(); ++i) {
    if (i > 0) out_ << ',';
    write_text(out_, columns_[i]);
  }
  out_ << '\n';
}

void CsvWriter::row(const std::vector<CsvCell>& cells) {
  if (cells.size() != columns_.size()) {
    throw std::logic_error("CsvWriter: a row has " + std::to_string(cells.size()) +
                           " cells but the header has " + std::to_string(columns_.size()) +
                           " columns");
  }
  // Check the whole row first, so that a bad row writes nothing.
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (const double* number = std::get_if<double>(&cells[i]); number && !std::isfinite(*number)) {
      throw std::logic_error("CsvWriter: column \"" + columns_[i] +
                             "\" gets the non-finite value " + format_number(*number));
    }
  }
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (i > 0) out_ << ',';
    if (const double* number = std::get_if<double>(&cells[i])) {
      out_ << format_number(*number);
    } else if (const long long* integer = std::get_if<long long>(&cells[i])) {
      out_ << format_integer(*integer);
    } else {
      write_text(out_, std::get<std::string>(cells[i]));
    }
  }
  out_ << '\n';
}

// ---- JSON -----------------------------------------------------------------------------

void write_json(std::ostream& out, const nlohmann::json& value) {
  std::string pointer;
  double bad = 0.0;
  if (find_non_finite(value, pointer, bad)) {
    throw std::logic_error(
        "write_json: non-finite number " + format_number(bad) + " at " +
        (pointer.empty() ? std::string("the document root") : "\"" + pointer + "\""));
  }
  out << value.dump(2) << '\n';
}

std::string format_number(double value) {
  char buffer[64];
  auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, end);
}

}  // namespace cutdyn::io
