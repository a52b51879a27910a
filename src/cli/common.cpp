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

void report_lobes(const io::Case& c, const app::LobesJobReport& view, const Outputs& outputs_args,
                  std::ostream& out, std::ostream& err) {
  using nlohmann::json;
  using units::m_to_mm;
  const LobesReport& report = view.lobes;
  if (report.status != LobesStatus::kSuccess) err << "cutdyn: warning: " << report.message << "\n";
  for (const std::string& w : view.warnings) err << "cutdyn: warning: " << w << "\n";
  const auto& pts = report.points;
  const auto* ref = view.reference.empty() ? nullptr : &view.reference;
  const std::size_t lowest = view.lowest;

  out << "cutdyn lobes: " << c.source << "\n";
  out << "  " << view.description << "\n";
  out << fmt::format("  method {}, {} speeds {}–{} rpm, depth limit {} mm, {:.2f} s\n", view.method,
                     pts.size(), human(report.options.rpm_min), human(report.options.rpm_max),
                     human(m_to_mm(view.depth_max_m)), report.seconds);
  out << "\n";
  std::string header = fmt::format("  {:>11}  {:>17}  {:>10}  {:>4}  {:>11}", "spindle_rpm",
                                   "critical_depth_mm", "chatter_hz", "lobe", "bifurcation");
  if (view.duty_cycle) header += fmt::format("  {:>10}", "duty_cycle");
  if (ref) header += fmt::format("  {:>21}", "conventional_depth_mm");
  out << header << "\n";
  const std::size_t stride = std::max<std::size_t>(1, (pts.size() + 19) / 20);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (i % stride != 0 && i + 1 != pts.size()) continue;
    const LobePoint& p = pts[i];
    std::string row = fmt::format("  {:>11.1f}  {:>16.4f}{}  {:>10.2f}  {:>4}  {:>11}", p.rpm,
                                  m_to_mm(p.boundary.depth_m), p.boundary.found ? ' ' : '+',
                                  p.boundary.chatter_hz, p.lobe, to_string(p.boundary.bifurcation));
    if (view.duty_cycle) row += fmt::format("  {:>10.4f}", p.duty_cycle);
    if (ref)
      row += fmt::format("  {:>20.4f}{}", m_to_mm((*ref)[i].depth_m), (*ref)[i].found ? ' ' : '+');
    out << row << "\n";
  }
  if (stride > 1) out << "  (every " << stride << "th speed shown; --out F.csv writes them all)\n";
  if (std::any_of(pts.begin(), pts.end(), [](const LobePoint& p) { return !p.boundary.found; }))
    out << "  + stable up to the depth limit at that speed\n";
  out << "\n  lowest critical depth " << depth_text(pts[lowest].boundary) << " at "
      << human(pts[lowest].rpm) << " rpm\n";
  const auto& pockets = view.pockets;
  if (!pockets.empty()) {
    out << "  stable pockets (local maxima):";
    for (std::size_t k = 0; k < pockets.size(); ++k)
      out << (k ? ";" : "") << " " << human(pts[pockets[k]].rpm) << " rpm, "
          << depth_text(pts[pockets[k]].boundary);
    out << "\n";
  }

  // Speed ranges stable at the target depth, and the speed with the widest margin in speed
  // and depth (stability/advice).
  json ranges = json::array();
  const SpeedAdvice& advice = view.advice;
  if (view.target_depth_m) {
    const double target = *view.target_depth_m;
    out << "\n  stable at " << human(m_to_mm(target)) << " mm:";
    for (const SpeedRange& r : view.stable_ranges) {
      out << (ranges.empty() ? " " : "; ") << human(r.rpm_from) << "–" << human(r.rpm_to) << " rpm";
      ranges.push_back({{"rpm_from", r.rpm_from}, {"rpm_to", r.rpm_to}});
    }
    if (ranges.empty()) {
      out << " no speed of the lobes\n";
    } else if (advice.found) {
      const LobePoint& p = pts[advice.index];
      out << "\n  recommended: " << human(advice.rpm) << " rpm (in " << human(advice.range.rpm_from)
          << "–" << human(advice.range.rpm_to) << " rpm, critical depth " << depth_text(p.boundary)
          << "): stable with the speed " << human(100.0 * advice.margin, 2) << " % (±"
          << human(advice.margin * advice.rpm, 3) << " rpm) off and the depth "
          << human(100.0 * advice.margin, 2) << " % larger\n";
    }
  }
  // One row of named values per speed, shared by the CSV and the JSON.
  std::vector<std::string> columns{"spindle_rpm", "critical_depth_mm", "chatter_hz",
                                   "lobe",        "bifurcation",       "beyond_limit"};
  if (view.duty_cycle) columns.push_back("duty_cycle");
  if (ref) columns.insert(columns.end(), {"conventional_depth_mm", "conventional_chatter_hz"});
  const auto row = [&](std::size_t i) {
    const LobePoint& p = pts[i];
    std::vector<io::CsvCell> cells{p.rpm,
                                   m_to_mm(p.boundary.depth_m),
                                   p.boundary.chatter_hz,
                                   static_cast<long long>(p.lobe),
                                   std::string(to_string(p.boundary.bifurcation)),
                                   static_cast<long long>(p.boundary.found ? 0 : 1)};
    if (view.duty_cycle) cells.emplace_back(p.duty_cycle);
    if (ref) {
      cells.emplace_back(m_to_mm((*ref)[i].depth_m));
      cells.emplace_back((*ref)[i].chatter_hz);
    }
    return cells;
  };

  io::OutputTransaction outputs;
  if (!outputs_args.csv.empty()) {
    io::CsvWriter csv(outputs.open(outputs_args.csv), columns);
    for (std::size_t i = 0; i < pts.size(); ++i) csv.row(row(i));
  }
  if (!outputs_args.json.empty()) {
    json points = json::array();
    for (std::size_t i = 0; i < pts.size(); ++i) {
      json j = json::object();
      const auto cells = row(i);
      for (std::size_t k = 0; k < columns.size(); ++k)
        std::visit([&](const auto& v) { j[columns[k]] = v; }, cells[k]);
      j["beyond_limit"] = !pts[i].boundary.found;
      points.push_back(std::move(j));
    }
    json doc{{"command", "lobes"},
             {"case", io::to_json(c)},
             {"source", c.source},
             {"method", view.method},
             {"seconds", report.seconds},
             {"evaluations", report.evaluations},
             {"lowest",
              {{"spindle_rpm", pts[lowest].rpm},
               {"critical_depth_mm", m_to_mm(pts[lowest].boundary.depth_m)}}},
             {"points", std::move(points)}};
    if (report.status != LobesStatus::kSuccess) doc["warning"] = report.message;
    if (!view.warnings.empty()) doc["warnings"] = view.warnings;
    if (view.target_depth_m) {
      doc["target_depth_mm"] = m_to_mm(*view.target_depth_m);
      doc["stable_ranges"] = ranges;
      if (advice.found) {
        doc["recommended_rpm"] = advice.rpm;
        doc["recommended_margin"] = advice.margin;
        doc["recommended_range"] = {{"rpm_from", advice.range.rpm_from},
                                    {"rpm_to", advice.range.rpm_to}};
      }
    }
    io::write_json(outputs.open(outputs_args.json), doc);
  }
  if (!outputs_args.plot.empty()) {
    io::PlotSpec spec;
    spec.title = view.title;
    spec.x_label = "spindle speed (rpm)";
    spec.y_label = "critical depth of cut (mm)";
    spec.y_min = 0.0;
    spec.y_max = m_to_mm(view.depth_max_m);
    io::PlotSeries main{view.label, {}, {}, "stable-region"};
    io::PlotSeries reference{view.reference_label, {}, {}, "lines"};
    for (std::size_t i = 0; i < pts.size(); ++i) {
      main.x.push_back(pts[i].rpm);
      main.y.push_back(m_to_mm(pts[i].boundary.depth_m));
      if (ref) {
        reference.x.push_back(pts[i].rpm);
        reference.y.push_back(m_to_mm((*ref)[i].depth_m));
      }
    }
    spec.series.push_back(std::move(main));
    if (ref) spec.series.push_back(std::move(reference));
    io::write_plot(spec, outputs_args.plot, outputs);
  }
  commit_outputs(outputs, outputs_args, out);
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
    out << "  conventional turning: critical depth " << depth_text(r.conventional->boundary)
        << ", " << (r.conventional->stable ? "stable" : "unstable") << " at this depth\n";
  for (const std::string& w : r.warnings) out << "  warning: " << w << "\n";
  if (args.json.empty()) return;
  io::OutputTransaction outputs;
  nlohmann::json doc{{"command", "check"},         {"case", io::to_json(c)},
                     {"source", c.source},         {"method", r.method},
                     {"spindle_rpm", args.rpm},    {"depth_mm", args.depth_mm},
                     {"stable", r.stable},         {"critical_depth_mm", units::m_to_mm(b.depth_m)},
                     {"beyond_limit", !b.found},   {"margin", nullptr},
                     {"chatter_hz", b.chatter_hz}, {"bifurcation", to_string(b.bifurcation)},
                     {"lobe", r.lobe}};
  if (r.margin) doc["margin"] = *r.margin;
  if (b.truncated) doc["warning"] = "the method could not cover every mode at this speed";
  if (r.duty_cycle) doc["duty_cycle"] = *r.duty_cycle;
  if (r.conventional)
    doc["conventional"] = {{"critical_depth_mm", units::m_to_mm(r.conventional->boundary.depth_m)},
                           {"chatter_hz", r.conventional->boundary.chatter_hz},
                           {"stable", r.conventional->stable}};
  if (!r.warnings.empty()) doc["warnings"] = r.warnings;
  io::write_json(outputs.open(args.json), doc);
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
