// `cutdyn sweep`: the lobes of every variant of a case (or of many case files) as one long CSV
// (the job is the library's: cutdyn/app/lobes_sweep.hpp). The file grows variant by variant
// in F.csv.partial and becomes F.csv when the sweep is done; `--resume` goes on from the
// variants a stopped run finished.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/sweep_mpi.hpp"
#include "cutdyn/app/lobes_sweep.hpp"
#include "cutdyn/core/detail/parallel.hpp"
#include "cutdyn/core/error.hpp"
#include "cutdyn/io/output.hpp"

namespace cutdyn::cli {
namespace {

struct SweepArgs {
  std::vector<std::string> cases;
  std::vector<std::string> vary;
  std::string method;
  std::string out;
  int threads = 0;
  bool resume = false;
};

// The text a variant's rows start with: its case and values, as the CSV writes them.
std::string lead_text(const std::vector<std::string>& columns, const app::LobesVariant& v) {
  std::vector<std::string> names;
  std::vector<io::CsvCell> cells;
  if (columns.front() == "case") {
    names.push_back("case");
    cells.emplace_back(v.file);
  }
  for (double x : v.values) {
    names.push_back("v" + std::to_string(names.size()));
    cells.emplace_back(x);
  }
  if (cells.empty()) return {};
  std::ostringstream text;
  io::CsvWriter(text, names).row(cells);
  std::string s = text.str();
  s.pop_back();  // the line end
  return s.substr(s.find('\n') + 1) + ",";
}

// The variant of each lead text (variant_of), for reading a partial file back.
class Leads {
 public:
  Leads(const std::vector<std::string>& columns, const std::vector<app::LobesVariant>& variants) {
    for (std::size_t i = 0; i < variants.size(); ++i)
      index_.emplace(lead_text(columns, variants[i]), i);
    cells_ = (columns.front() == "case" ? 1 : 0) + variants.front().values.size();
  }
  /// The variant a row belongs to (its first cells' text), or nullopt.
  std::optional<std::size_t> variant_of(const std::string& row) const {
    if (cells_ == 0) return index_.size() == 1 ? std::optional<std::size_t>(0) : std::nullopt;
    std::size_t at = 0;
    for (std::size_t k = 0; k < cells_; ++k) {  // past k cells, quotes respected
      bool quoted = false;
      while (at < row.size() && (quoted || row[at] != ',')) {
        if (row[at] == '"') quoted = !quoted;
        ++at;
      }
      if (at == row.size()) return std::nullopt;
      ++at;
    }
    const auto it = index_.find(row.substr(0, at));
    return it == index_.end() ? std::nullopt : std::optional<std::size_t>(it->second);
  }

 private:
  std::map<std::string, std::size_t> index_;
  std::size_t cells_ = 0;
};

// The rows of each variant in `partial`, by variant: variants are appended whole, in the order
// they finished; the last one of a stopped run may have been cut short and is left out
// (`keep_last` false). Throws unless the header and every row are this sweep's.
std::map<std::size_t, std::string> read_partial(const std::string& partial,
                                                const std::string& header, const Leads& leads,
                                                bool keep_last) {
  std::ifstream in(partial, std::ios::binary);
  std::string line;
  if (!std::getline(in, line) || line != header)
    throw InvalidInput({"--resume: " + partial + " is not this sweep's file (its header differs)"},
                       "command line");
  std::map<std::size_t, std::string> rows;
  std::optional<std::size_t> last;
  while (std::getline(in, line)) {
    const auto variant = leads.variant_of(line);
    if (!variant || (variant != last && rows.count(*variant)))
      throw InvalidInput(
          {"--resume: " + partial + ": a row that is not this sweep's: " + line.substr(0, 80)},
          "command line");
    rows[*variant] += line + "\n";
    last = variant;
  }
  if (last && !keep_last) rows.erase(*last);
  return rows;
}

// The rows of a variant as the file holds them (no header).
std::string variant_text(const std::vector<std::string>& columns, const app::LobesVariant& variant,
                         const app::LobesRequest& request) {
  std::ostringstream text;
  app::write_csv(text, {columns, app::lobes_variant_rows(columns, variant, request)});
  const std::string s = text.str();
  return s.substr(s.find('\n') + 1);
}

// Appends each variant's rows to the partial file as it finishes (whole, in one write).
class PartialWriter {
 public:
  PartialWriter(const std::string& path, std::size_t done, std::size_t total, std::ostream& err)
      : path_(path),
        file_(path, std::ios::binary | std::ios::app),
        done_(done),
        total_(total),
        err_(err) {
    if (!file_) throw InvalidInput({"--out: cannot write " + path}, "command line");
  }
  void deliver(const std::string& text) {
    std::lock_guard<std::mutex> lock(mutex_);
    file_ << text << std::flush;
    if (!file_) throw std::runtime_error("--out: cannot write " + path_);
    err_ << "cutdyn: sweep: " << ++done_ << "/" << total_ << " variants" << std::endl;
  }
  void close() { file_.close(); }

 private:
  std::mutex mutex_;
  std::string path_;
  std::ofstream file_;
  std::size_t done_, total_;
  std::ostream& err_;
};

// A failed variant is one row whose last cell (the error) is not empty.
bool failed(const std::string& rows) {
  return std::count(rows.begin(), rows.end(), '\n') == 1 && rows.size() > 1 &&
         rows[rows.size() - 2] != ',';
}

// The order to start the variants in under MPI: the largest first (by speeds × modes), so
// that no long one starts last; equal ones in their own order.
std::vector<std::size_t> largest_first(const std::vector<app::LobesVariant>& variants,
                                       std::vector<std::size_t> remaining) {
  const auto cost = [&](std::size_t i) {
    const auto& c = variants[i].c;
    return c ? static_cast<double>(c->lobes.grid.rpm_steps) *
                   static_cast<double>(1 + c->modal.modes.size() + c->frfs.size())
             : 0.0;
  };
  std::stable_sort(remaining.begin(), remaining.end(),
                   [&](std::size_t a, std::size_t b) { return cost(a) > cost(b); });
  return remaining;
}

int run_sweep(const SweepArgs& args, std::ostream& out, std::ostream& err,
              const std::optional<MpiWorld>& world) {
  const bool writer = !world || world->rank == 0;
  Validator v;
  if (args.out.empty()) v.add("--out: missing (where to write the CSV)");
  if (io::standard_stream(args.out) != 0)
    v.add("--out = " + args.out +
          ": a sweep keeps its rows in OUT.partial as it goes (for --resume) and needs a file");
  v.throw_if_any("command line");
  const std::vector<OutputFlag> files{{"--out", args.out},
                                      {"--out (its partial file)", args.out + ".partial"}};
  std::vector<io::Case> cases;
  for (const std::string& path : args.cases) cases.push_back(load_case(path, "", err, files));
  if (cases.empty()) cases.push_back(load_case("", "milling-insperger", err, files));
  std::vector<app::Sweep> vary;
  for (const std::string& spec : args.vary)
    vary.push_back(app::parse_sweep(spec, "--vary", "command line"));
  const auto variants = app::lobes_variants(cases, vary, "command line");
  const auto columns = app::lobes_sweep_columns(cases, vary);
  std::string header;
  for (const std::string& c : columns) header += (header.empty() ? "" : ",") + c;

  app::LobesRequest request;
  request.method = args.method;
  request.threads = args.threads;
  // Ranks on one machine share its cores: by default each takes its share.
  if (world && args.threads == 0)
    request.threads = std::max(
        1, static_cast<int>(std::thread::hardware_concurrency()) / std::max(1, world->local_size));
  request.names = flag_names();
  const auto compute = [&](std::size_t i) { return variant_text(columns, variants[i], request); };

  if (!writer) {  // a worker rank: compute what rank 0 hands out
    mpi_share(*world, {}, compute, {});
    return 0;
  }
  const std::string partial = args.out + ".partial";
  const Leads leads(columns, variants);
  // A finished file resumed: read back whole, nothing is done again.
  bool finished = false;
  if (args.resume && !std::filesystem::exists(partial) && std::filesystem::exists(args.out)) {
    std::filesystem::rename(args.out, partial);
    finished = true;
  }
  std::map<std::size_t, std::string> earlier;
  if (args.resume && std::filesystem::exists(partial))
    earlier = read_partial(partial, header, leads, finished);
  {  // the partial file: the header, then the variants kept from a stopped run
    std::ofstream start(partial, std::ios::binary | std::ios::trunc);
    start << header << "\n";
    for (const auto& [i, rows] : earlier) start << rows;
    if (!start) throw InvalidInput({"--out: cannot write " + partial}, "command line");
  }
  std::vector<std::size_t> remaining;
  for (std::size_t i = 0; i < variants.size(); ++i)
    if (!earlier.count(i)) remaining.push_back(i);
  PartialWriter file(partial, earlier.size(), variants.size(), err);
  const auto deliver = [&](std::size_t, std::string text) { file.deliver(text); };
  if (world && world->size > 1) {
    mpi_share(*world, largest_first(variants, remaining), compute, deliver);
  } else {
    for (std::size_t i : remaining) deliver(i, compute(i));
  }
  file.close();
  // The file: the variants in their order, written whole and renamed into place.
  const auto all = read_partial(partial, header, leads, true);
  std::size_t failures = 0;
  {
    io::OutputTransaction outputs;
    std::ostream& final_file = outputs.open(args.out);
    final_file << header << "\n";
    for (const auto& [i, rows] : all) {
      final_file << rows;
      failures += failed(rows) ? 1 : 0;
    }
    outputs.commit();
  }
  std::filesystem::remove(partial);
  out << "cutdyn sweep: " << variants.size() << " variants"
      << (earlier.empty() ? "" : " (" + std::to_string(earlier.size()) + " from the stopped run)")
      << (world && world->size > 1 ? ", on " + std::to_string(world->size) + " ranks" : "") << ", "
      << failures << " failed\n  wrote " << args.out << "\n";
  if (failures > 0)
    err << "cutdyn: warning: command line: " << failures << " variants failed: their rows in "
        << args.out << " carry the error\n";
  return 0;
}

// Under mpirun, every rank runs the sweep; only rank 0 speaks and writes. MPI ends however
// the sweep ends.
int run_sweep(const SweepArgs& args, std::ostream& out, std::ostream& err) {
  const std::optional<MpiWorld> world = mpi_start();
  struct Finish {
    ~Finish() { mpi_finish(); }
  } finish;
  std::ostream silent(nullptr);
  const bool quiet = world && world->rank != 0;
  return run_sweep(args, quiet ? silent : out, quiet ? silent : err, world);
}

}  // namespace

std::function<int(std::ostream&, std::ostream&)> add_sweep_command(CLI::App& app) {
  auto args = std::make_shared<SweepArgs>();
  auto* c = app.add_subcommand(
      "sweep", "the lobes of every variant of a case, or of many case files, as one CSV");
  c->add_option("CASES", args->cases,
                "case files (TOML) or built-in examples' names (default milling-insperger)");
  c->add_option("--vary", args->vary,
                "a case key over values, KEY=FROM:STEP:TO (e.g. modes[0].damping_ratio="
                "0.01:0.01:0.05); repeat for every combination, the last varying fastest");
  c->add_option("--method", args->method, "stability method (default: each case's [lobes])");
  c->add_option("--out", args->out, "write the CSV: the varied keys, then the lobes' columns")
      ->required();
  c->add_option("--threads", args->threads, "threads for each variant's lobes (default: all)")
      ->check(CLI::Range(0, kMaxThreads));
  c->add_flag("--resume", args->resume,
              "go on from OUT.partial, the variants a stopped run finished");
  return [c, args](std::ostream& out, std::ostream& err) -> int {
    if (!c->parsed()) return -1;
    return run_sweep(*args, out, err);
  };
}

}  // namespace cutdyn::cli
