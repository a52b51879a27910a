// For the targets whose reader takes a path: the input written to a file of this process (in
// /dev/shm when there is one, so that no disk is written).
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace cutdyn::fuzz {

/// The path of this process' input file, with `extension`; removed when the process exits.
inline const std::string& input_path(const char* extension) {
  struct File {
    std::string path;
    ~File() { std::remove(path.c_str()); }
  };
  static const File file{[&] {
    const std::filesystem::path dir = std::filesystem::is_directory("/dev/shm")
                                          ? std::filesystem::path("/dev/shm")
                                          : std::filesystem::temp_directory_path();
    return (dir / ("cutdyn-fuzz-" + std::to_string(::getpid()) + extension)).string();
  }()};
  return file.path;
}

/// Writes the input to input_path(extension) and returns that path.
inline const std::string& write_input(const std::uint8_t* data, std::size_t size,
                                      const char* extension) {
  const std::string& path = input_path(extension);
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) {
    std::perror(path.c_str());
    std::abort();
  }
  if (size > 0) std::fwrite(data, 1, size, f);
  std::fclose(f);
  return path;
}

}  // namespace cutdyn::fuzz
