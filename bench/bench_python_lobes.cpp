// The cost of calling `lobes` from Python: `cutdyn.lobes(case)` through an embedded interpreter
// against the C++ call it wraps, `app::run_lobes(case, request)` with the same method and
// threads, on the case `cutdyn lobes` runs without one (the example turning-ultrasonic, the
// CLI's default; milling-insperger as a second case), measured in the same run — and where the
// difference goes: the steps of the module's `lobes` (src/python/module.cpp) timed one by one.
// The requirement: the Python call costs no more than 5 % over the C++ call on the default
// case. docs/benchmarks.md.
#include <pybind11/embed.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <future>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bench_support.hpp"
#include "cutdyn/app/render.hpp"
#include "cutdyn/app/report_json.hpp"
#include "cutdyn/app/stability.hpp"
#include "cutdyn/core/detail/parallel.hpp"
#include "cutdyn/io/case_file.hpp"
#include "python/common.hpp"  // the module's own conversions and worker thread

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
constexpr int kRounds = 21;  // interleaved C++/Python pairs per comparison
constexpr double kRequirement = 0.05;

// ---- the two sides, each case made once outside the timing ------------------------------

struct Side {
  io::Case cpp;       // io::load_example, as a C++ user reads it
  py::object python;  // cutdyn.example(name), as a Python user makes it
};

struct Python {
  py::module_ cutdyn;
  py::object lobes;  // cutdyn.lobes
  std::map<int, Side> sides;
};
// Cleared before the interpreter ends (main).
std::optional<Python> g_python;

Python& py_state() {
  if (!g_python) {
    g_python.emplace();
    g_python->cutdyn = py::module_::import("cutdyn");
    g_python->lobes = g_python->cutdyn.attr("lobes");
  }
  return *g_python;
}

const Side& side(int index) {
  Python& p = py_state();
  auto it = p.sides.find(index);
  if (it == p.sides.end()) {
    Side s{io::load_example(kCases[index]), p.cutdyn.attr("example")(kCases[index])};
    it = p.sides.emplace(index, std::move(s)).first;
  }
  return it->second;
}

// The C++ call: the job the module's `lobes` runs, with the method of the case's [lobes] (as
// `cutdyn.lobes(case)`) and the same threads.
app::LobesJobReport cpp_lobes(const io::Case& c, int threads) {
  app::LobesRequest request;
  request.threads = threads;
  return app::run_lobes(c, request);
}

// The Python call: `cutdyn.lobes(case)` for all cores (its default), else with threads=…;
// the result object is released inside the timing, as the C++ report is.
void python_lobes(const py::object& c, int threads) {
  if (threads == 0)
    py_state().lobes(c);
  else
    py_state().lobes(c, py::arg("threads") = threads);
}

std::string case_key(const std::string& prefix, const benchmark::State& state) {
  return prefix + "/" + kCases[state.range(0)] + (state.range(1) == 1 ? "/1" : "/all");
}

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The C++ call runs its parallel loops on the OpenMP team of the calling thread, which outlives
// the call: a C++ program has it ready from its second call on. The module runs each job on a
// thread started for the call, which starts its own team. Two teams alive at once make libgomp
// count more threads than cores and throttle the spin-wait of both, a state that neither a C++
// program nor a Python one calling only cutdyn is in; so the calling thread's team is started
// before each C++ call and ended after every call, outside the timing (docs/benchmarks.md).
void start_openmp_team(int threads) {
  parallel_for(2, threads, [](int) {});
}
void release_openmp_team() { omp_pause_resource_all(omp_pause_soft); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// ---- 1. each side on its own (the Google Benchmark table) ---------------------------------

void BM_LobesCpp(benchmark::State& state) {
  const Side& s = side(static_cast<int>(state.range(0)));
  const int threads = static_cast<int>(state.range(1));
  std::size_t speeds = 0;
  timed(state, case_key("cpp", state),
        [&] { speeds = cpp_lobes(s.cpp, threads).lobes.points.size(); });
  release_openmp_team();
  state.counters["speeds"] = static_cast<double>(speeds);
  state.counters["threads"] = threads > 0 ? threads : all_threads();
}

void BM_LobesPython(benchmark::State& state) {
  const Side& s = side(static_cast<int>(state.range(0)));
  const int threads = static_cast<int>(state.range(1));
  timed(state, case_key("python", state), [&] { python_lobes(s.python, threads); });
  state.counters["threads"] = threads > 0 ? threads : all_threads();
}

// ---- 2. the comparison: C++ and Python calls interleaved ----------------------------------

// kRounds pairs of `base` and `other`, the order alternating from round to round, so that a
// slow stretch of a shared machine falls on both sides alike: the medians and the minima of
// each side, and the median and quartiles of the rounds' own ratios, under `key`. `base` (the
// C++ call) runs with the calling thread's team started, as in a C++ program.
template <typename Base, typename Other>
Result& interleave(benchmark::State& state, const std::string& key, int threads, Base base,
                   Other other) {
  std::vector<double> a, b, ratios;
  const auto time = [](std::vector<double>& into, auto& body) {
    const auto start = Clock::now();
    body();
    into.push_back(seconds_since(start));
    release_openmp_team();
  };
  const auto run_base = [&] {
    start_openmp_team(threads);
    time(a, base);
  };
  Result& r = timed(state, key, [&] {
    a.clear();
    b.clear();
    ratios.clear();
    for (int round = 0; round < kRounds; ++round) {
      if (round % 2 == 0) {
        run_base();
        time(b, other);
      } else {
        time(b, other);
        run_base();
      }
      ratios.push_back(b.back() / a.back());
    }
  });
  r.figures["cpp_median"] = median(a);
  r.figures["py_median"] = median(b);
  r.figures["cpp_min"] = *std::min_element(a.begin(), a.end());
  r.figures["py_min"] = *std::min_element(b.begin(), b.end());
  r.figures["paired_ratio"] = median(ratios);
  std::sort(ratios.begin(), ratios.end());
  r.figures["paired_q1"] = ratios[ratios.size() / 4];
  r.figures["paired_q3"] = ratios[3 * ratios.size() / 4];
  r.figures["threads"] = threads > 0 ? threads : all_threads();
  state.counters["cpp_ms"] = 1e3 * r.figures["cpp_median"];
  state.counters["other_ms"] = 1e3 * r.figures["py_median"];
  state.counters["overhead_pct"] = 1e2 * (r.figures["py_median"] / r.figures["cpp_median"] - 1.0);
  state.counters["paired_overhead_pct"] = 1e2 * (r.figures["paired_ratio"] - 1.0);
  return r;
}

// The C++ call against `cutdyn.lobes(case)`.
void BM_LobesInterleaved(benchmark::State& state) {
  const Side& s = side(static_cast<int>(state.range(0)));
  const int threads = static_cast<int>(state.range(1));
  // Same result on both sides (not timed): the same speeds, the same method.
  const app::LobesJobReport reference = cpp_lobes(s.cpp, threads);
  release_openmp_team();
  const py::object result = py_state().lobes(s.python, py::arg("threads") = threads);
  const bool same = py::len(result.attr("spindle_rpm")) == reference.lobes.points.size() &&
                    result.attr("method").cast<std::string>() == reference.method;
  Result& r = interleave(
      state, case_key("interleaved", state), threads,
      [&] { benchmark::DoNotOptimize(cpp_lobes(s.cpp, threads)); },
      [&] { python_lobes(s.python, threads); });
  r.figures["speeds"] = static_cast<double>(reference.lobes.points.size());
  if (!same) state.SkipWithError("the Python result differs from the C++ report");
}

// The C++ call against the same job run as the module runs it — on a worker thread started
// for the call, the GIL released, the progress report that stops it on Ctrl-C — without any
// conversion of the report: what the thread costs at the scale of the whole call.
void BM_WorkerInterleaved(benchmark::State& state) {
  const Side& s = side(static_cast<int>(state.range(0)));
  const int threads = static_cast<int>(state.range(1));
  interleave(
      state, case_key("worker", state), threads,
      [&] { benchmark::DoNotOptimize(cpp_lobes(s.cpp, threads)); },
      [&] {
        benchmark::DoNotOptimize(
            python::run_interruptible<app::LobesJobReport>([&](const std::atomic<bool>& cancel) {
              app::LobesRequest request;
              request.threads = threads;
              request.progress = python::stop_on(cancel);
              return app::run_lobes(s.cpp, request);
            }));
      });
}

// The C++ call against the same call on a thread started for it (std::async, waited for with
// get()): the fresh thread alone, without the module's GIL release and Ctrl-C polling.
void BM_ThreadInterleaved(benchmark::State& state) {
  const Side& s = side(static_cast<int>(state.range(0)));
  const int threads = static_cast<int>(state.range(1));
  interleave(
      state, case_key("thread", state), threads,
      [&] { benchmark::DoNotOptimize(cpp_lobes(s.cpp, threads)); },
      [&] {
        benchmark::DoNotOptimize(
            std::async(std::launch::async, [&] { return cpp_lobes(s.cpp, threads); }).get());
      });
}

// The C++ call with the calling thread's team started against the same call starting it: what
// a team's start costs a call, as each call from Python pays it on its fresh thread.
void BM_TeamInterleaved(benchmark::State& state) {
  const Side& s = side(static_cast<int>(state.range(0)));
  const int threads = static_cast<int>(state.range(1));
  const auto call = [&] { benchmark::DoNotOptimize(cpp_lobes(s.cpp, threads)); };
  interleave(state, case_key("team", state), threads, call, call);
}

// ---- 3. where the difference goes: the steps of the module's `lobes` ----------------------

// Each step as src/python/module.cpp runs it after (or around) app::run_lobes, with the
// module's own helpers (src/python/common.cpp), on the report of the default case, all
// threads. The median over batches of the time per call.
struct Step {
  enum Kind { kThread, kConversion, kAlternative };
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

// The report's values made into Python objects directly, as the module's to_python now does
// (it went through the JSON text, dump then Python's json.loads, before); kept here to time the
// two ways against each other.
py::object python_of(const nlohmann::json& j) {
  using Type = nlohmann::json::value_t;
  switch (j.type()) {
    case Type::boolean:
      return py::bool_(j.get<bool>());
    case Type::number_integer:
      return py::int_(j.get<std::int64_t>());
    case Type::number_unsigned:
      return py::int_(j.get<std::uint64_t>());
    case Type::number_float:
      return py::float_(j.get<double>());
    case Type::string:
      return py::str(j.get_ref<const std::string&>());
    case Type::array: {
      py::list list(j.size());
      std::size_t i = 0;
      for (const auto& item : j) list[i++] = python_of(item);
      return list;
    }
    case Type::object: {
      py::dict dict;
      for (const auto& [key, value] : j.items()) dict[py::str(key)] = python_of(value);
      return dict;
    }
    default:
      return py::none();
  }
}

void BM_PythonSteps(benchmark::State& state) {
  const Side& s = side(kDefaultCase);
  const int threads = 0;
  const app::LobesJobReport report = cpp_lobes(s.cpp, threads);
  release_openmp_team();
  std::vector<Step> steps;
  Result& r = timed(state, "steps", [&] {
    steps.clear();
    // The worker thread: a job that does nothing, run as the module runs every job (GIL
    // released, std::async, the calling thread polling for Ctrl-C).
    steps.push_back(
        {"worker thread + GIL release (empty job)",
         per_call(
             200,
             [] { python::run_interruptible<int>([](const std::atomic<bool>&) { return 0; }); }),
         Step::kThread});
    // A fresh thread has no OpenMP team: its first parallel region starts one (the calling
    // thread's is ready between C++ calls). Its cost depends on the spin-wait of the team's
    // threads and on what else runs on the cores (docs/benchmarks.md).
    const auto two_jobs = [&] { parallel_for(2, threads, [](int) {}); };
    const double fresh = per_call(200, [&] {
      python::run_interruptible<int>([&](const std::atomic<bool>&) {
        two_jobs();
        return 0;
      });
    });
    const double warm = per_call(200, two_jobs);
    release_openmp_team();
    steps.push_back({"  + a parallel region on it (starts its OpenMP team)",
                     std::max(0.0, fresh - warm - steps.back().seconds), Step::kThread});
    app::ReportTable table;
    steps.push_back({"app::lobes_table (report -> rows of cells)",
                     per_call(20, [&] { table = app::lobes_table(report); })});
    steps.push_back({"columns_of (rows -> numpy arrays)",
                     per_call(20, [&] { benchmark::DoNotOptimize(python::columns_of(table)); })});
    nlohmann::json json;
    steps.push_back({"app::to_json (report -> nlohmann::json)",
                     per_call(5, [&] { json = app::to_json(s.cpp, report); })});
    std::string text;
    steps.push_back({"  json.dump() (-> JSON text)", per_call(5, [&] { text = json.dump(); })});
    const py::object loads = py::module_::import("json").attr("loads");
    steps.push_back({"  json.loads (JSON text -> Python dict)", per_call(5, [&] { loads(text); })});
    steps.push_back({"text_of (the text `cutdyn lobes` prints)", per_call(20, [&] {
                       benchmark::DoNotOptimize(python::text_of(s.cpp, report));
                     })});
    // The Python side: cutdyn.Lobes(native) over the dict the native part returns.
    py::dict native;
    native["columns"] = python::columns_of(table);
    native["report"] = python::to_python(json);
    native["text"] = text;
    const py::object wrapper = py_state().cutdyn.attr("Lobes");
    steps.push_back(
        {"cutdyn.Lobes(...) (the Python result object)", per_call(200, [&] { wrapper(native); })});
    // What would do without the JSON text: the same dict built directly.
    if (!python_of(json).equal(python::to_python(json)))
      state.SkipWithError("the direct conversion differs from json.loads");
    steps.push_back({"report -> Python dict directly (instead of dump + loads)",
                     per_call(5, [&] { python_of(json); }), Step::kAlternative});
  });
  double sum = 0.0;
  for (const Step& step : steps)
    if (step.kind == Step::kConversion) sum += step.seconds;
  r.figures["conversions"] = sum;
  state.counters["conversions_ms"] = 1e3 * sum;
  g_steps = steps;
}

constexpr auto kMs = benchmark::kMillisecond;

// Args: {case, threads}; threads 0 = all cores (the Python default), 1 = one (less noise).
void both_threads(benchmark::internal::Benchmark* b) {
  b->ArgNames({"case", "threads"})->Args({kDefaultCase, 0})->Args({kDefaultCase, 1});
  b->Args({1, 0});
}

BENCHMARK(BM_LobesCpp)->Apply(both_threads)->Unit(kMs)->UseRealTime();
BENCHMARK(BM_LobesPython)->Apply(both_threads)->Unit(kMs)->UseRealTime();
BENCHMARK(BM_LobesInterleaved)->Apply(both_threads)->Iterations(1)->Unit(kMs)->UseRealTime();
BENCHMARK(BM_TeamInterleaved)
    ->ArgNames({"case", "threads"})
    ->Args({kDefaultCase, 0})
    ->Iterations(1)
    ->Unit(kMs)
    ->UseRealTime();
BENCHMARK(BM_ThreadInterleaved)
    ->ArgNames({"case", "threads"})
    ->Args({kDefaultCase, 0})
    ->Iterations(1)
    ->Unit(kMs)
    ->UseRealTime();
BENCHMARK(BM_WorkerInterleaved)
    ->ArgNames({"case", "threads"})
    ->Args({kDefaultCase, 0})
    ->Args({kDefaultCase, 1})
    ->Iterations(1)
    ->Unit(kMs)
    ->UseRealTime();
BENCHMARK(BM_PythonSteps)->Iterations(1)->Unit(kMs)->UseRealTime();

// ---- summary ---------------------------------------------------------------------------

std::string label(int index, int threads) {
  return std::string(kCases[index]) + (threads == 1 ? "/1" : "/all");
}

void percent_line(const char* what, double ratio, const char* note = "") {
  std::printf("  %-58s %11.3fx  (%+.1f %%)%s\n", what, ratio, 1e2 * (ratio - 1.0), note);
}

// The verdict goes by the median of the rounds' own ratios: each round's two calls share the
// machine's load of that moment, which the medians of each side alone do not.
void comparison(int index, int threads) {
  const auto r = result("interleaved/" + label(index, threads));
  std::printf("\n%s%s, %s, %d interleaved rounds:\n", kCases[index],
              index == kDefaultCase ? " (the default case)" : "",
              threads == 1 ? "1 thread" : "all threads", kRounds);
  if (!r) {
    std::printf("  %-58s (not run)\n", "comparison");
    return;
  }
  const auto& f = r->figures;
  std::printf("  %-58s %12.0f\n", "speeds", f.at("speeds"));
  std::printf("  %-58s %12s  (min %s)\n", "C++ app::run_lobes, median",
              seconds_text(f.at("cpp_median")).c_str(), seconds_text(f.at("cpp_min")).c_str());
  std::printf("  %-58s %12s  (min %s)\n", "Python cutdyn.lobes(case), median",
              seconds_text(f.at("py_median")).c_str(), seconds_text(f.at("py_min")).c_str());
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
      "C++: app::run_lobes(case, request); Python: cutdyn.lobes(case) in an embedded "
      "interpreter;\neach side's case made once, the case's [lobes] method, the same "
      "threads.\n");
  comparison(kDefaultCase, 0);
  comparison(kDefaultCase, 1);
  comparison(1, 0);

  std::printf(
      "\nWhere the Python call's extra time goes (%s; each ratio its own %d "
      "interleaved rounds):\n",
      kCases[kDefaultCase], kRounds);
  const auto paired = [](const char* what, const std::string& key) {
    const auto w = result(key);
    if (!w) {
      std::printf("  %-58s (not run)\n", what);
      return;
    }
    char iqr[64];
    std::snprintf(iqr, sizeof iqr, ", quartiles %+.1f..%+.1f %%",
                  1e2 * (w->figures.at("paired_q1") - 1.0),
                  1e2 * (w->figures.at("paired_q3") - 1.0));
    percent_line(what, w->figures.at("paired_ratio"), iqr);
  };
  paired("C++, OpenMP team started in the call / ready, all thr.",
         "team/" + label(kDefaultCase, 0));
  paired("C++ on a fresh thread (std::async) / C++, all thr.", "thread/" + label(kDefaultCase, 0));
  paired("C++ on the module's worker thread / C++, all thr.", "worker/" + label(kDefaultCase, 0));
  paired("C++ on the module's worker thread / C++, 1 thr.", "worker/" + label(kDefaultCase, 1));
  if (g_steps.empty()) {
    std::printf("  %-58s (not run)\n", "steps of the module's lobes");
    std::printf("\n");
    return;
  }
  const auto steps_of = [](Step::Kind kind) {
    double sum = 0.0;
    for (const Step& step : g_steps) {
      if (step.kind != kind) continue;
      std::printf("  %-58s %12s\n", step.what.c_str(), seconds_text(step.seconds).c_str());
      sum += step.seconds;
    }
    return sum;
  };
  std::printf("  the steps of the module's lobes, one by one (all threads):\n");
  steps_of(Step::kThread);
  std::printf("  the report's conversions:\n");
  const double sum = steps_of(Step::kConversion);
  std::printf("  %-58s %12s\n", "sum of the conversions", seconds_text(sum).c_str());
  for (const int threads : {0, 1}) {
    if (const auto r = result("interleaved/" + label(kDefaultCase, threads))) {
      char what[96];
      std::snprintf(what, sizeof what, "conversions / C++ call (median), %s",
                    threads == 1 ? "1 thread" : "all threads");
      std::printf("  %-58s %11.2f %%\n", what, 1e2 * sum / r->figures.at("cpp_median"));
    }
  }
  std::printf("  what a fix could do instead (not what the module does):\n");
  steps_of(Step::kAlternative);
  std::printf("\n");
}

}  // namespace
}  // namespace cutdyn

int main(int argc, char** argv) {
  pybind11::scoped_interpreter interpreter;
  pybind11::module_::import("sys").attr("path").attr("insert")(0, CUTDYN_PYTHON_DIR);
  const int status = cutdyn::bench::run_benchmarks(argc, argv, cutdyn::print_summary);
  cutdyn::g_python.reset();  // before the interpreter ends
  return status;
}
