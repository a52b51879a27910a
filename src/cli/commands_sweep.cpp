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
#include "cutdyn/core/error.hpp"

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

// How many variants of `partial` (a stopped run's file) are complete: its header must be this
// sweep's, its rows this sweep's variants in order; the last variant in it may have been cut
// short, and is done again. Truncates the file after the complete ones.
std::size_t resume_from(const std::string& partial, const std::string& header,
                        const std::vector<std::string>& columns,
                        const std::vector<app::LobesVariant>& variants) {
  const auto size = static_cast<std::streamoff>(std::filesystem::file_size(partial));
  std::ifstream in(partial, std::ios::binary);
  std::string line;
  if (!std::getline(in, line) || line != header)
    throw InvalidInput({"--resume: " + partial + " is not this sweep's file (its header differs)"},
                       "command line");
  // Where the reading is: tellg, or the file's size once the last line (maybe cut short,
  // without its line end) is read.
  const auto position = [&] {
    const std::streamoff at = in.tellg();
    return at < 0 ? size : at;
  };
  const std::streamoff header_end = position();
  std::vector<std::streamoff> variant_end;  // where each variant's last row ends
  std::size_t current = 0;
  const auto starts = [&](std::size_t i) {
    return i < variants.size() && line.rfind(lead_text(columns, variants[i]), 0) == 0;
  };
  while (std::getline(in, line)) {
    if (variant_end.empty() ? !starts(0) : !starts(current) && !starts(++current))
      throw InvalidInput({"--resume: " + partial +
                          ": a row that is not the next variant's: " + line.substr(0, 80)},
                         "command line");
    variant_end.resize(current + 1, header_end);
    variant_end[current] = position();
  }
  // Variants before the last one in the file are complete; the last may not be. (With one
  // case and no key varied, the one variant's rows cannot be told apart: it is done again.)
  const std::size_t done = lead_text(columns, variants.front()).empty() ? 0 : current;
  in.close();
  std::filesystem::resize_file(
      partial, static_cast<std::uintmax_t>(done == 0 ? header_end : variant_end[done - 1]));
  return done;
}

// The rows of a variant as the file holds them (no header).
std::string variant_text(const std::vector<std::string>& columns, const app::LobesVariant& variant,
                         const app::LobesRequest& request) {
  std::ostringstream text;
  app::write_csv(text, {columns, app::lobes_variant_rows(columns, variant, request)});
  const std::string s = text.str();
  return s.substr(s.find('\n') + 1);
}

// Appends the variants' rows in the variants' order, whatever order they finish in.
class OrderedWriter {
 public:
  OrderedWriter(const std::string& path, std::size_t start, std::size_t total, std::ostream& err)
      : path_(path),
        file_(path, std::ios::binary | std::ios::app),
        next_(start),
        total_(total),
        err_(err) {
    if (!file_) throw InvalidInput({"--out: cannot write " + path}, "command line");
  }
  void deliver(std::size_t index, std::string text) {
    std::lock_guard<std::mutex> lock(mutex_);
    pending_[index] = std::move(text);
    for (auto it = pending_.find(next_); it != pending_.end(); it = pending_.find(next_)) {
      file_ << it->second << std::flush;
      if (!file_) throw std::runtime_error("--out: cannot write " + path_);
      // A failed variant is one row whose last cell (the error) is not empty.
      const std::string& rows = it->second;
      if (std::count(rows.begin(), rows.end(), '\n') == 1 && rows.size() > 1 &&
          rows[rows.size() - 2] != ',')
        ++failed_;
      pending_.erase(it);
      ++next_;
      err_ << "cutdyn: sweep: " << next_ << "/" << total_ << " variants" << std::endl;
    }
  }
  std::size_t failed() const { return failed_; }
  void close() { file_.close(); }

 private:
  std::mutex mutex_;
  std::string path_;
  std::ofstream file_;
  std::size_t next_, total_, failed_ = 0;
  std::map<std::size_t, std::string> pending_;
  std::ostream& err_;
};

// The order to start the variants in under MPI: the largest first (by speeds × modes), so
// that no long one starts last; equal ones in their own order.
std::vector<std::size_t> largest_first(const std::vector<app::LobesVariant>& variants,
                                       std::size_t start) {
  const auto cost = [&](std::size_t i) {
    const auto& c = variants[i].c;
    return c ? static_cast<double>(c->lobes.rpm_steps) *
                   static_cast<double>(1 + c->modal.modes.size() + c->frfs.size())
             : 0.0;
  };
  std::vector<std::size_t> order;
  for (std::size_t i = start; i < variants.size(); ++i) order.push_back(i);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return cost(a) > cost(b); });
  return order;
}

int run_sweep(const SweepArgs& args, std::ostream& out, std::ostream& err,
              const std::optional<MpiWorld>& world) {
  const bool writer = !world || world->rank == 0;
  Validator v;
  if (args.out.empty()) v.add("--out: missing (where to write the CSV)");
  check_output_folder(v, "--out", args.out);
  v.throw_if_any("command line");
  std::vector<io::Case> cases;
  for (const std::string& path : args.cases) cases.push_back(load_case(path, "", err));
  if (cases.empty()) cases.push_back(load_case("", "milling-insperger", err));
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
  std::size_t start = 0;
  // A finished file resumed: its variants are checked, none is done again but its last.
  if (args.resume && !std::filesystem::exists(partial) && std::filesystem::exists(args.out))
    std::filesystem::rename(args.out, partial);
  if (args.resume && std::filesystem::exists(partial)) {
    start = resume_from(partial, header, columns, variants);
  } else {
    std::ofstream(partial, std::ios::binary | std::ios::trunc) << header << "\n";
  }
  OrderedWriter file(partial, start, variants.size(), err);
  const auto deliver = [&](std::size_t i, std::string text) { file.deliver(i, std::move(text)); };
  if (world && world->size > 1) {
    mpi_share(*world, largest_first(variants, start), compute, deliver);
  } else {
    for (std::size_t i = start; i < variants.size(); ++i) deliver(i, compute(i));
  }
  file.close();
  std::filesystem::rename(partial, args.out);
  out << "cutdyn sweep: " << variants.size() << " variants"
      << (start > 0 ? " (" + std::to_string(start) + " from the stopped run)" : "")
      << (world && world->size > 1 ? ", on " + std::to_string(world->size) + " ranks" : "") << ", "
      << file.failed() << " failed\n  wrote " << args.out << "\n";
  if (file.failed() > 0)
    err << "cutdyn: warning: command line: " << file.failed() << " variants failed: their rows in "
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
      ->check(CLI::Range(0, 1024));
  c->add_flag("--resume", args->resume,
              "go on from OUT.partial, the variants a stopped run finished");
  return [c, args](std::ostream& out, std::ostream& err) -> int {
    if (!c->parsed()) return -1;
    return run_sweep(*args, out, err);
  };
}

}  // namespace cutdyn::cli
