// The repository cites only what is in it: no note kept outside it, no tracker numbers, and
// every published source by a key of docs/bibliography.md. Fails naming each file and line.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
const fs::path kRoot = CUTDYN_SOURCE_DIR;

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The repository's own text files: the top-level files and everything under the source
// folders, without tests/golden (program output) and this file (it spells the patterns).
std::vector<fs::path> repository_files() {
  static const std::set<std::string> kExtensions = {".cpp",   ".hpp", ".h",  ".md", ".toml",
                                                    ".cmake", ".txt", ".py", ".in", ".json"};
  const auto wanted = [](const fs::path& p) {
    const std::string name = p.filename().string();
    return kExtensions.count(p.extension().string()) > 0 || name == "run";
  };
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(kRoot))
    if (e.is_regular_file() && wanted(e.path())) files.push_back(e.path());
  for (const char* dir : {"src", "include", "tests", "docs", "examples", "bench", "cmake", ".ci"}) {
    if (!fs::is_directory(kRoot / dir)) continue;
    for (const auto& e : fs::recursive_directory_iterator(kRoot / dir)) {
      const fs::path rel = fs::relative(e.path(), kRoot);
      if (!e.is_regular_file() || !wanted(e.path())) continue;
      if (rel.generic_string().rfind("tests/golden/", 0) == 0) continue;
      if (rel.generic_string() == "tests/docs/references_test.cpp") continue;
      files.push_back(e.path());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

// Every line of every file that matches, as "path:line: text".
std::vector<std::string> lines_matching(const std::regex& re) {
  std::vector<std::string> hits;
  for (const fs::path& f : repository_files()) {
    std::istringstream in(read(f));
    int n = 0;
    for (std::string line; std::getline(in, line);) {
      ++n;
      if (std::regex_search(line, re))
        hits.push_back(fs::relative(f, kRoot).generic_string() + ":" + std::to_string(n) + ": " +
                       line);
    }
  }
  return hits;
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += "  " + x + "\n";
  return s;
}

TEST(Docs, CiteNothingOutsideTheRepository) {
  // Shared notes kept beside the repository and a tracker's numbers cannot be followed by a
  // reader of it: state the rule, or point to docs/ or a bibliography key, instead. (The names
  // are spelled in pieces so that this file does not match itself.)
  const std::string pattern = std::string("(models|product|archi") + "tecture)\\.md" + "|docs/" +
                              "archi" + "tecture\\b" + "|\\bissues?\\s+#?[0-9]+";
  const auto hits = lines_matching(std::regex(pattern, std::regex::icase));
  EXPECT_TRUE(hits.empty()) << "references to texts outside the repository:\n" << joined(hits);
}

// The keys cited in brackets: "[Ermolaev2020]", "[Zheng2012, eq. 4]", "[Oxley1989; Lalwani2009]".
std::set<std::string> cited_keys(const std::string& text) {
  static const std::regex group(R"(\[([^\[\]\n]*)\])");
  static const std::regex key(R"(\b[A-Z][a-z]+(?:[A-Z][a-z]+)*[0-9]{4}[a-z]?\b)");
  std::set<std::string> keys;
  for (auto g = std::sregex_iterator(text.begin(), text.end(), group); g != std::sregex_iterator();
       ++g) {
    const std::string inside = (*g)[1].str();
    for (auto k = std::sregex_iterator(inside.begin(), inside.end(), key);
         k != std::sregex_iterator(); ++k)
      keys.insert(k->str());
  }
  return keys;
}

TEST(Docs, EveryCitedKeyIsInTheBibliography) {
  const std::string bibliography = read(kRoot / "docs" / "bibliography.md");
  ASSERT_FALSE(bibliography.empty()) << "docs/bibliography.md is missing";
  // An entry is a list item that starts with its key in bold: "* **[Ermolaev2020]** …".
  std::set<std::string> entries;
  static const std::regex entry(R"((^|\n)\* \*\*\[([A-Za-z]+[0-9]{4}[a-z]?)\]\*\*)");
  for (auto e = std::sregex_iterator(bibliography.begin(), bibliography.end(), entry);
       e != std::sregex_iterator(); ++e)
    EXPECT_TRUE(entries.insert((*e)[2].str()).second) << "two entries for " << (*e)[2].str();
  ASSERT_GE(entries.size(), 4u);

  std::vector<std::string> missing;
  std::set<std::string> cited;
  for (const fs::path& f : repository_files()) {
    for (const std::string& k : cited_keys(read(f))) {
      cited.insert(k);
      if (!entries.count(k)) missing.push_back(fs::relative(f, kRoot).generic_string() + ": " + k);
    }
  }
  EXPECT_TRUE(missing.empty()) << "cited keys without an entry in docs/bibliography.md:\n"
                               << joined(missing);
  // The four sources of the models are cited where they are used.
  for (const char* k : {"Ermolaev2020", "Zenkin2012", "Zheng2012", "Chikishev2018"})
    EXPECT_TRUE(cited.count(k)) << k;
}

TEST(Docs, CitationKeysAreFoundInTheirForms) {
  EXPECT_EQ(cited_keys("see [Zheng2012, eq. 4] and [Oxley1989; AdibiSedeh2003]"),
            (std::set<std::string>{"AdibiSedeh2003", "Oxley1989", "Zheng2012"}));
  EXPECT_TRUE(cited_keys("[material] [[modes]] [0, 2π) [AISI1045] kZheng2012Preset").empty());
}

}  // namespace
