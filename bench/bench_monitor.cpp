// Monitor estimation: cutting force from servo-motor currents, in samples per second
// per core, from memory and from CSV text, and the ratio against the straightforward way
// (ε from a raw difference; iostream parsing and writing), measured in the same run. The CSV
// reader and writer also against the previous ones (monitor_csv_baseline.hpp: std::from_chars
// and std::to_chars per field), and the whole of `cutdyn monitor estimate` short of the file
// descriptors (app::EstimateJob). docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "cutdyn/app/monitor.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/drive/equivalent_current.hpp"
#include "cutdyn/monitor/current_csv.hpp"
#include "cutdyn/monitor/force_estimator.hpp"
#include "monitor_csv_baseline.hpp"

namespace cutdyn {
namespace {

using namespace bench;

constexpr int kSamples = 1'000'000;  // three axes interleaved, 1 kHz per axis
constexpr double kDt = 1e-3;

struct Log {
  std::vector<double> t, iu, iv, iw, w;
  std::vector<int> axis;
  std::string csv;
};

// Speeds varying slowly around 50–120 rad/s, a pulsating force, noise on currents and speed.
const Log& log_data() {
  static const Log log = [] {
    Log l;
    std::mt19937_64 rng(1);
    std::normal_distribution<double> g(0.0, 1.0);
    const char names[3] = {'x', 'y', 'z'};
    double angle[3] = {0, 0, 0};
    std::ostringstream csv;
    csv.precision(9);
    csv << "time_s,axis,iu_a,iv_a,iw_a,speed_rad_s\n";
    for (int k = 0; k < kSamples; ++k) {
      const int a = k % 3;
      const double t = (k / 3) * kDt;
      const AxisModel m = zheng2012_axis(names[a]);
      const double w = 80.0 + 40.0 * std::sin(0.5 * t + a);
      const double eps = 20.0 * std::cos(0.5 * t + a);
      const double f = 2000.0 + 500.0 * std::sin(units::kTwoPi * 25.0 * t);
      const double peak = std::sqrt(2.0) * m.equivalent_current_a(f, w, eps);
      angle[a] += 4.0 * w * kDt;
      l.t.push_back(t);
      l.axis.push_back(a);
      l.iu.push_back(peak * std::cos(angle[a]) + 0.1 * g(rng));
      l.iv.push_back(peak * std::cos(angle[a] - units::kTwoPi / 3) + 0.1 * g(rng));
      l.iw.push_back(peak * std::cos(angle[a] + units::kTwoPi / 3) + 0.1 * g(rng));
      l.w.push_back(w + 0.2 * g(rng));
      csv << t << ',' << names[a] << ',' << l.iu.back() << ',' << l.iv.back() << ',' << l.iw.back()
          << ',' << l.w.back() << '\n';
    }
    l.csv = csv.str();
    return l;
  }();
  return log;
}

AxisCalibration calibration(char axis) {
  AxisCalibration c = zheng2012_calibration(axis);
  c.current_noise_a = 0.1 / std::sqrt(3.0);
  c.speed_noise_rad_s = 0.2;
  return c;
}

void BM_EstimateFromMemory(benchmark::State& state) {
  const Log& l = log_data();
  double sum = 0.0;
  Result& r = timed(state, "memory", [&] {
    std::vector<AxisForceEstimator> est{AxisForceEstimator(calibration('x')),
                                        AxisForceEstimator(calibration('y')),
                                        AxisForceEstimator(calibration('z'))};
    sum = 0.0;
    for (int k = 0; k < kSamples; ++k) {
      const ForceEstimate e = est[static_cast<std::size_t>(l.axis[k])].update(
          l.t[k], l.iu[k], l.iv[k], l.iw[k], l.w[k]);
      sum += e.force_n + e.force_sigma_n;
    }
    benchmark::DoNotOptimize(sum);
  });
  r.figures["per_s"] = kSamples / r.seconds;
  state.counters["samples_per_s"] = kSamples / r.seconds;
}

// The straightforward loop: ε as a raw difference of the measured speed, no uncertainty.
void BM_RawDifferenceFromMemory(benchmark::State& state) {
  const Log& l = log_data();
  const AxisModel m[3] = {zheng2012_axis('x'), zheng2012_axis('y'), zheng2012_axis('z')};
  double sum = 0.0;
  Result& r = timed(state, "memory_raw", [&] {
    double last_w[3] = {0, 0, 0}, last_t[3] = {-1, -1, -1};
    sum = 0.0;
    for (int k = 0; k < kSamples; ++k) {
      const int a = l.axis[k];
      const double id = equivalent_current(l.iu[k], l.iv[k], l.iw[k], CurrentMeasure::kRms);
      const double eps = last_t[a] < 0 ? 0.0 : (l.w[k] - last_w[a]) / (l.t[k] - last_t[a]);
      last_w[a] = l.w[k];
      last_t[a] = l.t[k];
      sum += m[a].cutting_force_n(id, l.w[k], eps);
    }
    benchmark::DoNotOptimize(sum);
  });
  r.figures["per_s"] = kSamples / r.seconds;
  state.counters["samples_per_s"] = kSamples / r.seconds;
}

// CSV text in, CSV text out, as `cutdyn monitor estimate` does it (64 KiB pieces), with the
// reader and writer of `Csv` (the current ones, or the previous ones of baseline::).
struct CurrentCsv {
  using Parser = CurrentCsvParser;
  static void row(std::string& out, double t, std::string_view axis, const ForceEstimate& e) {
    append_estimate_row(out, t, axis, e);
  }
  // In place, as app::EstimateJob writes them: `out` is storage, the text is [0, used).
  static constexpr bool kInPlace = true;
  static void row(std::string& out, std::size_t& used, double t, std::string_view axis,
                  const ForceEstimate& e) {
    if (out.size() < used + kEstimateRowRoom + axis.size() + 1)
      out.resize(std::max(2 * out.size(), used + kEstimateRowRoom + axis.size() + 1));
    char* p = write_estimate_row(out.data() + used, t, axis, e);
    *p++ = '\n';
    used = static_cast<std::size_t>(p - out.data());
  }
};
struct BaselineCsv {
  using Parser = baseline::BaselineCsvParser;
  static constexpr bool kInPlace = false;
  static void row(std::string& out, double t, std::string_view axis, const ForceEstimate& e) {
    baseline::append_estimate_row(out, t, axis, e);
  }
};

template <typename Csv>
void estimate_from_csv(benchmark::State& state, const std::string& key) {
  const Log& l = log_data();
  std::size_t bytes = 0;
  Result& r = timed(state, key, [&] {
    typename Csv::Parser parser("bench");
    std::map<std::string, AxisCalibration> cal{
        {"x", calibration('x')}, {"y", calibration('y')}, {"z", calibration('z')}};
    std::vector<AxisForceEstimator> est;
    std::vector<CurrentRow> rows;
    std::vector<CsvLineError> errors;
    std::string out = kEstimateHeader;
    std::size_t used = out.size();
    bytes = 0;
    const std::string_view text = l.csv;
    const auto process = [&] {
      for (const CurrentRow& row : rows) {
        while (est.size() <= static_cast<std::size_t>(row.axis))
          est.emplace_back(cal.at(parser.axes()[est.size()]));
        const ForceEstimate e = est[static_cast<std::size_t>(row.axis)].update(
            row.time_s, row.iu_a, row.iv_a, row.iw_a, row.speed_rad_s);
        const std::string& axis = parser.axes()[static_cast<std::size_t>(row.axis)];
        if constexpr (Csv::kInPlace) {
          Csv::row(out, used, row.time_s, axis, e);
        } else {
          Csv::row(out, row.time_s, axis, e);
          out += '\n';
        }
      }
      rows.clear();
      if constexpr (Csv::kInPlace) {
        bytes += used;
        used = 0;
      } else {
        bytes += out.size();
        out.clear();
      }
    };
    for (std::size_t at = 0; at < text.size(); at += 1 << 16) {
      parser.feed(text.substr(at, 1 << 16), rows, errors, true);
      process();
    }
    parser.finish(rows, errors, true);
    process();
    benchmark::DoNotOptimize(bytes);
  });
  r.figures["per_s"] = kSamples / r.seconds;
  r.figures["mb_per_s"] = static_cast<double>(l.csv.size()) / r.seconds / 1e6;
  state.counters["samples_per_s"] = kSamples / r.seconds;
}

void BM_EstimateFromCsv(benchmark::State& state) { estimate_from_csv<CurrentCsv>(state, "csv"); }

void BM_EstimateFromCsvBaseline(benchmark::State& state) {
  estimate_from_csv<BaselineCsv>(state, "csv_baseline");
}

// The reading alone (rows in memory), current and previous.
template <typename Parser>
void read_csv(benchmark::State& state, const std::string& key) {
  const Log& l = log_data();
  std::size_t good = 0;
  Result& r = timed(state, key, [&] {
    Parser parser("bench");
    std::vector<CurrentRow> rows;
    std::vector<CsvLineError> errors;
    good = 0;
    const std::string_view text = l.csv;
    for (std::size_t at = 0; at < text.size(); at += 1 << 16) {
      parser.feed(text.substr(at, 1 << 16), rows, errors, true);
      good += rows.size();
      rows.clear();
    }
    parser.finish(rows, errors, true);
    good += rows.size();
    benchmark::DoNotOptimize(good);
  });
  r.figures["per_s"] = kSamples / r.seconds;
  state.counters["samples_per_s"] = kSamples / r.seconds;
}

void BM_ReadCsv(benchmark::State& state) { read_csv<CurrentCsvParser>(state, "read"); }
void BM_ReadCsvBaseline(benchmark::State& state) {
  read_csv<baseline::BaselineCsvParser>(state, "read_baseline");
}

// The writing alone (the estimates of the log, computed once), current and previous.
template <typename Csv>
void write_csv(benchmark::State& state, const std::string& key) {
  const Log& l = log_data();
  static const std::vector<ForceEstimate> estimates = [&] {
    std::vector<AxisForceEstimator> est{AxisForceEstimator(calibration('x')),
                                        AxisForceEstimator(calibration('y')),
                                        AxisForceEstimator(calibration('z'))};
    std::vector<ForceEstimate> e;
    for (int k = 0; k < kSamples; ++k)
      e.push_back(est[static_cast<std::size_t>(l.axis[k])].update(l.t[k], l.iu[k], l.iv[k], l.iw[k],
                                                                  l.w[k]));
    return e;
  }();
  const char* const names[3] = {"x", "y", "z"};
  std::size_t bytes = 0;
  Result& r = timed(state, key, [&] {
    std::string out;
    bytes = 0;
    for (int k = 0; k < kSamples; ++k) {
      Csv::row(out, l.t[k], names[l.axis[k]], estimates[static_cast<std::size_t>(k)]);
      out += '\n';
      if (out.size() > (1 << 16)) {
        bytes += out.size();
        out.clear();
      }
    }
    bytes += out.size();
    benchmark::DoNotOptimize(bytes);
  });
  r.figures["per_s"] = kSamples / r.seconds;
  state.counters["samples_per_s"] = kSamples / r.seconds;
}

void BM_WriteCsv(benchmark::State& state) { write_csv<CurrentCsv>(state, "write"); }
void BM_WriteCsvBaseline(benchmark::State& state) {
  write_csv<BaselineCsv>(state, "write_baseline");
}

// What `cutdyn monitor estimate` runs between its read() and write() calls: app::EstimateJob
// (the bad-line policy, the estimators made as the axes appear, the warnings, the rows
// gathered per piece and handed to the sink), 64 KiB pieces.
void BM_EstimateJobFromCsv(benchmark::State& state) {
  const Log& l = log_data();
  std::size_t bytes = 0;
  Result& r = timed(state, "job", [&] {
    app::Calibration cal{{"x", calibration('x')}, {"y", calibration('y')}, {"z", calibration('z')}};
    app::EstimateOptions options;
    bytes = 0;
    app::EstimateJob job(std::move(cal), "bench", options, std::nullopt, {}, "bench",
                         {[&](std::string_view rows) { bytes += rows.size(); }, {}});
    const std::string_view text = l.csv;
    for (std::size_t at = 0; at < text.size(); at += 1 << 16) job.feed(text.substr(at, 1 << 16));
    benchmark::DoNotOptimize(job.finish().samples);
    benchmark::DoNotOptimize(bytes);
  });
  r.figures["per_s"] = kSamples / r.seconds;
  r.figures["mb_per_s"] = static_cast<double>(l.csv.size()) / r.seconds / 1e6;
  state.counters["samples_per_s"] = kSamples / r.seconds;
}

// The straightforward text path: getline per line, a stringstream per line split on ',',
// std::stod per field, a map from axis name to its state, raw differencing, operator<<.
void BM_StraightforwardCsv(benchmark::State& state) {
  const Log& l = log_data();
  const std::map<std::string, AxisModel> models{
      {"x", zheng2012_axis('x')}, {"y", zheng2012_axis('y')}, {"z", zheng2012_axis('z')}};
  std::size_t bytes = 0;
  Result& r = timed(state, "csv_raw", [&] {
    std::istringstream in(l.csv);
    std::ostringstream out;
    out << "time_s,axis,force_n\n";
    struct Last {
      double t = -1, w = 0;
    };
    std::map<std::string, Last> last;
    std::string line;
    std::getline(in, line);  // header (columns in the documented order)
    while (std::getline(in, line)) {
      std::stringstream ss(line);
      std::vector<std::string> f;
      for (std::string cell; std::getline(ss, cell, ',');) f.push_back(cell);
      const double t = std::stod(f[0]), iu = std::stod(f[2]), iv = std::stod(f[3]),
                   iw = std::stod(f[4]), w = std::stod(f[5]);
      Last& p = last[f[1]];
      const double eps = p.t < 0 ? 0.0 : (w - p.w) / (t - p.t);
      p = {t, w};
      const AxisModel& m = models.at(f[1]);
      const double force =
          m.cutting_force_n(equivalent_current(iu, iv, iw, CurrentMeasure::kRms), w, eps);
      out << t << ',' << f[1] << ',' << force << '\n';
    }
    bytes = out.str().size();
    benchmark::DoNotOptimize(bytes);
  });
  r.figures["per_s"] = kSamples / r.seconds;
  state.counters["samples_per_s"] = kSamples / r.seconds;
}

constexpr auto kMs = benchmark::kMillisecond;
BENCHMARK(BM_EstimateFromMemory)->Unit(kMs)->UseRealTime();
BENCHMARK(BM_RawDifferenceFromMemory)->Unit(kMs)->UseRealTime();
BENCHMARK(BM_EstimateFromCsv)->Unit(kMs)->UseRealTime();
BENCHMARK(BM_EstimateFromCsvBaseline)->Unit(kMs)->UseRealTime();
BENCHMARK(BM_EstimateJobFromCsv)->Unit(kMs)->UseRealTime();
BENCHMARK(BM_ReadCsv)->Unit(kMs)->UseRealTime();
BENCHMARK(BM_ReadCsvBaseline)->Unit(kMs)->UseRealTime();
BENCHMARK(BM_WriteCsv)->Unit(kMs)->UseRealTime();
BENCHMARK(BM_WriteCsvBaseline)->Unit(kMs)->UseRealTime();
BENCHMARK(BM_StraightforwardCsv)->Unit(kMs)->UseRealTime();

void per_second(const char* what, const std::optional<Result>& r) {
  if (!r) {
    std::printf("  %-58s (not run)\n", what);
    return;
  }
  std::printf("  %-58s %10.2f M/s\n", what, 1e-6 * r->figures.at("per_s"));
}

void print_summary() {
  std::printf("\n==== cutdyn monitor estimation: summary (wall clock, one thread) ====\n\n");
  std::printf("  %d samples, 3 axes interleaved, noisy currents and speed\n", kSamples);
  const auto mem = result("memory"), mem_raw = result("memory_raw"), csv = result("csv"),
             csv_base = result("csv_baseline"), job = result("job"), csv_raw = result("csv_raw");
  per_second("from memory: observer + uncertainty (cutdyn)", mem);
  per_second("from memory: raw difference, no uncertainty", mem_raw);
  per_second("from CSV text to CSV text (cutdyn)", csv);
  per_second("from CSV text to CSV text, the previous reader and writer", csv_base);
  per_second("from CSV text to CSV text through app::EstimateJob", job);
  per_second("reading CSV text alone (cutdyn)", result("read"));
  per_second("reading CSV text alone, the previous reader", result("read_baseline"));
  per_second("writing CSV text alone (cutdyn)", result("write"));
  per_second("writing CSV text alone, the previous writer", result("write_baseline"));
  per_second("from CSV text: getline/stringstream/stod/<< + raw difference", csv_raw);
  if (csv)
    std::printf("  %-58s %10.1f MB/s\n", "CSV input read (cutdyn)", csv->figures.at("mb_per_s"));
  if (csv_base)
    std::printf("  %-58s %10.1f MB/s\n", "CSV input read, the previous reader and writer",
                csv_base->figures.at("mb_per_s"));
  const auto times = [](const char* what, const std::optional<Result>& slow,
                        const std::optional<Result>& fast) {
    if (slow && fast) std::printf("  %-58s %11.2fx\n", what, slow->seconds / fast->seconds);
  };
  times("ratio previous / cutdyn, CSV text (time)", csv_base, csv);
  times("ratio previous / cutdyn, reading alone (time)", result("read_baseline"), result("read"));
  times("ratio previous / cutdyn, writing alone (time)", result("write_baseline"), result("write"));
  times("ratio straightforward / cutdyn, CSV text (time)", csv_raw, csv);
  if (mem && mem_raw)
    std::printf("  %-58s %11.2fx\n", "ratio raw difference / cutdyn, from memory (time)",
                mem_raw->seconds / mem->seconds);
  std::printf("\n");
}

}  // namespace
}  // namespace cutdyn

int main(int argc, char** argv) {
  return cutdyn::bench::run_benchmarks(argc, argv, cutdyn::print_summary);
}
