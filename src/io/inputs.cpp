#include "cutdyn/io/inputs.hpp"

#include <sys/stat.h>

#include <algorithm>

namespace cutdyn::io {
namespace {

thread_local InputScope* current_scope = nullptr;

// The identity of an existing regular file (links followed).
std::optional<std::pair<dev_t, ino_t>> regular_file_identity(const std::filesystem::path& path) {
  struct stat s {};
  if (path.empty() || ::stat(path.c_str(), &s) != 0 || !S_ISREG(s.st_mode)) return std::nullopt;
  return std::pair{s.st_dev, s.st_ino};
}

}  // namespace

InputScope::InputScope() : previous_(current_scope) { current_scope = this; }

InputScope::~InputScope() { current_scope = previous_; }

InputScope* InputScope::current() { return current_scope; }

void InputScope::note(const std::filesystem::path& path) {
  const auto id = regular_file_identity(path);
  if (!id) return;
  const bool known = std::any_of(files_.begin(), files_.end(), [&](const File& f) {
    return f.device == id->first && f.inode == id->second;
  });
  if (!known) files_.push_back(File{id->first, id->second, path.string()});
}

std::optional<std::string> InputScope::replaced_by(const std::filesystem::path& target) const {
  if (target.empty() || target == "-") return std::nullopt;
  const auto id = regular_file_identity(target);
  if (!id) return std::nullopt;
  for (const File& f : files_)
    if (f.device == id->first && f.inode == id->second) return f.name;
  return std::nullopt;
}

void note_input(const std::filesystem::path& path) {
  if (current_scope) current_scope->note(path);
}

std::string input_overwrite_problem(const std::filesystem::path& target, const std::string& flag) {
  if (!current_scope) return {};
  const auto input = current_scope->replaced_by(target);
  if (!input) return {};
  return (flag.empty() ? "" : flag + " = ") + target.string() +
         ": it is an input of the command (" + *input + ") and would be overwritten";
}

}  // namespace cutdyn::io
