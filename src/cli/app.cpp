#include "cli/app.hpp"

#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>

#include "cli/commands.hpp"
#include "cutdyn/core/error.hpp"
#include "cutdyn/io/case_file.hpp"
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
      if (value == "-") return true;
  }
  return false;
}

}  // namespace

int run(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  CLI::App app{
      "cutdyn: machining-process dynamics. Chatter stability lobes, time-domain simulation and\n"
      "cutting forces for turning, conventional and ultrasonic-vibration-assisted.\n"
      "Without CASE a command runs its built-in default case (see `cutdyn example --list`).",
      "cutdyn"};
  app.set_help_all_flag("--help-all", "print help for every command");
  bool version = false;
  app.add_flag("--version", version, "print the version");
  app.require_subcommand(0, 1);

  // example
  auto* example = app.add_subcommand("example", "print a built-in case file");
  bool list = false;
  std::string example_name;
  example->add_flag("--list", list, "list the built-in cases");
  example->add_option("NAME", example_name, "the case to print");

  // lobes
  LobesArgs lobes;
  auto* lobes_cmd =
      app.add_subcommand("lobes", "stability lobes: critical depth against spindle speed");
  lobes_cmd->add_option("CASE", lobes.case_path, "case file (TOML)");
  add_outputs(lobes_cmd, lobes.outputs,
              "write the lobes as CSV: spindle_rpm,critical_depth_mm,chatter_hz,lobe,...");
  lobes_cmd->add_option("--method", lobes.method,
                        std::string(kStabilityMethodNames) +
                            " (overrides [lobes].method; zero-order and closed-form are one "
                            "method: in turning the closed form, in milling the averaged "
                            "solution)");
  lobes_cmd->add_option("--threads", lobes.threads, "threads (default: all cores)")
      ->check(CLI::Range(0, 1024));
  lobes_cmd->add_option("--target-depth-mm", lobes.target_depth_mm,
                        "list the spindle-speed ranges that are stable at this depth");

  // check
  CheckArgs check;
  auto* check_cmd = app.add_subcommand("check", "one point: stable?, margin, chatter frequency");
  check_cmd->add_option("CASE", check.case_path, "case file (TOML)");
  check_cmd->add_option("--rpm", check.rpm, "spindle speed (rpm)")->required();
  check_cmd->add_option("--depth-mm", check.depth_mm, "depth (width) of cut (mm)")->required();
  check_cmd->add_option("--json", check.json, "write the result as JSON");
  check_cmd->add_option("--method", check.method, "as for `lobes`");

  // simulate
  SimulateArgs sim;
  auto* sim_cmd = app.add_subcommand("simulate", "time-domain simulation of the cut");
  sim_cmd->add_option("CASE", sim.case_path, "case file (TOML)");
  add_outputs(sim_cmd, sim.outputs,
              "write the traces as CSV: process,time_s,displacement_um,force_n,chip_thickness_um");
  sim_cmd->add_option("--rpm", sim.rpm, "spindle speed (rpm), overrides [simulate].rpm");
  sim_cmd->add_option("--depth-mm", sim.depth_mm,
                      "depth of cut (mm), overrides [simulate].depth_mm");
  sim_cmd->add_option("--duration-s", sim.duration_s, "simulated time (s)");
  sim_cmd->add_option("--sweep", sim.sweep,
                      "milling: vary one case key over a range, KEY=FROM:STEP:TO (e.g. "
                      "force_law.t2_s=0:0.05:1), and tabulate the summary at each value");
  sim_cmd->add_option(
      "--metric", sim.metric,
      "with --sweep: the metric to plot (force_pulsation, mean_force_n, "
      "peak_force_n, mean_teeth_in_cut, vibration_pp_x_um, vibration_pp_y_um, "
      "chatter_indicator, contact_loss, surface_location_error_um; default force_pulsation)");
  sim_cmd->add_option("--threads", sim.threads, "with --sweep: threads (default: all cores)")
      ->check(CLI::Range(0, 1024));

  // drive
  DriveArgs drive;
  auto* drive_cmd = app.add_subcommand(
      "drive",
      "feed drives under the milling load: torque and speed ripple, kδ, δ, position error");
  drive_cmd->add_option("CASE", drive.case_path, "case file (TOML) with [[drives]]");
  add_outputs(drive_cmd, drive.outputs,
              "write the traces as CSV: axis,time_s,axis_force_n,load_torque_nm,speed_rad_s,"
              "position_error_um,epsilon_um");
  drive_cmd->add_option("--rpm", drive.rpm, "spindle speed (rpm), overrides [simulate].rpm");
  drive_cmd->add_option("--depth-mm", drive.depth_mm, "axial depth of cut (mm)");
  drive_cmd->add_option("--currents", drive.currents,
                        "write the motor phase currents as CSV: time_s,axis,iu_a,iv_a,iw_a,"
                        "speed_rad_s,rotor_angle_rad (needs [drives] motor data)");
  drive_cmd->add_option("--seed", drive.seed,
                        "seed of the current noise, for every axis (each axis draws its own "
                        "stream of it); overrides [[drives]] seed")
      ->check(CLI::Range(0, 2147483647));
  drive_cmd->add_option("--sweep", drive.sweep,
                        "vary one case key, KEY=FROM:STEP:TO (e.g. simulate.rpm=1000:500:20000)");
  drive_cmd->add_option("--metric", drive.metric,
                        "with --sweep: epsilon_um (default), drive_error_um, cutter_error_um, "
                        "k_delta, static_error, torque_ripple_nm, speed_ripple_rad_s");
  drive_cmd->add_option("--threads", drive.threads, "with --sweep: threads (default: all cores)")
      ->check(CLI::Range(0, 1024));

  // plan
  PlanArgs plan;
  auto* plan_cmd =
      app.add_subcommand("plan", "two-edge face milling of a large bore: feeds, speeds, quality");
  plan_cmd->add_option("CASE", plan.case_path, "case file (TOML) with [bore], [cutter], [process]");
  plan_cmd->add_option("--json", plan.json, "write every quantity and the effective case as JSON");
  plan_cmd->add_option(
      "--plot", plan.plot,
      "the trade-off: main time and straightness against S0 and h (needs [limits])");
  plan_cmd->add_option("--axial-feed-mm", plan.axial_feed_mm,
                       "a fixed axial feed S0 (mm per blank revolution) instead of the largest");

  // force
  ForceArgs force;
  auto* force_cmd =
      app.add_subcommand("force", "cutting forces, duty cycle of vibration-assisted cutting");
  force_cmd->add_option("CASE", force.case_path, "case file (TOML)");
  force_cmd->add_option("--json", force.json, "write the results as JSON");
  force_cmd->add_option("--plot", force.plot, "draw the force pulses over three vibration periods");

  // monitor calibrate | estimate | teach
  const auto run_monitor = add_monitor_command(app);

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
  if (version) {
    out << "cutdyn " << CUTDYN_VERSION << "\n";
    return 0;
  }

  try {
    if (example->parsed()) {
      if (list || example_name.empty()) {
        for (const auto& [name, text] : io::examples()) {
          // First comment line is the description.
          std::string first(text.substr(0, text.find('\n')));
          if (first.rfind("# ", 0) == 0) first = first.substr(2);
          out << name << "\n    " << first << "\n";
        }
        return 0;
      }
      const auto text = io::example_text(example_name);
      if (!text) io::load_example(example_name);  // throws the list of names
      out << *text;
      return 0;
    }
    // An output file given as "-" goes to standard output; the report then goes to stderr.
    io::OutputTransaction::set_standard_output(&out);
    struct ResetStandardOutput {
      ~ResetStandardOutput() { io::OutputTransaction::set_standard_output(nullptr); }
    } reset_standard_output;
    std::ostream* report = &out;
    for (const CLI::App* sub : {lobes_cmd, check_cmd, sim_cmd, drive_cmd, plan_cmd, force_cmd})
      if (sub->parsed() && writes_to_standard_output(*sub)) report = &err;
    if (lobes_cmd->parsed()) return run_lobes(lobes, *report, err);
    if (check_cmd->parsed()) return run_check(check, *report, err);
    if (sim_cmd->parsed()) return run_simulate(sim, *report, err);
    if (drive_cmd->parsed()) return run_drive(drive, *report, err);
    if (plan_cmd->parsed()) return run_plan(plan, *report, err);
    if (force_cmd->parsed()) return run_force(force, *report, err);
    if (const int code = run_monitor(out, err); code >= 0) return code;
    err << app.help();
    return 2;
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
