// Writes the fuzz targets' seed corpora and the case dictionaries (docs/fuzzing.md) from the
// repository's own examples and test data, so that no corpus is kept in git:
//   make_seeds SOURCE_DIR OUT_DIR
// OUT_DIR/seeds/<target>/ gets one file per seed, OUT_DIR/dicts/ the dictionaries of the case
// keys (TOML and JSON spellings) made from io::case_schema(). Small hand-made seeds and the
// other dictionaries are in fuzz/seeds/ and fuzz/*.dict.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cutdyn/io/case_file.hpp"
#include "cutdyn/io/frf_file.hpp"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_file(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

// The files in `dir` whose names end with `suffix`, sorted.
std::vector<fs::path> files(const fs::path& dir, const std::string& suffix) {
  std::vector<fs::path> out;
  if (!fs::is_directory(dir)) return out;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (e.is_regular_file() && name.size() >= suffix.size() &&
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
      out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

// The first `n` lines of a text.
std::string first_lines(const std::string& text, int n) {
  std::size_t at = 0;
  for (int i = 0; i < n && at != std::string::npos; ++i) {
    at = text.find('\n', at);
    if (at != std::string::npos) ++at;
  }
  return at == std::string::npos ? text : text.substr(0, at);
}

// A JSON file on one line.
std::string compact(const std::string& text) { return json::parse(text).dump(); }

// A dictionary entry: the text quoted and escaped as libFuzzer's -dict files take it.
std::string entry(const std::string& text) {
  std::string out = "\"";
  for (const unsigned char ch : text) {
    if (ch == '"' || ch == '\\') {
      out += '\\';
      out += static_cast<char>(ch);
    } else if (ch < 0x20 || ch >= 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02X", ch);
      out += hex;
    } else {
      out += static_cast<char>(ch);
    }
  }
  return out + "\"";
}

void write_dicts(const fs::path& out) {
  std::set<std::string> toml, js;
  const json schema = cutdyn::io::case_schema();
  for (auto t = schema.begin(); t != schema.end(); ++t) {
    std::string table = t.key();
    if (const auto space = table.find(' '); space != std::string::npos) table.resize(space);
    const bool top = table == "(top" || table.empty();
    if (!top) {
      const bool array = t.value().value("array", false);
      toml.insert(array ? "[[" + table + "]]" : "[" + table + "]");
      toml.insert(table);
      js.insert("\"" + table + "\"");
    }
    if (!t.value().contains("keys")) continue;
    for (auto k = t.value()["keys"].begin(); k != t.value()["keys"].end(); ++k) {
      toml.insert(k.key() + " = ");
      js.insert("\"" + k.key() + "\":");
      if (k.value().contains("choices") && k.value()["choices"].is_array())
        for (const json& c : k.value()["choices"])
          if (c.is_string()) {
            toml.insert("\"" + c.get<std::string>() + "\"");
            js.insert("\"" + c.get<std::string>() + "\"");
          }
    }
  }
  for (const char* s : {"true", "false", "1e308", "-0.0", "nan", "inf", "\"\"", "[]", "{}"}) {
    toml.insert(s);
    js.insert(s);
  }
  for (const char* s : {"null", "[{}]", "[[]]"}) js.insert(s);
  for (const char* s : {"\n[", "]\n", "= [", "= {", "'''", "\"\"\"", "0x", "1979-05-27"})
    toml.insert(s);
  std::string t, j;
  for (const std::string& s : toml) t += entry(s) + "\n";
  for (const std::string& s : js) j += entry(s) + "\n";
  write_file(out / "dicts" / "case_toml.dict", t);
  write_file(out / "dicts" / "case_json.dict", j);
}

// The first `n` points of an FRF.
cutdyn::MeasuredFrf head(const cutdyn::MeasuredFrf& frf, std::size_t n) {
  cutdyn::MeasuredFrf out;
  n = std::min(n, frf.frequency_hz.size());
  out.frequency_hz.assign(frf.frequency_hz.begin(), frf.frequency_hz.begin() + n);
  out.receptance_m_per_n.assign(frf.receptance_m_per_n.begin(), frf.receptance_m_per_n.begin() + n);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: make_seeds SOURCE_DIR OUT_DIR\n");
    return 2;
  }
  const fs::path source = argv[1], out = argv[2];
  const fs::path seeds = out / "seeds";
  fs::remove_all(seeds);
  int count = 0;
  const auto seed = [&](const std::string& target, const std::string& name,
                        const std::string& text) {
    write_file(seeds / target / name, text);
    ++count;
  };

  // Case files: every example as TOML, as JSON (its effective case) and as the API's requests.
  for (const fs::path& p : files(source / "examples", ".toml"))
    seed("case_toml", p.filename().string(), read_file(p));
  for (const fs::path& p : files(source / "examples" / "frf", ".toml"))
    seed("case_toml", p.filename().string(), read_file(p));
  const std::string queries[] = {"", "method=zero-order&format=csv", "rpm=2000&depth_mm=1",
                                 "rpm=2000&depth_mm=0.5&duration_s=0.05&points=50"};
  for (const auto& [name, text] : cutdyn::io::examples()) {
    const json c = cutdyn::io::to_json(cutdyn::io::load_example(name));
    const std::string doc = c.dump();
    seed("case_json", std::string(name) + ".json", doc);
    for (char path = 0; path < 4; ++path)
      seed("api", std::string(name) + "-" + std::to_string(path),
           std::string(1, path) + queries[static_cast<int>(path)] + "\n" + doc);
  }

  // FRF files: each example file's first points in every format and variant the writer has,
  // behind the target's option byte (0: format detected, no hint).
  for (const fs::path& p : files(source / "examples" / "frf", ".uff")) {
    const cutdyn::MeasuredFrf frf = head(cutdyn::read_frf(p), 12);
    const std::string stem = p.stem().string();
    seed("frf", stem + ".frf",
         std::string(1, '\0') + cutdyn::format_frf(frf, cutdyn::FrfFormat::kCutPro).text);
    seed("frf", stem + ".csv",
         std::string(1, '\0') + cutdyn::format_frf(frf, cutdyn::FrfFormat::kCsv).text);
    cutdyn::FrfWriteOptions o;
    seed("frf", stem + ".uff",
         std::string(1, '\0') + format_frf(frf, cutdyn::FrfFormat::kUff, o).text);
    o.uff_single_precision = true;
    o.uff_spacing = cutdyn::UffSpacing::kUneven;
    seed("frf", stem + "-single-uneven.uff",
         std::string(1, '\0') + format_frf(frf, cutdyn::FrfFormat::kUff, o).text);
    o = {};
    o.uff_binary = true;
    seed("frf", stem + "-58b.uff",
         std::string(1, '\0') + format_frf(frf, cutdyn::FrfFormat::kUff, o).text);
  }

  // Force files: the examples' mean forces and the monitor's estimates in the golden files.
  for (const fs::path& p : files(source / "examples" / "forces", ".csv"))
    seed("force_file", p.filename().string(), read_file(p));
  for (const fs::path& p : files(source / "tests" / "golden", ".e.csv"))
    seed("force_file", p.filename().string(), first_lines(read_file(p), 40));

  // The monitor's calibration and band files written by the golden runs.
  for (const fs::path& p : files(source / "tests" / "golden", ".calib.json"))
    seed("calibration", p.filename().string(), compact(read_file(p)));
  for (const fs::path& p : files(source / "tests" / "golden", ".band.json"))
    seed("band", p.filename().string(), compact(read_file(p)));

  // The hand-made seeds.
  if (fs::is_directory(source / "fuzz" / "seeds"))
    for (const auto& dir : fs::directory_iterator(source / "fuzz" / "seeds"))
      for (const fs::path& p : files(dir.path(), ""))
        seed(dir.path().filename().string(), p.filename().string(), read_file(p));

  write_dicts(out);
  std::printf("make_seeds: %d seeds in %s\n", count, seeds.string().c_str());
  return 0;
}
