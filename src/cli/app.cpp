#include "cli/app.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <exception>
#include <functional>
#include <iostream>
#include <optional>

#include "cli/commands.hpp"
#include "cutdyn/app/drive.hpp"
#include "cutdyn/app/simulate.hpp"
#include "cutdyn/core/detail/parallel.hpp"
#include "cutdyn/core/error.hpp"
#include "cutdyn/io/case_file.hpp"
#include "cutdyn/io/inputs.hpp"
#include "cutdyn/io/output.hpp"

namespace cutdyn::cli {
namespace {

void add_outputs(CLI::App* cmd, Outputs& o, const char* csv_help) {
  cmd->add_option("--out", o.csv, csv_help);
  cmd->add_option("--json", o.json,
                  "write the results and the effective case as JSON (- for standard output, as "
                  "for --out; the report then goes to stderr)");
  cmd->add_option("--plot", o.plot,
                  "draw a figure (.svg, .png or .pdf); its data (.dat) and gnuplot script (.gp) "
                  "are written beside it");
}

}  // namespace

namespace {

// Whether one of the command's output files is "-" (standard output).
bool writes_to_standard_output(const CLI::App& command) {
  for (const char* name : {"--out", "--json", "--currents", "--plot"}) {
    const CLI::Option* option = command.get_option_no_throw(name);
    if (!option || option->count() == 0) continue;
    for (const std::string& value : option->results())
      if (io::standard_stream(value) == 1) return true;
  }
  return false;
}

// The commands' flags, each bound to its arguments; `parsed` names the command that ran.
struct Commands {
  LobesArgs lobes;
  CheckArgs check;
  SimulateArgs sim;
  DriveArgs drive;
  PlanArgs plan;
  ForceArgs force;
  IdentifyArgs identify;
  FitArgs fit;
  bool list = false;
  std::string example_name;
  CLI::App *example = nullptr, *lobes_cmd = nullptr, *check_cmd = nullptr, *sim_cmd = nullptr,
           *drive_cmd = nullptr, *plan_cmd = nullptr, *force_cmd = nullptr;
  CLI::App* identify_cmd = nullptr;
  CLI::App* fit_cmd = nullptr;
  std::function<int(std::ostream&, std::ostream&)> run_monitor, run_serve, run_sweep;
};

void add_stability_commands(CLI::App& app, Commands& c) {
  c.lobes_cmd =
      app.add_subcommand("lobes", "stability lobes: critical depth against spindle speed");
  CLI::App* lobes = c.lobes_cmd;
  lobes->add_option("CASE", c.lobes.case_path, "case file (TOML), or a built-in example's name");
  add_outputs(lobes, c.lobes.outputs,
              "write the lobes as CSV: spindle_rpm,critical_depth_mm,chatter_hz,lobe,"
              "bifurcation,beyond_limit (and duty_cycle,conventional_depth_mm,"
              "conventional_chatter_hz for vibration-assisted turning)");
  lobes->add_option("--method", c.lobes.method,
                    std::string(kStabilityMethodNames) +
                        " (overrides [lobes].method; zero-order and closed-form are one method: "
                        "in turning the closed form, in milling the averaged solution)");
  lobes->add_option("--threads", c.lobes.threads, "threads (default: all cores)")
      ->check(CLI::Range(0, kMaxThreads));
  lobes->add_option("--target-depth-mm", c.lobes.target_depth_mm,
                    "list the spindle-speed ranges that are stable at this depth and recommend "
                    "the speed with the widest margin");

  c.check_cmd = app.add_subcommand(
      "check",
      "one point: stable?, margin, chatter frequency. Exit status 0 for either verdict (the "
      "verdict is in the report and in --json \"stable\"), 2 for bad input");
  CLI::App* check = c.check_cmd;
  check->add_option("CASE", c.check.case_path, "case file (TOML), or a built-in example's name");
  check->add_option("--rpm", c.check.rpm, "spindle speed (rpm)")->required();
  check->add_option("--depth-mm", c.check.depth_mm, "depth (width) of cut (mm)")->required();
  check->add_option("--json", c.check.json, "write the result as JSON (- for standard output)");
  check->add_option("--method", c.check.method, "as for `lobes`");
}

void add_simulate_command(CLI::App& app, Commands& c) {
  c.sim_cmd = app.add_subcommand(
      "simulate", "time-domain simulation of the cut (turning, milling; sweeps for milling)");
  CLI::App* sim = c.sim_cmd;
  sim->add_option("CASE", c.sim.case_path, "case file (TOML), or a built-in example's name");
  add_outputs(sim, c.sim.outputs,
              "write the traces as CSV. Turning: process,time_s,displacement_um,force_n,"
              "chip_thickness_um; milling: time_s,fx_n,fy_n,force_n,x_um,y_um,teeth_in_cut,cutting_force_n; a "
              "sweep: the swept key and the metrics");
  sim->add_option("--rpm", c.sim.rpm, "spindle speed (rpm), overrides [simulate].rpm");
  sim->add_option("--depth-mm", c.sim.depth_mm, "depth of cut (mm), overrides [simulate].depth_mm");
  sim->add_option("--duration-s", c.sim.duration_s,
                  "simulated time (s), overrides [simulate].duration_s (turning) or revolutions "
                  "(milling)");
  sim->add_option("--sweep", c.sim.sweep,
                  "milling: vary one case key over a range, KEY=FROM:STEP:TO (e.g. "
                  "force_law.t2_s=0:0.05:1 or modes[0].damping_ratio=0.01:0.01:0.05), and "
                  "tabulate the summary at each value");
  std::string metrics;
  for (const std::string& m : app::milling_metric_names())
    metrics += (metrics.empty() ? "" : ", ") + m;
  sim->add_option("--metric", c.sim.metric,
                  "with --sweep: the metric to plot (" + metrics + "; default force_pulsation)");
  sim->add_option("--threads", c.sim.threads, "with --sweep: threads (default: all cores)")
      ->check(CLI::Range(0, kMaxThreads));
}

void add_drive_command(CLI::App& app, Commands& c) {
  c.drive_cmd = app.add_subcommand(
      "drive",
      "feed drives under the milling load: torque and speed ripple, kδ, δ, position error");
  CLI::App* drive = c.drive_cmd;
  drive->add_option("CASE", c.drive.case_path,
                    "case file (TOML) with [[drives]], or a built-in example's name");
  add_outputs(drive, c.drive.outputs,
              "write the traces as CSV: axis,time_s,axis_force_n,load_torque_nm,speed_rad_s,"
              "position_error_um,epsilon_um");
  drive->add_option("--rpm", c.drive.rpm, "spindle speed (rpm), overrides [simulate].rpm");
  drive->add_option("--depth-mm", c.drive.depth_mm, "axial depth of cut (mm)");
  drive->add_option("--currents", c.drive.currents,
                    "write the motor phase currents as CSV: time_s,axis,iu_a,iv_a,iw_a,"
                    "speed_rad_s,rotor_angle_rad (needs [drives] motor data)");
  drive
      ->add_option("--seed", c.drive.seed,
                   "seed of the current noise, for every axis (each axis draws its own "
                   "stream of it); overrides [[drives]] seed")
      ->check(CLI::Range(0, 2147483647));
  drive->add_option("--sweep", c.drive.sweep,
                    "vary one case key, KEY=FROM:STEP:TO (e.g. simulate.rpm=1000:500:20000)");
  std::string metrics;
  for (const std::string& m : app::drive_metric_names())
    metrics += (metrics.empty() ? "" : ", ") + m;
  drive->add_option("--metric", c.drive.metric,
                    "with --sweep: " + metrics + " (default epsilon_um)");
  drive->add_option("--threads", c.drive.threads, "with --sweep: threads (default: all cores)")
      ->check(CLI::Range(0, kMaxThreads));
}

void add_plan_and_force_commands(CLI::App& app, Commands& c) {
  c.plan_cmd =
      app.add_subcommand("plan", "two-edge face milling of a large bore: feeds, speeds, quality");
  CLI::App* plan = c.plan_cmd;
  plan->add_option("CASE", c.plan.case_path, "case file (TOML) with [bore], [cutter], [process]");
  plan->add_option("--json", c.plan.json, "write every quantity and the effective case as JSON");
  plan->add_option("--plot", c.plan.plot,
                   "the trade-off: main time and straightness against S0 and h (needs [limits])");
  plan->add_option("--axial-feed-mm", c.plan.axial_feed_mm,
                   "a fixed axial feed S0 (mm per blank revolution) instead of the largest");

  c.force_cmd = app.add_subcommand(
      "force", "cutting forces of a turning cut; the duty cycle of vibration-assisted cutting");
  CLI::App* force = c.force_cmd;
  force->add_option("CASE", c.force.case_path, "case file (TOML), or a built-in example's name");
  force->add_option("--json", c.force.json, "write the results as JSON");
  force->add_option("--plot", c.force.plot,
                    "the force pulses over three vibration periods, or with a [material] the "
                    "prediction against the uncut chip thickness");
}

void add_identify_command(CLI::App& app, Commands& c) {
  c.identify_cmd = app.add_subcommand(
      "identify",
      "milling cutting and edge coefficients (Kt, Kr, Kte, Kre) from the measured forces of test "
      "cuts at several feeds");
  CLI::App* identify = c.identify_cmd;
  identify
      ->add_option("CASE", c.identify.case_path,
                   "milling case file (TOML) with [tool] and [operation]: the cutter and the "
                   "engagement of the test cuts; or a built-in example's name")
      ->required();
  identify
      ->add_option("FORCES", c.identify.force_files,
                   "force files (CSV): mean forces feed_per_tooth_mm,depth_mm,fx_n,fy_n[,fz_n], "
                   "or one force record time_s,fx_n,fy_n[,fz_n] per feed with its cut in "
                   "comments (# feed_per_tooth_mm = , # depth_mm = , # rpm = ), or the output "
                   "of `cutdyn monitor estimate` (time_s,axis,force_n,…) with the same comments")
      ->required();
  add_outputs(identify, c.identify.outputs,
              "write the coefficients as a [cutting] table (TOML) to paste into the case, with "
              "their 95 % intervals as comments");
}

void add_fit_command(CLI::App& app, Commands& c) {
  c.fit_cmd = app.add_subcommand(
      "fit", "modes (natural frequency, damping ratio, stiffness) fitted to a measured FRF");
  CLI::App* fit = c.fit_cmd;
  fit->add_option("FILE", c.fit.file,
                  "the measured FRF: CutPro text (.frf), CSV or UFF 58/58b (docs/frf-files.md)")
      ->required();
  fit->add_option("--modes", c.fit.modes,
                  "number of modes, or auto (default): chosen from the stabilisation diagram");
  fit->add_option("--band", c.fit.band, "LO:HI, the band fitted in Hz (default: the whole table)");
  fit->add_option("--direction", c.fit.direction,
                  "x or y: where the modes act (default: a UFF file's response direction, else x)")
      ->check(CLI::IsMember({"x", "y"}));
  fit->add_option("--format", c.fit.format, "frf, csv or uff (default: from the content)");
  fit->add_option("--units", c.fit.units,
                  "CutPro text: the file's units in place of its header's, e.g. \"kHz, mm/N\"");
  add_outputs(fit, c.fit.outputs,
              "write the modes as [[modes]] tables (TOML) to paste into a case file");
}

// `cutdyn example [--list] [NAME]`: the built-in cases, each with its whole description (the
// comment lines it opens with).
int run_example(const Commands& c, std::ostream& out) {
  if (c.list || c.example_name.empty()) {
    for (const auto& [name, text] : io::examples()) {
      out << name << "\n";
      std::size_t at = 0;
      while (at < text.size() && text.compare(at, 2, "# ") == 0) {
        const std::size_t end = std::min(text.find('\n', at), text.size());
        out << "    " << text.substr(at + 2, end - at - 2) << "\n";
        at = end + 1;
      }
    }
    return 0;
  }
  const auto text = io::example_text(c.example_name);
  if (!text) io::load_example(c.example_name);  // throws the list of names
  out << *text;
  return 0;
}

// Runs the command that was parsed; an output file "-" sends the report to stderr.
int dispatch(Commands& c, CLI::App& app, std::ostream& out, std::ostream& err) {
  if (c.example->parsed()) return run_example(c, out);
  io::OutputTransaction::set_standard_output(&out);
  io::OutputTransaction::set_standard_error(&err);
  struct ResetStandardStreams {
    ~ResetStandardStreams() {
      io::OutputTransaction::set_standard_output(nullptr);
      io::OutputTransaction::set_standard_error(nullptr);
    }
  } reset_standard_streams;
  // The files the command reads, which none of its outputs may replace.
  io::InputScope inputs;
  std::ostream* report = &out;
  for (const CLI::App* sub : {c.lobes_cmd, c.check_cmd, c.sim_cmd, c.drive_cmd, c.plan_cmd,
                              c.force_cmd, c.identify_cmd, c.fit_cmd})
    if (sub->parsed() && writes_to_standard_output(*sub)) report = &err;
  if (c.lobes_cmd->parsed()) return run_lobes(c.lobes, *report, err);
  if (c.check_cmd->parsed()) return run_check(c.check, *report, err);
  if (c.sim_cmd->parsed()) return run_simulate(c.sim, *report, err);
  if (c.drive_cmd->parsed()) return run_drive(c.drive, *report, err);
  if (c.plan_cmd->parsed()) return run_plan(c.plan, *report, err);
  if (c.force_cmd->parsed()) return run_force(c.force, *report, err);
  if (c.identify_cmd->parsed()) return run_identify(c.identify, *report, err);
  if (c.fit_cmd->parsed()) return run_fit(c.fit, *report, err);
  if (const int code = c.run_monitor(out, err); code >= 0) return code;
  if (const int code = c.run_serve(out, err); code >= 0) return code;
  if (const int code = c.run_sweep(out, err); code >= 0) return code;
  err << app.help();
  return 2;
}

// Help asked for (exit 0, on stdout), or a parse error (exit 2); nullopt when parsing passed.
std::optional<int> parse(CLI::App& app, const std::vector<std::string>& args, std::ostream& out,
                         std::ostream& err) {
  std::vector<std::string> reversed(args.rbegin(), args.rend());
  try {
    app.parse(reversed);
  } catch (const CLI::CallForHelp&) {
    out << app.help();
    return 0;
  } catch (const CLI::CallForAllHelp&) {
    out << app.help("", CLI::AppFormatMode::All);
    return 0;
  } catch (const CLI::ParseError& e) {
    // Subcommand help comes through here as CallForHelp from the subcommand.
    if (e.get_exit_code() == 0) {
      for (CLI::App* sub : app.get_subcommands()) {
        out << sub->help();
        return 0;
      }
      out << app.help();
      return 0;
    }
    err << "cutdyn: error: command line: " << e.what() << "\n";
    err << "Run `cutdyn --help` for usage.\n";
    return 2;
  }
  return std::nullopt;
}

}  // namespace

int run(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  CLI::App app{
      "cutdyn: machining-process dynamics.\n"
      "  lobes, check    chatter stability of turning (conventional and ultrasonic-vibration-"
      "assisted)\n"
      "                  and milling (zero-order, multi-frequency, full discretization)\n"
      "  simulate        time-domain simulation of a turning or milling cut; sweeps of any case "
      "key\n"
      "  force           cutting forces of a turning cut, given or by Oxley's theory; the duty "
      "cycle\n"
      "  drive           feed drives under the milling load: ripple, kδ, position error, "
      "currents\n"
      "  fit             modes fitted to a measured FRF (CutPro .frf, CSV, UFF 58), for a case\n"
      "  identify        milling cutting and edge coefficients from measured forces\n"
      "  monitor         cutting force from servo-motor currents: calibrate, estimate, teach-in\n"
      "  plan            two-edge face milling of a large bore: feeds, speeds, quality\n"
      "  sweep           the lobes of every variant of a case (keys over values, files)\n"
      "  serve           the stability explorer in the browser\n"
      "Without CASE a command runs its built-in default case (see `cutdyn example --list`);\n"
      "fit and identify read measurements and need their files.",
      "cutdyn"};
  app.set_help_all_flag("--help-all", "print help for every command");
  bool version = false;
  app.add_flag("--version", version, "print the version");
  app.require_subcommand(0, 1);
  Commands c;
  c.example = app.add_subcommand("example", "print a built-in case file (--list: all, described)");
  c.example->add_flag("--list", c.list, "list the built-in cases with their descriptions");
  c.example->add_option("NAME", c.example_name, "the case to print");
  add_stability_commands(app, c);
  add_simulate_command(app, c);
  add_drive_command(app, c);
  add_plan_and_force_commands(app, c);
  add_identify_command(app, c);
  add_fit_command(app, c);
  c.run_monitor = add_monitor_command(app);
  c.run_serve = add_serve_command(app);
  c.run_sweep = add_sweep_command(app);
  if (const auto code = parse(app, args, out, err)) return *code;
  if (version) {
    out << "cutdyn " << CUTDYN_VERSION << "\n";
    return 0;
  }
  try {
    return dispatch(c, app, out, err);
  } catch (const InvalidInput& e) {
    const std::string where = e.where().empty() ? "input" : e.where();
    for (const std::string& problem : e.problems())
      err << "cutdyn: error: " << where << ": " << problem << "\n";
    return 2;
  } catch (const std::exception& e) {
    err << "cutdyn: error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace cutdyn::cli
