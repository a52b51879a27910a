// The stability reports rendered: the text and figure of `cutdyn lobes` (the summary table,
// the lowest depth, stable pockets, the speeds stable at a target depth) and the verdict of
// `cutdyn check` (docs/models/turning.md, docs/models/milling-stability.md).
#include <fmt/format.h>

#include <algorithm>

#include "cutdyn/app/detail/render_text.hpp"
#include "cutdyn/app/detail/text.hpp"
#include "cutdyn/app/render.hpp"
#include "cutdyn/core/units.hpp"

namespace cutdyn::app {
namespace {

using units::m_to_mm;

const std::vector<CriticalDepth>* reference_of(const LobesJobReport& r) {
  return r.reference.empty() ? nullptr : &r.reference;
}

// Every speed up to 20 rows (then every n-th), with the marks below the table.
void print_table(const LobesJobReport& r, std::ostream& out) {
  const auto& pts = r.lobes.points;
  const auto* ref = reference_of(r);
  std::string header = fmt::format("  {:>11}  {:>17}  {:>10}  {:>4}  {:>11}", "spindle_rpm",
                                   "critical_depth_mm", "chatter_hz", "lobe", "bifurcation");
  if (r.duty_cycle) header += fmt::format("  {:>10}", "duty_cycle");
  if (ref) header += fmt::format("  {:>21}", "conventional_depth_mm");
  out << header << "\n";
  const std::size_t stride = std::max<std::size_t>(1, (pts.size() + 19) / 20);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (i % stride != 0 && i + 1 != pts.size()) continue;
    const LobePoint& p = pts[i];
    std::string row = fmt::format("  {:>11.1f}  {:>16.4f}{}  {:>10.2f}  {:>4}  {:>11}", p.rpm,
                                  m_to_mm(p.boundary.depth_m), p.boundary.found ? ' ' : '+',
                                  p.boundary.chatter_hz, p.lobe, to_string(p.boundary.bifurcation));
    if (r.duty_cycle) row += fmt::format("  {:>10.4f}", p.duty_cycle);
    if (ref)
      row += fmt::format("  {:>20.4f}{}", m_to_mm((*ref)[i].depth_m), (*ref)[i].found ? ' ' : '+');
    out << row << "\n";
  }
  if (stride > 1) out << "  (one speed in " << stride << " shown; --out F.csv writes them all)\n";
  if (std::any_of(pts.begin(), pts.end(), [](const LobePoint& p) { return !p.boundary.found; }))
    out << "  + stable up to the depth limit at that speed\n";
}

// The lowest depth, the pockets and, at a target depth, the stable speeds and the advice.
void print_findings(const LobesJobReport& r, std::ostream& out) {
  const auto& pts = r.lobes.points;
  out << "\n  lowest critical depth " << depth_text(pts[r.lowest].boundary) << " at "
      << human(pts[r.lowest].rpm) << " rpm\n";
  if (!r.pockets.empty()) {
    out << "  stable pockets (local maxima; 90 % of the depth over):";
    for (std::size_t k = 0; k < r.pockets.size(); ++k) {
      const SpeedRange w = pocket_width(pts, r.pockets[k]);
      out << (k ? ";" : "") << " " << human(pts[r.pockets[k]].rpm) << " rpm, "
          << depth_text(pts[r.pockets[k]].boundary) << " (" << human(w.rpm_from) << "–"
          << human(w.rpm_to) << " rpm)";
    }
    out << "\n";
  }
  if (!r.target_depth_m) return;
  out << "\n  stable at " << human(m_to_mm(*r.target_depth_m)) << " mm:";
  for (std::size_t k = 0; k < r.stable_ranges.size(); ++k)
    out << (k == 0 ? " " : "; ") << human(r.stable_ranges[k].rpm_from) << "–"
        << human(r.stable_ranges[k].rpm_to) << " rpm";
  const SpeedAdvice& advice = r.advice;
  if (r.stable_ranges.empty()) {
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

}  // namespace

void write_text(std::ostream& out, const io::Case& c, const LobesJobReport& r) {
  out << "cutdyn lobes: " << c.source << "\n";
  out << "  " << r.description << "\n";
  out << fmt::format("  method {}, {} speeds {}–{} rpm, depth limit {} mm, {:.2f} s\n", r.method,
                     r.lobes.points.size(), human(r.lobes.options.rpm_min),
                     human(r.lobes.options.rpm_max), human(m_to_mm(r.depth_max_m)),
                     r.lobes.seconds);
  out << "\n";
  print_table(r, out);
  print_findings(r, out);
}

io::PlotSpec figure(const LobesJobReport& r) {
  const auto& pts = r.lobes.points;
  const auto* ref = reference_of(r);
  io::PlotSpec spec;
  spec.title = r.title;
  spec.x_label = "spindle speed (rpm)";
  spec.y_label = "critical depth of cut (mm)";
  io::PlotSeries main{r.label, {}, {}, "stable-region"};
  io::PlotSeries reference{r.reference_label, {}, {}, "lines"};
  // The kinds of boundary told apart: Hopf the line itself, flip and fold marked on it.
  io::PlotSeries flip{"flip boundary (period doubling)", {}, {}, "points"};
  io::PlotSeries fold{"fold boundary (a multiplier at +1)", {}, {}, "points"};
  double top = 0.0;
  bool limit_reached = false;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const double depth = m_to_mm(pts[i].boundary.depth_m);
    main.x.push_back(pts[i].rpm);
    main.y.push_back(depth);
    top = std::max(top, depth);
    limit_reached = limit_reached || !pts[i].boundary.found;
    if (pts[i].boundary.found && pts[i].boundary.bifurcation == Bifurcation::kFlip) {
      flip.x.push_back(pts[i].rpm);
      flip.y.push_back(depth);
    } else if (pts[i].boundary.found && pts[i].boundary.bifurcation == Bifurcation::kFold) {
      fold.x.push_back(pts[i].rpm);
      fold.y.push_back(depth);
    }
    if (ref) {
      reference.x.push_back(pts[i].rpm);
      reference.y.push_back(m_to_mm((*ref)[i].depth_m));
      top = std::max(top, reference.y.back());
      limit_reached = limit_reached || !(*ref)[i].found;
    }
  }
  const double limit = m_to_mm(r.depth_max_m);
  if (r.target_depth_m) top = std::max(top, m_to_mm(*r.target_depth_m));
  // The depth axis fits the lobes; the search's limit is drawn only where a speed reaches it.
  spec.y_min = 0.0;
  spec.y_max = limit_reached || !(top > 0.0) ? limit : std::min(limit, 1.15 * top);
  spec.series.push_back(std::move(main));
  if (ref) spec.series.push_back(std::move(reference));
  if (!flip.x.empty()) spec.series.push_back(std::move(flip));
  if (!fold.x.empty()) spec.series.push_back(std::move(fold));
  if (limit_reached && !pts.empty())
    spec.series.push_back({"depth limit of the search (lobes.depth_max_mm): stable up to it",
                           {pts.front().rpm, pts.back().rpm},
                           {limit, limit},
                           "dashed"});
  if (r.target_depth_m && !pts.empty()) {
    const double target = m_to_mm(*r.target_depth_m);
    spec.series.push_back(
        {"target depth", {pts.front().rpm, pts.back().rpm}, {target, target}, "dashed"});
    if (r.advice.found)
      spec.series.push_back({"recommended speed " + human(r.advice.rpm, 5) + " rpm",
                             {r.advice.rpm},
                             {target},
                             "marker"});
  }
  return spec;
}

void write_text(std::ostream& out, const io::Case& c, const CheckJobReport& r) {
  const CriticalDepth& b = r.boundary;
  out << "cutdyn check: " << c.source << " at " << human(r.rpm) << " rpm, depth "
      << human(m_to_mm(r.depth_m)) << " mm\n";
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
  if (b.unconverged)
    out << "  warning: the critical depth still moved by more than the tolerance when the time "
           "step was halved; it may be off by more\n";
  if (r.duty_cycle && r.conventional) out << "  duty cycle " << human(*r.duty_cycle) << "\n";
  if (r.conventional)
    out << "  conventional turning: critical depth " << depth_text(r.conventional->boundary) << ", "
        << (r.conventional->stable ? "stable" : "unstable") << " at this depth\n";
  for (const std::string& w : r.warnings) out << "  warning: " << w << "\n";
}

}  // namespace cutdyn::app
