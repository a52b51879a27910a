#include "cli/common.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <variant>

#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/io/output.hpp"
#include "cutdyn/io/plot.hpp"
#include "cutdyn/stability/advice.hpp"

namespace cutdyn::cli {

io::Case load_case(const std::string& path, std::string_view default_example, std::ostream& err) {
  io::Case c = app::load_case(path, default_example);
  for (const std::string& w : c.warnings)
    err << "cutdyn: warning: " << c.source << ": " << w << "\n";
  return c;
}

std::string oxley_summary(const io::Case& c, const OxleyPrediction& p) {
  return fmt::format(
      "Kc and Kt predicted by Oxley's theory with Johnson–Cook flow stress: {} at {} m/min, "
      "h = {} mm, rake {}°",
      c.material->name, human(units::m_per_s_to_m_per_min(p.cut.speed_m_per_s)),
      human(units::m_to_mm(p.cut.uncut_chip_thickness_m)),
      human(units::rad_to_deg(p.cut.rake_rad)));
}

void check_output_folder(Validator& v, const char* flag, const std::string& path) {
  if (path.empty()) return;
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  if (!parent.empty() && !std::filesystem::is_directory(parent))
    v.add(std::string(flag) + " = " + path + ": the folder " + parent.string() + " does not exist");
}

app::RequestNames flag_names() {
  app::RequestNames n;
  n.where = "command line";
  n.rpm = "--rpm";
  n.depth = "--depth-mm";
  n.duration = "--duration-s";
  n.method = "--method";
  n.torque_constant = "--kt";
  n.inertia = "--inertia";
  n.base = "--base";
  n.idle = "--idle";
  n.loaded = "--loaded";
  n.measure = "--measure";
  n.bandwidth = "--bandwidth-hz";
  return n;
}

void check_outputs(const Outputs& o) {
  if (!o.plot.empty()) io::check_figure_path(o.plot);
  Validator v;
  check_output_folder(v, "--out", o.csv);
  check_output_folder(v, "--json", o.json);
  check_output_folder(v, "--plot", o.plot);
  const auto same = [](const std::string& a, const std::string& b) {
    return !a.empty() && !b.empty() &&
           std::filesystem::weakly_canonical(a) == std::filesystem::weakly_canonical(b);
  };
  if (same(o.csv, o.json) || same(o.csv, o.plot) || same(o.json, o.plot))
    v.add("--out, --json and --plot must name different files");
  v.throw_if_any("command line");
}

std::string depth_text(const CriticalDepth& b) {
  const std::string mm = human(units::m_to_mm(b.depth_m)) + " mm";
  return b.found ? mm : "> " + mm;
}

void commit_outputs(io::OutputTransaction& outputs, const Outputs& o, std::ostream& out) {
  outputs.commit();
  for (const std::string* f : {&o.csv, &o.json, &o.plot})
    if (!f->empty()) out << "  wrote " << (*f == "-" ? "standard output" : *f) << "\n";
}

void report_check(const io::Case& c, const CheckArgs& args, const app::CheckJobReport& r,
                  std::ostream& out) {
  const CriticalDepth& b = r.boundary;
  out << "cutdyn check: " << c.source << " at " << human(args.rpm) << " rpm, depth "
      << human(args.depth_mm) << " mm\n";
  out << "  " << r.description << "\n";
  out << "  " << (r.stable ? "STABLE" : "UNSTABLE (chatter)") << "\n";
  out << "  critical depth " << depth_text(b) << " (" << r.method << ")";
  if (b.found)
    out << ", " << to_string(b.bifurcation) << " at " << human(b.chatter_hz, 5) << " Hz, lobe "
        << r.lobe;
  if (!r.margin)
    out << "\n  no depth margin: unstable at any depth\n";
  else
    out << "\n  depth margin " << (b.found ? "" : "more than ") << human(100.0 * *r.margin, 3)
        << " % of the critical depth\n";
  if (b.truncated)
    out << "  warning: " << r.method
        << " could not cover every mode at this speed; the critical depth may be wrong\n";
  if (r.duty_cycle && r.conventional) out << "  duty cycle " << human(*r.duty_cycle) << "\n";
  if (r.conventional)
    out << "  conventional turning: critical depth " << depth_text(r.conventional->boundary) << ", "
        << (r.conventional->stable ? "stable" : "unstable") << " at this depth\n";
  for (const std::string& w : r.warnings) out << "  warning: " << w << "\n";
  if (args.json.empty()) return;
  io::OutputTransaction outputs;
  io::write_json(outputs.open(args.json), app::to_json(c, r));
  outputs.commit();
  out << "  wrote " << args.json << "\n";
}

std::function<void(int, int)> progress_reporter(std::ostream& err, std::string label) {
  if (!isatty(STDERR_FILENO)) return {};
  return [&err, label](int done, int total) {
    err << "\r" << label << ": " << done << "/" << total << (done == total ? "\n" : "")
        << std::flush;
  };
}

}  // namespace cutdyn::cli
