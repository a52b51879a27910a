// The cost of calling `lobes` from Python: `cutdyn.lobes(case)` against the C++ call it wraps,
// `app::run_lobes(case, request)` with the same method and threads, on the case `cutdyn lobes`
// runs without one (the example turning-ultrasonic, the CLI's default; 1 thread, and
// milling-insperger, as further comparisons) — each side in a process of its own, as a C++
// program and a Python program run it — and where the difference goes: the steps of the
// module's `lobes` (src/python/module.cpp) timed one by one. The requirement: the Python call
// costs no more than 5 % over the C++ call on the default case. docs/benchmarks.md.
//
// The comparison runs two child processes per round, the order alternating from round to round:
//   * the C++ child: this program re-run as `bench_python_lobes --cpp-child CASE THREADS CALLS`,
//     which reads the case once (io::load_example) and times CALLS calls of app::run_lobes on
//     its main thread, as a C++ program makes them;
//   * the Python child: `python3 -c SCRIPT DIR CASE THREADS CALLS`, which imports cutdyn from
//     the build tree, makes the case once (cutdyn.example) and times CALLS calls of
//     cutdyn.lobes(case) (threads=… unless all cores, the default).
// Each child prints the result's speeds and method, then one duration per call; the first call
// of each child (it starts the OpenMP team, and in Python the module's worker thread) is dropped.
// Each process has one OpenMP team, kept between its calls: in one process the module's worker
// thread and the calling thread each keep a team, which libgomp counts together (more threads
// than cores) and which then slow each other down — a state neither program is in.
#include <pybind11/embed.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "bench_support.hpp"
#include "cutdyn/app/render.hpp"
#include "cutdyn/app/report_json.hpp"
#include "cutdyn/app/stability.hpp"
#include "cutdyn/io/case_file.hpp"
#include "python/common.hpp"  // the module's own conversions and worker thread

extern char** environ;

namespace cutdyn {
namespace {

using namespace bench;
namespace py = pybind11;

// range(0) of the benchmarks: which case.
const char* const kCases[] = {
    "turning-ultrasonic",  // `cutdyn lobes` without a case (src/cli/commands_turning.cpp)
    "milling-insperger",
};
constexpr int kDefaultCase = 0;
constexpr int kRounds = 12;        // rounds of one C++ and one Python child, order alternating
constexpr int kCallsPerChild = 6;  // calls each child times; its first is dropped (warm-up)
constexpr double kRequirement = 0.05;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The quartile q (0.25, 0.75) of v, linearly interpolated.
double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  const double at = q * static_cast<double>(v.size() - 1);
  const auto i = static_cast<std::size_t>(at);
  if (i + 1 >= v.size()) return v.back();
  return v[i] + (at - static_cast<double>(i)) * (v[i + 1] - v[i]);
}

// The C++ call: the job the module's `lobes` runs, with the method of the case's [lobes] (as
// `cutdyn.lobes(case)`) and the same threads (0 = all cores).
app::LobesJobReport cpp_lobes(const io::Case& c, int threads) {
  app::LobesRequest request;
  request.threads = threads;
  return app::run_lobes(c, request);
}

// ---- the children ---------------------------------------------------------------------------

// The C++ child (`--cpp-child CASE THREADS CALLS`): what a C++ program does, on its main thread,
// no interpreter. The report is released inside the timing, as Python's result is.
int cpp_child(const char* name, int threads, int calls) {
  const io::Case c = io::load_example(name);
  std::vector<double> seconds;
  for (int i = 0; i < calls; ++i) {
    const auto start = Clock::now();
    {
      const app::LobesJobReport report = cpp_lobes(c, threads);
      if (i == 0)
        std::printf("# speeds %zu method %s\n", report.lobes.points.size(), report.method.c_str());
    }
    seconds.push_back(seconds_since(start));
  }
  for (const double s : seconds) std::printf("%.9f\n", s);
  return 0;
}

// The Python child: a Python program calling cutdyn.lobes(case) as a user writes it; its result
// released inside the timing (the expression's value is dropped at once), except the first
// call's, kept to report its speeds and method (that call is dropped as warm-up anyway).
constexpr const char* kPythonChild = R"(import sys, time
sys.path.insert(0, sys.argv[1])
import cutdyn
name, threads, calls = sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
case = cutdyn.example(name)
lobes, clock = cutdyn.lobes, time.perf_counter
seconds = []
start = clock()
first = lobes(case) if threads == 0 else lobes(case, threads=threads)
seconds.append(clock() - start)
print("# speeds", len(first.spindle_rpm), "method", first.method)
del first
for _ in range(calls - 1):
    if threads == 0:
        start = clock()
        lobes(case)
        seconds.append(clock() - start)
    else:
        start = clock()
        lobes(case, threads=threads)
        seconds.append(clock() - start)
print("\n".join("%.9f" % s for s in seconds))
)";

// Runs `args` (args[0] a path), its stdout captured, stderr passed through; throws unless it
// exits with 0. The parent only waits on the pipe meanwhile.
std::string run_child(const std::vector<std::string>& args) {
  int fds[2];
  if (pipe(fds) != 0) throw std::runtime_error("pipe failed");
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_addclose(&actions, fds[0]);
  posix_spawn_file_actions_addclose(&actions, fds[1]);
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, args[0].c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(fds[1]);
  std::string out;
  char buf[4096];
  for (ssize_t n; (n = read(fds[0], buf, sizeof buf)) != 0;) {
    if (n < 0) {
      if (errno == EINTR) continue;
      break;
    }
    out.append(buf, static_cast<std::size_t>(n));
  }
  close(fds[0]);
  if (spawned != 0) throw std::runtime_error("cannot start " + args[0] + ": " + strerror(spawned));
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw std::runtime_error(args[0] + " failed; its output:\n" + out);
  return out;
}

// One child's report: the result's speeds and method, the durations of its calls after the
// first.
struct ChildRun {
  std::size_t speeds = 0;
  std::string method;
  std::vector<double> seconds;
};

ChildRun parse_child(const std::string& out) {
  ChildRun run;
  std::istringstream in(out);
  std::string line;
  bool first = true;
  while (std::getline(in, line)) {
    if (line.rfind("# speeds ", 0) == 0) {
      std::istringstream words(line.substr(2));
      std::string w;
      words >> w >> run.speeds >> w >> run.method;
    } else if (!line.empty()) {
      if (!first) run.seconds.push_back(std::stod(line));
      first = false;
    }
  }
  if (run.seconds.empty()) throw std::runtime_error("a child printed no durations:\n" + out);
  return run;
}

ChildRun cpp_run(int index, int threads) {
  return parse_child(
      run_child({std::filesystem::read_symlink("/proc/self/exe").string(), "--cpp-child",
                 kCases[index], std::to_string(threads), std::to_string(kCallsPerChild)}));
}

ChildRun python_run(int index, int threads) {
  return parse_child(
      run_child({CUTDYN_PYTHON_EXECUTABLE, "-c", kPythonChild, CUTDYN_PYTHON_DIR, kCases[index],
                 std::to_string(threads), std::to_string(kCallsPerChild)}));
}

// The machine's load average over the last minute (what `uptime` shows first); these
// processes add up to one or two (the threads) to it while they run.
double load_average() {
  double load[1] = {-1.0};
  return getloadavg(load, 1) == 1 ? load[0] : -1.0;
}

std::string case_key(const std::string& prefix, int index, int threads) {
  return prefix + "/" + kCases[index] + (threads == 1 ? "/1" : "/all");
}

// ---- 1. the comparison: a C++ and a Python process per round --------------------------------

// kRounds rounds of one C++ child and one Python child, the order alternating, so that a slow
// stretch of a shared machine falls on both sides alike: the medians and minima of each side's
// calls, and the median and quartiles of the rounds' own ratios (the median Python call of the
// round over its median C++ call).
void BM_LobesProcesses(benchmark::State& state) {
  const int index = static_cast<int>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  std::vector<double> cpp, python, ratios;
  std::size_t speeds = 0;
  bool same = true;
  const double load_before = load_average();
  const auto rounds = [&] {
    cpp.clear();
    python.clear();
    ratios.clear();
    for (int round = 0; round < kRounds; ++round) {
      ChildRun a, b;
      if (round % 2 == 0) {
        a = cpp_run(index, threads);
        b = python_run(index, threads);
      } else {
        b = python_run(index, threads);
        a = cpp_run(index, threads);
      }
      // Same result on both sides: the same speeds, the same method.
      same = same && a.speeds == b.speeds && a.method == b.method && a.speeds > 0;
      speeds = a.speeds;
      cpp.insert(cpp.end(), a.seconds.begin(), a.seconds.end());
      python.insert(python.end(), b.seconds.begin(), b.seconds.end());
      ratios.push_back(median(b.seconds) / median(a.seconds));
    }
  };
  Result* timing = nullptr;
  try {
    timing = &timed(state, case_key("processes", index, threads), rounds);
  } catch (const std::exception& e) {  // a child that did not start or failed
    state.SkipWithError(e.what());
    return;
  }
  Result& r = *timing;
  r.figures["cpp_median"] = median(cpp);
  r.figures["py_median"] = median(python);
  r.figures["cpp_min"] = *std::min_element(cpp.begin(), cpp.end());
  r.figures["py_min"] = *std::min_element(python.begin(), python.end());
  r.figures["paired_ratio"] = median(ratios);
  r.figures["paired_q1"] = quantile(ratios, 0.25);
  r.figures["paired_q3"] = quantile(ratios, 0.75);
  r.figures["calls"] = static_cast<double>(cpp.size());
  r.figures["speeds"] = static_cast<double>(speeds);
  state.counters["cpp_ms"] = 1e3 * r.figures["cpp_median"];
  state.counters["py_ms"] = 1e3 * r.figures["py_median"];
  state.counters["paired_overhead_pct"] = 1e2 * (r.figures["paired_ratio"] - 1.0);
  state.counters["speeds"] = static_cast<double>(speeds);
  r.figures["load_before"] = load_before;
  r.figures["load_after"] = load_average();
  if (!same) state.SkipWithError("the Python result differs from the C++ report");
}

// ---- 2. where the difference goes: the steps of the module's `lobes` ------------------------

// Each step as src/python/module.cpp runs it after (or around) app::run_lobes, with the
// module's own helpers (src/python/common.cpp, compiled into this program), on the report of the
// default case, all threads, in this (the parent) process. The median over batches of the time
// per call. None of them runs an OpenMP region but the one report made beforehand.
struct Step {
  enum Kind { kThread, kConversion, kBefore };
  std::string what;
  double seconds = 0.0;
  Kind kind = kConversion;
};
std::vector<Step> g_steps;

template <typename Body>
double per_call(int calls, Body body, int batches = 7) {
  std::vector<double> t;
  for (int b = 0; b < batches; ++b) {
    const auto start = Clock::now();
    for (int i = 0; i < calls; ++i) body();
    t.push_back(seconds_since(start) / calls);
  }
  return median(t);
}

void BM_PythonSteps(benchmark::State& state) {
  const py::module_ cutdyn = py::module_::import("cutdyn");
  const io::Case c = io::load_example(kCases[kDefaultCase]);
  const app::LobesJobReport report = cpp_lobes(c, 0);
  std::vector<Step> steps;
  Result& r = timed(state, "steps", [&] {
    steps.clear();
    // The worker thread: a job that does nothing, run as the module runs every job (GIL
    // released, handed to a kept worker thread, the calling thread waiting and polling for
    // Ctrl-C every 50 ms).
    steps.push_back(
        {"kept worker thread + GIL release (empty job)",
         per_call(
             200,
             [] { python::run_interruptible<int>([](const std::atomic<bool>&) { return 0; }); }),
         Step::kThread});
    app::ReportTable table;
    steps.push_back({"app::lobes_table (report -> rows of cells)",
                     per_call(20, [&] { table = app::lobes_table(report); })});
    steps.push_back({"columns_of (rows -> numpy arrays)",
                     per_call(20, [&] { benchmark::DoNotOptimize(python::columns_of(table)); })});
    nlohmann::json json;
    steps.push_back({"app::to_json (report -> nlohmann::json)",
                     per_call(5, [&] { json = app::to_json(c, report); })});
    steps.push_back({"to_python (nlohmann::json -> Python dict)",
                     per_call(5, [&] { benchmark::DoNotOptimize(python::to_python(json)); })});
    steps.push_back({"text_of (the text `cutdyn lobes` prints)",
                     per_call(20, [&] { benchmark::DoNotOptimize(python::text_of(c, report)); })});
    // The Python side: cutdyn.Lobes(native) over the dict the native part returns.
    py::dict native;
    native["columns"] = python::columns_of(table);
    native["report"] = python::to_python(json);
    native["text"] = python::text_of(c, report);
    const py::object wrapper = cutdyn.attr("Lobes");
    steps.push_back(
        {"cutdyn.Lobes(...) (the Python result object)", per_call(200, [&] { wrapper(native); })});
    // What the module did before (86096ef): the report through JSON text and json.loads. The
    // same dict (the default case's report holds no NaN, which the text would turn to None).
    const py::object loads = py::module_::import("json").attr("loads");
    steps.push_back({"json.dump() + json.loads (the module before 86096ef)",
                     per_call(5, [&] { loads(json.dump()); }), Step::kBefore});
    if (!loads(json.dump()).equal(python::to_python(json)))
      state.SkipWithError("to_python differs from json.loads of the JSON text");
  });
  double sum = 0.0;
  for (const Step& step : steps)
    if (step.kind != Step::kBefore) sum += step.seconds;
  r.figures["steps"] = sum;
  state.counters["steps_ms"] = 1e3 * sum;
  g_steps = steps;
}

constexpr auto kMs = benchmark::kMillisecond;

// Args: {case, threads}; threads 0 = all cores (the Python default), 1 = one.
BENCHMARK(BM_LobesProcesses)
    ->ArgNames({"case", "threads"})
    ->Args({kDefaultCase, 0})
    ->Args({kDefaultCase, 1})
    ->Args({1, 0})
    ->Iterations(1)
    ->Unit(kMs)
    ->UseRealTime();
BENCHMARK(BM_PythonSteps)->Iterations(1)->Unit(kMs)->UseRealTime();

// ---- summary ---------------------------------------------------------------------------

void percent_line(const char* what, double ratio, const char* note = "") {
  std::printf("  %-58s %11.3fx  (%+.1f %%)%s\n", what, ratio, 1e2 * (ratio - 1.0), note);
}

// The verdict goes by the median of the rounds' own ratios: each round's two processes run
// back to back and share the machine's load of that moment, which each side's median alone
// does not.
void comparison(int index, int threads) {
  const auto r = result(case_key("processes", index, threads));
  std::printf("\n%s%s, %s, %d rounds of two processes:\n", kCases[index],
              index == kDefaultCase ? " (the default case)" : "",
              threads == 1 ? "1 thread" : "all threads", kRounds);
  if (!r) {
    std::printf("  %-58s (not run)\n", "comparison");
    return;
  }
  const auto& f = r->figures;
  std::printf("  %-58s %12.0f\n", "speeds", f.at("speeds"));
  std::printf("  %-58s %7.2f, %.2f\n", "load average (1 min) before, after", f.at("load_before"),
              f.at("load_after"));
  char what[96];
  std::snprintf(what, sizeof what, "C++ app::run_lobes, median of %.0f calls", f.at("calls"));
  std::printf("  %-58s %12s  (min %s)\n", what, seconds_text(f.at("cpp_median")).c_str(),
              seconds_text(f.at("cpp_min")).c_str());
  std::snprintf(what, sizeof what, "Python cutdyn.lobes(case), median of %.0f calls",
                f.at("calls"));
  std::printf("  %-58s %12s  (min %s)\n", what, seconds_text(f.at("py_median")).c_str(),
              seconds_text(f.at("py_min")).c_str());
  char iqr[64];
  std::snprintf(iqr, sizeof iqr, ", quartiles %+.1f..%+.1f %%", 1e2 * (f.at("paired_q1") - 1.0),
                1e2 * (f.at("paired_q3") - 1.0));
  percent_line("ratio Python / C++, median of the rounds' ratios", f.at("paired_ratio"), iqr);
  percent_line("ratio Python / C++, medians", f.at("py_median") / f.at("cpp_median"));
  percent_line("ratio Python / C++, minima", f.at("py_min") / f.at("cpp_min"));
  std::printf("  %-58s %12s\n", "requirement: Python at most 5 % over C++",
              f.at("paired_ratio") - 1.0 <= kRequirement ? "met" : "NOT MET");
}

void print_summary() {
  std::printf(
      "\n==== cutdyn lobes from Python: summary (wall clock, this run; %d threads = all) ====\n",
      all_threads());
  std::printf(
      "C++: app::run_lobes(case, request) in a C++ process; Python: cutdyn.lobes(case) in a\n"
      "python3 process; each child makes its case once and times %d calls, the first dropped;\n"
      "the case's [lobes] method, the same threads.\n",
      kCallsPerChild);
  comparison(kDefaultCase, 0);
  comparison(kDefaultCase, 1);
  comparison(1, 0);

  std::printf("\nWhere the Python call's extra time goes (%s, all threads, in this process):\n",
              kCases[kDefaultCase]);
  if (g_steps.empty()) {
    std::printf("  %-58s (not run)\n", "steps of the module's lobes");
    std::printf("\n");
    return;
  }
  double sum = 0.0;
  for (const Step& step : g_steps) {
    if (step.kind == Step::kBefore) continue;
    std::printf("  %-58s %12s\n", step.what.c_str(), seconds_text(step.seconds).c_str());
    sum += step.seconds;
  }
  std::printf("  %-58s %12s\n", "sum of the steps", seconds_text(sum).c_str());
  for (const int threads : {0, 1}) {
    if (const auto r = result(case_key("processes", kDefaultCase, threads))) {
      char what[96];
      std::snprintf(what, sizeof what, "steps / C++ call (median), %s",
                    threads == 1 ? "1 thread" : "all threads");
      std::printf("  %-58s %11.2f %%\n", what, 1e2 * sum / r->figures.at("cpp_median"));
    }
  }
  std::printf("  for comparison, what the module did before (not timed above):\n");
  for (const Step& step : g_steps)
    if (step.kind == Step::kBefore)
      std::printf("  %-58s %12s\n", step.what.c_str(), seconds_text(step.seconds).c_str());
  std::printf("\n");
}

}  // namespace
}  // namespace cutdyn

int main(int argc, char** argv) {
  // The C++ side of the comparison: this program re-run, no interpreter started.
  if (argc == 5 && std::strcmp(argv[1], "--cpp-child") == 0)
    return cutdyn::cpp_child(argv[2], std::atoi(argv[3]), std::atoi(argv[4]));
  pybind11::scoped_interpreter interpreter;
  pybind11::module_::import("sys").attr("path").attr("insert")(0, CUTDYN_PYTHON_DIR);
  return cutdyn::bench::run_benchmarks(argc, argv, cutdyn::print_summary);
}
