// The files a command reads, so that none of its outputs can replace one of them.
//
// A command opens an InputScope before it reads anything. Every reader of the library (case
// files, the FRF and force files a case names, calibrations, bands, current logs) notes the
// files it opens in the scope of its thread, and OutputTransaction refuses, as invalid input,
// to write a file the scope holds. Files are compared by identity (device and inode), so a
// hard link, a symbolic link or another spelling of the same file is caught. Only regular
// files are noted: a terminal or a pipe may be both read and written.
//
// Without a scope (the library used on its own, the explorer's server) nothing is recorded
// and nothing is refused.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace cutdyn::io {

class InputScope {
 public:
  /// Makes this scope the current one of the calling thread (until it is destroyed).
  InputScope();
  ~InputScope();
  InputScope(const InputScope&) = delete;
  InputScope& operator=(const InputScope&) = delete;

  /// The calling thread's scope, or nullptr.
  static InputScope* current();

  /// Records `path` if it names an existing regular file (links followed).
  void note(const std::filesystem::path& path);

  /// The input (as it was named when noted) that writing `target` would replace, if any.
  std::optional<std::string> replaced_by(const std::filesystem::path& target) const;

 private:
  struct File {
    dev_t device;
    ino_t inode;
    std::string name;
  };
  std::vector<File> files_;
  InputScope* previous_;
};

/// Notes `path` in the calling thread's scope, if there is one.
void note_input(const std::filesystem::path& path);

/// "[FLAG = ]TARGET: it is an input of the command (INPUT) and would be overwritten" if
/// writing `target` would replace an input noted in the calling thread's scope; empty
/// otherwise ("-" and empty targets never do).
std::string input_overwrite_problem(const std::filesystem::path& target,
                                    const std::string& flag = {});

}  // namespace cutdyn::io
