// Output files that appear whole or not at all.
//
// A command opens every output through one OutputTransaction. Each regular file is written to
// a temporary name in the target's folder; `commit()` renames them all into place. If the
// transaction is destroyed without commit (an error was thrown), the temporaries are
// removed and no output file is left behind, partial or stale.
//
// Other targets are written through, not replaced: "-" and /dev/stdout are standard output,
// /dev/stderr standard error (the streams set by `set_standard_output` and
// `set_standard_error`), a symbolic link is followed (its target file gets the atomic
// rename, the link stays), and an existing FIFO, device or socket is opened and written at
// commit. Their content is held in memory until then, so an error still writes nothing.
//
// A target named twice, or one that is an input of the command (a file noted in the thread's
// InputScope, cutdyn/io/inputs.hpp), is refused with InvalidInput.
#pragma once

#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <ostream>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

namespace cutdyn::io {

class OutputTransaction {
 public:
  OutputTransaction() = default;
  OutputTransaction(const OutputTransaction&) = delete;
  OutputTransaction& operator=(const OutputTransaction&) = delete;
  ~OutputTransaction();

  /// Opens `target` for writing (truncating). Throws std::runtime_error naming the path
  /// if its folder does not exist or is not writable, or for "-" when no standard output is
  /// set.
  std::ostream& open(const std::filesystem::path& target);

  /// Where "-" goes (the command line sets its standard output; nullptr: "-" is refused).
  /// For the calling thread.
  static void set_standard_output(std::ostream* out);
  /// Where /dev/stderr goes (nullptr: to the device, as any other). For the calling thread.
  static void set_standard_error(std::ostream* err);

  /// Adds a file that was written by someone else (e.g. gnuplot) at `temporary`, to be
  /// renamed to `target` on commit and deleted on rollback.
  void adopt(const std::filesystem::path& temporary, const std::filesystem::path& target);

  /// A fresh, empty temporary folder beside `target` (removed on commit or rollback).
  std::filesystem::path scratch_dir(const std::filesystem::path& target);

  /// Flushes and closes every stream, then renames every temporary into place.
  /// Throws std::runtime_error if any write failed (then nothing is renamed).
  void commit();

 private:
  struct Entry {
    std::filesystem::path temporary;
    std::filesystem::path target;
    std::unique_ptr<std::ofstream> stream;  // null for adopted files and written-through ones
    /// Written through at commit: "-" (standard output) or a FIFO, device or socket.
    std::unique_ptr<std::ostringstream> held;
  };
  void rollback() noexcept;
  void check_target(const std::filesystem::path& requested, const std::filesystem::path& id) const;
  std::vector<Entry> entries_;
  std::vector<std::filesystem::path> scratch_dirs_;
  bool committed_ = false;
};

/// 1 if `target` names standard output ("-", /dev/stdout, /dev/fd/1, /proc/self/fd/1), 2 if
/// it names standard error (/dev/stderr, /dev/fd/2, /proc/self/fd/2), else 0.
int standard_stream(const std::filesystem::path& target);

/// One CSV cell: a number, an integer or a text (quoted if it holds , or ").
using CsvCell = std::variant<double, long long, std::string>;

/// Writes a header line, then rows. Doubles are written in shortest round-trip form.
/// A non-finite double is a programming error: it throws std::logic_error naming the
/// column, so that NaN never reaches an output file.
class CsvWriter {
 public:
  CsvWriter(std::ostream& out, std::vector<std::string> columns);
  void row(const std::vector<CsvCell>& cells);

 private:
  std::ostream& out_;
  std::vector<std::string> columns_;
};

/// Writes `value` with 2-space indentation and a final newline. Throws std::logic_error
/// if it holds a non-finite number (nlohmann::json would write null).
void write_json(std::ostream& out, const nlohmann::json& value);

/// Formats a double in shortest round-trip form ("0.1", "2.26e+08").
std::string format_number(double value);

}  // namespace cutdyn::io
