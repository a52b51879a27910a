// `cutdyn monitor calibrate | estimate | teach`: cutting force from servo-motor currents
// (docs/models/monitor.md). The jobs are the library's (cutdyn/app/monitor.hpp); this file
// parses the flags into their options and renders their Reports.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <system_error>

#include "cli/app.hpp"
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cutdyn/app/monitor.hpp"
#include "cutdyn/app/render.hpp"
#include "cutdyn/core/error.hpp"
#include "cutdyn/io/output.hpp"

namespace cutdyn::cli {
namespace {

using nlohmann::json;

// The flags of each subcommand: the job's options, filled by the flags directly, and what
// only the command line has (the files it writes, values still to be parsed).
struct CalibrateArgs {
  app::CalibrateOptions options;
  std::vector<std::string> kt;       // --kt [AXIS=]VALUE, N·m/A
  std::vector<std::string> inertia;  // --inertia [AXIS=]VALUE, kg·m²
  std::string measure;               // --measure rms|space-vector
  std::string on_bad_line = "stop";
  std::string out;  // --out calib.json (required)
};

struct EstimateArgs {
  app::EstimateOptions options;
  std::string calib;        // --calib C.json (or "zheng2012")
  std::string input = "-";  // INPUT.csv, or - for standard input
  std::string out;          // --out F.csv (else standard output, line by line)
  std::string band;         // --band B.json: add level/limits/alarm columns
  std::string alarms;       // --alarms F.csv: the alarm events
  std::string json;         // --json F.json: the summary (filter, warnings) as JSON
  std::string on_bad_line = "stop";
};

struct TeachArgs {
  app::TeachOptions options;
  std::string out;  // --out band.json (required)
  std::string on_bad_line = "stop";
};

// What --on-bad-line says.
bool stop_at_bad_line(const std::string& policy) {
  if (policy == "stop") return true;
  if (policy == "skip") return false;
  throw InvalidInput({"--on-bad-line = \"" + policy + "\": must be stop or skip"}, "command line");
}

// A required output: given, and checked as every output (cli/common.hpp) against `inputs`.
void check_out_flag(const std::string& out, const char* flag,
                    const std::vector<std::string>& inputs) {
  if (out.empty())
    throw InvalidInput({std::string(flag) + ": missing (where to write)"}, "command line");
  check_output_files({{flag, out}}, inputs);
}

// The report on standard error when the output file is standard output: that then holds the
// file and nothing else.
std::ostream& report_stream(const std::string& out_file, std::ostream& out, std::ostream& err) {
  return io::standard_stream(out_file) == 1 ? err : out;
}

void throw_if(const std::vector<std::string>& problems) {
  if (!problems.empty()) throw InvalidInput(problems, "command line");
}

// ---- what the jobs report as it happens ----------------------------------------------------

app::MonitorListener listener(std::ostream& err) {
  return {[&err](const app::MonitorWarning& w) {
            err << "cutdyn: warning: " << app::warning_text(w) << "\n";
          },
          [&err](const std::string& axis, const AlarmEvent& a) {
            err << "cutdyn: alarm: " << app::alarm_text(axis, a) << "\n";
          }};
}

// ---- calibrate ------------------------------------------------------------------------------

// --kt and --inertia, "[AXIS=]VALUE" each.
std::vector<app::AxisValue> axis_values(const std::vector<std::string>& texts, const char* flag) {
  std::vector<app::AxisValue> values;
  for (const std::string& text : texts) {
    const auto v = app::parse_axis_value(text);
    if (!v)
      throw InvalidInput(
          {std::string(flag) + " = \"" + text + "\": must be VALUE or AXIS=VALUE with a number"},
          "command line");
    values.push_back({v->first, v->second});
  }
  return values;
}

int run_calibrate(const CalibrateArgs& args, std::ostream& out, std::ostream& err) {
  app::CalibrateOptions options = args.options;
  options.stop_at_bad_line = stop_at_bad_line(args.on_bad_line);
  options.names = flag_names();
  std::vector<std::string> inputs = options.idle;
  inputs.insert(inputs.end(), options.loaded.begin(), options.loaded.end());
  inputs.push_back(options.base);
  check_out_flag(args.out, "--out", inputs);
  throw_if(options.fit.validate());
  if (!args.measure.empty()) {
    options.measure = parse_current_measure(args.measure);
    if (!options.measure)
      throw InvalidInput({"--measure = \"" + args.measure + "\": must be rms or space-vector"},
                         "command line");
  }
  options.torque_constant_nm_per_a = axis_values(args.kt, "--kt");
  options.inertia_kg_m2 = axis_values(args.inertia, "--inertia");

  const app::CalibrateReport report = app::calibrate(options, listener(err));
  std::ostream& text = report_stream(args.out, out, err);
  app::write_text(text, report);
  io::OutputTransaction outputs;
  io::write_json(outputs.open(args.out), app::calibration_json(report.axes));
  outputs.commit();
  text << "  wrote " << args.out << "\n";
  return 0;
}

// ---- estimate -------------------------------------------------------------------------------

// The options of an estimate, every problem with the flags thrown before anything is read.
app::EstimateOptions estimate_options(const EstimateArgs& args) {
  app::EstimateOptions options = args.options;
  options.stop_at_bad_line = stop_at_bad_line(args.on_bad_line);
  options.names = flag_names();
  throw_if(options.estimator.validate());
  throw_if(options.alarms.validate());
  check_output_files({{"--out", args.out}, {"--alarms", args.alarms}, {"--json", args.json}},
                     {args.calib, args.band, args.input});
  Validator v;
  if (!args.alarms.empty() && args.band.empty()) v.add("--alarms needs --band");
  if (!(options.tooth_frequency_hz >= 0.0) || !std::isfinite(options.tooth_frequency_hz))
    v.add("--tooth-frequency-hz = " + human(options.tooth_frequency_hz) +
          ": must be a finite number >= 0 (0: not reported)");
  v.throw_if_any("command line");
  return options;
}

// Whether the estimate goes to standard output, line by line as it is computed.
bool streams(const EstimateArgs& args) {
  return args.out.empty() || io::standard_stream(args.out) == 1;
}

void print_estimate(const EstimateArgs& args, const app::EstimateReport& r, std::ostream& out,
                    std::ostream& err) {
  std::ostream& report = streams(args) ? err : out;
  app::write_text(report, r);
  // With the estimate on standard output the report goes to stderr, the lines that name the
  // files written too: standard output holds the CSV and nothing else.
  for (const std::string* f : {&args.out, &args.alarms, &args.json})
    if (!f->empty())
      report << "  wrote " << (io::standard_stream(*f) == 1 ? "standard output" : *f) << "\n";
}

// The reader of the estimate on standard output has closed it (`... | head -1`).
struct OutputClosed {};

int run_estimate(const EstimateArgs& args, std::ostream& out, std::ostream& err) {
  const app::EstimateOptions options = estimate_options(args);
  app::Calibration calibration = app::read_calibration(args.calib);
  std::optional<app::BandFile> band;
  if (!args.band.empty()) band = app::read_band(args.band);

  io::OutputTransaction outputs;
  const bool streaming = streams(args);
  std::ostream& sink = streaming ? out : outputs.open(args.out);
  if (streaming) {
    // A closed reader shows as a failed write (EPIPE), not as a signal, whatever SIGPIPE's
    // disposition was inherited: the run then ends quietly with kExitOutputClosed. Not
    // restored: the exit flushes standard output once more.
    struct sigaction ignore = {};
    ignore.sa_handler = SIG_IGN;
    sigemptyset(&ignore.sa_mask);
    sigaction(SIGPIPE, &ignore, nullptr);
  }
  app::LogInput in(args.input);
  const auto write = [&](std::string_view rows) {
    errno = 0;
    sink.write(rows.data(), static_cast<std::streamsize>(rows.size()));
    if (!streaming) return;
    sink.flush();  // a live stream is answered line by line
    if (sink) return;
    if (errno == EPIPE) throw OutputClosed{};
    throw std::runtime_error("standard output: write error" +
                             (errno ? ": " + std::generic_category().message(errno) : ""));
  };
  app::EstimateJob job(std::move(calibration), args.calib, options, std::move(band), args.band,
                       in.name(), {write, {}}, listener(err));
  try {
    for (std::string_view chunk = in.read(); !chunk.empty(); chunk = in.read()) job.feed(chunk);
  } catch (const OutputClosed&) {
    return kExitOutputClosed;  // no summary, no files: the run did not reach the input's end
  }
  const app::EstimateReport report = job.finish();

  if (!args.json.empty()) io::write_json(outputs.open(args.json), app::to_json(report));
  if (!args.alarms.empty()) {
    io::CsvWriter csv(outputs.open(args.alarms),
                      {"time_s", "axis", "alarm", "detected_s", "level", "limit"});
    for (const auto& [axis, a] : report.alarms)
      csv.row({a.time_s, axis, std::string(to_string(a.kind)), a.detected_s, a.level_n, a.limit_n});
  }
  outputs.commit();
  print_estimate(args, report, out, err);
  return 0;
}

// ---- teach ----------------------------------------------------------------------------------

int run_teach(const TeachArgs& args, std::ostream& out, std::ostream& err) {
  app::TeachOptions options = args.options;
  options.stop_at_bad_line = stop_at_bad_line(args.on_bad_line);
  std::vector<std::string> inputs = options.references;
  inputs.push_back(options.calibration);
  check_out_flag(args.out, "--out", inputs);
  throw_if(options.estimator.validate());
  if (options.rpm.has_value() != options.teeth.has_value())
    throw InvalidInput({options.rpm ? "--rpm needs --teeth (the tooth period is 60/(teeth·rpm))"
                                    : "--teeth needs --rpm (the tooth period is 60/(teeth·rpm))"},
                       "command line");
  throw_if(options.effective_band().validate());
  if (options.references.empty())
    throw InvalidInput({"REFERENCE: give at least one reference run"}, "command line");

  const app::TeachReport report = app::teach(options, listener(err));
  std::ostream& text = report_stream(args.out, out, err);
  app::write_text(text, report);
  io::OutputTransaction outputs;
  io::write_json(outputs.open(args.out), app::band_json(report.band));
  outputs.commit();
  text << "  wrote " << args.out << "\n";
  return 0;
}

// ---- the flags --------------------------------------------------------------------------------

void add_bad_line(CLI::App* c, std::string& policy) {
  c->add_option("--on-bad-line", policy,
                "stop (default): a malformed line is an error (exit 2); skip: leave it out "
                "and report how many were skipped");
}

void add_estimator(CLI::App* c, std::string& calib, EstimatorOptions& o, std::string& policy) {
  c->add_option("--calib", calib,
                "calibration file (JSON, from `monitor calibrate`) or "
                "zheng2012 (the source's preset)")
      ->required();
  c->add_option("--bandwidth-hz", o.bandwidth_hz,
                "f_b of the estimate's filter, where its gain is 0.5 and its lag 90° (−3 dB at "
                "0.644·f_b; default 50)");
  c->add_option("--standstill-rad-s", o.standstill_rad_s,
                "below this speed the axis is at standstill (default 0.5)");
  add_bad_line(c, policy);
}

CLI::App* add_calibrate(CLI::App* monitor, CalibrateArgs& a) {
  auto* c = monitor->add_subcommand("calibrate",
                                    "fit Tnzm and X (idle logs) and KBlf (loaded logs) per axis");
  app::CalibrateOptions& o = a.options;
  c->add_option("--idle", o.idle, "no-cut logs at constant speeds (CSV)")->expected(1, -1);
  c->add_option("--loaded", o.loaded, "logs with a reference force column (CSV)")->expected(1, -1);
  c->add_option("--base", o.base,
                "calibration file or zheng2012: KT, J, measure and the values not fitted");
  c->add_option("--kt", a.kt, "torque constant [AXIS=]VALUE (N·m/A)");
  c->add_option("--inertia", a.inertia, "inertia at the motor [AXIS=]VALUE (kg·m²)");
  c->add_option("--measure", a.measure,
                "equivalent current: space-vector (default; --base keeps its own) | rms");
  c->add_option("--force-column", o.force_column,
                "reference force column of the loaded logs (default force_n)");
  c->add_option("--window-s", o.fit.window_s, "averaging window (default 0.05 s)");
  c->add_option("--steady-tolerance", o.fit.steady_tolerance,
                "a window is steady if its speed changes by at most this fraction (default "
                "0.01)");
  c->add_option("--standstill-rad-s", o.fit.standstill_rad_s,
                "windows with a slower sample are not used (default 0.5)");
  c->add_option("--out", a.out, "write the calibration (JSON)")->required();
  add_bad_line(c, a.on_bad_line);
  return c;
}

CLI::App* add_estimate(CLI::App* monitor, EstimateArgs& a) {
  auto* c = monitor->add_subcommand("estimate",
                                    "estimate the cutting force from a current log, as it arrives");
  c->add_option("INPUT", a.input, "current log (CSV), - for standard input (default)");
  add_estimator(c, a.calib, a.options.estimator, a.on_bad_line);
  c->add_option("--out", a.out, "write the estimate to a file (else standard output)");
  c->add_option("--band", a.band, "band file from `monitor teach`: add alarms");
  c->add_option("--alarms", a.alarms, "with --band: write the alarm events (CSV)");
  c->add_option("--tooth-frequency-hz", a.options.tooth_frequency_hz,
                "also report the estimate's filter gain and lag at this frequency (e.g. teeth × "
                "rpm/60)");
  c->add_option("--json", a.json,
                "write a summary as JSON: the filter of each axis, what force_sigma_n covers, "
                "warnings");
  AlarmOptions& alarms = a.options.alarms;
  c->add_option("--persist-s", alarms.persist_s,
                "overload and breakage must last this long (default 0.005 s)");
  c->add_option("--wear-fraction", alarms.wear_fraction,
                "relative rise of the smoothed level that means wear (default 0.15)");
  c->add_option("--wear-time-constant-s", alarms.wear_time_constant_s,
                "smoothing of the wear indicator (default 0.5 s)");
  return c;
}

CLI::App* add_teach(CLI::App* monitor, TeachArgs& a) {
  auto* c = monitor->add_subcommand(
      "teach", "teach-in: learn the band of the estimated force from reference runs");
  app::TeachOptions& o = a.options;
  c->add_option("REFERENCE", o.references, "reference runs (CSV current logs), one cycle each")
      ->required();
  add_estimator(c, o.calibration, o.estimator, a.on_bad_line);
  c->add_option("--out", a.out, "write the band (JSON)")->required();
  c->add_option("--bin-s", o.band.bin_s, "band bin width (default 0.01 s)");
  c->add_option("--rpm", o.rpm,
                "spindle speed of the cut (with --teeth): the level is averaged over the tooth "
                "period T = 60/(teeth·rpm) and smoothed with 0.12·T, the phase tolerance is one "
                "revolution; a broken tooth is then caught within about one tooth period");
  c->add_option("--teeth", o.teeth, "number of teeth of the cutter (with --rpm)");
  c->add_option("--smoothing-s", o.smoothing_s,
                "time constant of the monitored level (default 0.01 s; with --rpm and --teeth "
                "0.12 tooth periods)");
  c->add_option("--k-sigma", o.band.k_sigma, "half-width: k·sigma (default 3) ...");
  c->add_option("--relative-margin", o.band.relative_margin, "... + this·mean (default 0.1) ...");
  c->add_option("--absolute-margin-n", o.band.absolute_margin_n, "... + this (default 0 N) ...");
  c->add_option("--peak-margin", o.band.peak_margin,
                "... + this·the peak mean level (default 0.05)");
  c->add_option("--phase-tolerance-s", o.phase_tolerance_s,
                "each bin takes the widest limits within ± this much cycle time, so that the "
                "band does not depend on the spindle phase at cycle start: at least one spindle "
                "revolution, 60/rpm (default 0.1 s; with --rpm: 60/rpm)");
  c->add_option("--average-s", o.average_s,
                "moving average of |F| over this window before the smoothing: the tooth period "
                "60/(teeth·rpm) removes the tooth pattern (default 0: none; with --rpm and "
                "--teeth: the tooth period)");
  c->add_option("--cutting-fraction", o.band.cutting_fraction,
                "bins whose mean is at least this fraction of the peak are cutting (default "
                "0.2); breakage is watched there");
  return c;
}

}  // namespace

std::function<int(std::ostream&, std::ostream&)> add_monitor_command(CLI::App& app) {
  auto* monitor = app.add_subcommand(
      "monitor", "cutting force from servo-motor currents: calibrate, estimate, teach-in limits");
  monitor->require_subcommand(1);
  auto cal = std::make_shared<CalibrateArgs>();
  auto est = std::make_shared<EstimateArgs>();
  auto teach = std::make_shared<TeachArgs>();
  auto* c1 = add_calibrate(monitor, *cal);
  auto* c2 = add_estimate(monitor, *est);
  auto* c3 = add_teach(monitor, *teach);
  return [=](std::ostream& out, std::ostream& err) -> int {
    if (!monitor->parsed()) return -1;
    if (c1->parsed()) return run_calibrate(*cal, out, err);
    if (c2->parsed()) return run_estimate(*est, out, err);
    if (c3->parsed()) return run_teach(*teach, out, err);
    return -1;
  };
}

}  // namespace cutdyn::cli
