// docs/case-files.md shows one key table per case section, generated from the field tables
// (src/io/case_fields.hpp) between `<!-- keys: NAME -->` and `<!-- end keys -->`; the prose
// around them is written by hand. A table that differs fails with the lines that differ;
// CUTDYN_UPDATE_DOCS=1 writes the generated tables into the doc instead.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "io/case_fields.hpp"

namespace cutdyn::io {
namespace {

const std::string kDoc = std::string(CUTDYN_SOURCE_DIR) + "/docs/case-files.md";
constexpr std::string_view kEnd = "<!-- end keys -->";

std::string marker_name(const detail::Section& s) {
  if (s.name.empty()) return "top";
  return (s.plan ? "plan " : "") + std::string(s.name);
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// The lines that differ, "- doc" and "+ table", for the failure message.
std::string diff(const std::string& doc, const std::string& table) {
  const auto a = lines_of(doc), b = lines_of(table);
  std::string out;
  for (std::size_t i = 0; i < std::max(a.size(), b.size()); ++i) {
    const std::string x = i < a.size() ? a[i] : "(none)", y = i < b.size() ? b[i] : "(none)";
    if (x != y) out += "  line " + std::to_string(i + 1) + ":\n  - " + x + "\n  + " + y + "\n";
  }
  return out;
}

TEST(CaseFileDoc, KeyTablesAreTheFieldTables) {
  std::ifstream in(kDoc);
  ASSERT_TRUE(in) << kDoc;
  std::stringstream buffer;
  buffer << in.rdbuf();
  std::string text = buffer.str();
  const bool update = std::getenv("CUTDYN_UPDATE_DOCS") != nullptr;
  for (const detail::Section& s : detail::case_sections()) {
    const std::string begin = "<!-- keys: " + marker_name(s) + " -->\n";
    const auto at = text.find(begin);
    if (at == std::string::npos) {
      ADD_FAILURE() << kDoc << " has no " << begin << "(the key table of [" << s.name << "])";
      continue;
    }
    const auto from = at + begin.size();
    const auto to = text.find(kEnd, from);
    ASSERT_NE(to, std::string::npos) << "no " << kEnd << " after " << begin;
    const std::string table = detail::key_table_markdown(s);
    if (update) {
      text.replace(from, to - from, table);
    } else {
      EXPECT_EQ(text.substr(from, to - from), table)
          << "the key table of [" << s.name << "] in " << kDoc
          << " differs from the field table (CUTDYN_UPDATE_DOCS=1 rewrites it):\n"
          << diff(text.substr(from, to - from), table);
    }
  }
  if (update) std::ofstream(kDoc, std::ios::binary) << text;
}

}  // namespace
}  // namespace cutdyn::io
