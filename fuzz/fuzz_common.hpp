// Shared by the libFuzzer targets (docs/fuzzing.md). Each target hands the bytes to one reader
// of outside input and swallows only what that reader documents for bad input:
// cutdyn::InvalidInput. Any other exception escapes LLVMFuzzerTestOneInput and ends the run
// (std::terminate), as a crash, a sanitizer report or a hang does: each is a finding.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "cutdyn/core/error.hpp"

namespace cutdyn::fuzz {

inline std::string_view text_of(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

/// Runs `read`; an InvalidInput it throws is the documented answer to bad input.
template <typename F>
void expect_invalid_input_only(F&& read) {
  try {
    read();
  } catch (const InvalidInput&) {
  }
}

/// A broken promise of the code under test (not an exception it may throw): reported as a
/// crash with `what`.
[[noreturn]] inline void fail(const char* what) {
  std::fprintf(stderr, "cutdyn fuzz: %s\n", what);
  std::abort();
}

}  // namespace cutdyn::fuzz
