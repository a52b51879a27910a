// `cutdyn fit`: modes fitted to a measured FRF file (docs/models/modal-fitting.md).
#include <cmath>
#include <string>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cutdyn/app/fit.hpp"
#include "cutdyn/app/render.hpp"
#include "cutdyn/app/report_json.hpp"
#include "cutdyn/io/output.hpp"
#include "cutdyn/io/plot.hpp"

namespace cutdyn::cli {
namespace {

// "--modes auto" or a whole number; "--band LO:HI" in Hz.
app::FitRequest fit_request(const FitArgs& args) {
  app::FitRequest r;
  r.file = args.file;
  Validator v;
  if (args.modes != "auto") {
    std::size_t used = 0;
    int n = 0;
    try {
      n = std::stoi(args.modes, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != args.modes.size() || n < 1 || n > kMaxFitModes)
      v.add("--modes = " + args.modes + ": must be auto or a whole number from 1 to " +
            std::to_string(kMaxFitModes));
    r.fit.modes = n;
  }
  if (!args.band.empty()) {
    const auto colon = args.band.find(':');
    double lo = 0.0, hi = 0.0;
    bool ok = colon != std::string::npos;
    try {
      std::size_t a = 0, b = 0;
      lo = std::stod(args.band.substr(0, colon), &a);
      hi = std::stod(args.band.substr(colon + 1), &b);
      ok = ok && a == colon && b == args.band.size() - colon - 1;
    } catch (const std::exception&) {
      ok = false;
    }
    if (!ok || !std::isfinite(lo) || !std::isfinite(hi) || lo < 0.0 || hi <= lo)
      v.add("--band = " + args.band + ": must be LO:HI in Hz with 0 <= LO < HI");
    r.fit.lo_hz = lo;
    r.fit.hi_hz = hi;
  }
  if (!args.format.empty()) {
    r.file_options.format = parse_frf_format(args.format);
    if (!r.file_options.format) v.add("--format = " + args.format + ": must be frf, csv or uff");
  }
  if (!args.units.empty()) r.file_options.units = args.units;
  if (!args.direction.empty()) r.direction = args.direction == "y" ? Direction::kY : Direction::kX;
  v.throw_if_any("command line");
  return r;
}

}  // namespace

int run_fit(const FitArgs& args, std::ostream& out, std::ostream& err) {
  check_outputs(args.outputs, {args.file});
  const app::FitRequest request = fit_request(args);
  const app::FitJobReport r = app::run_fit(request);
  // A modes file without modes would stand for a structure with none: nothing is written.
  if (r.fit.modes.empty() && !args.outputs.csv.empty())
    throw InvalidInput(
        {"--out = " + args.outputs.csv + ": no mode found in the band " + human(r.fit.lo_hz) + "–" +
         human(r.fit.hi_hz) + " Hz, so no [[modes]] to write" +
         (args.band.empty() ? "" : " (widen --band " + args.band + "?)")},
        r.source);
  app::write_text(out, r);
  for (const std::string& w : r.warnings)
    err << "cutdyn: warning: " << r.source << ": " << w << "\n";
  io::OutputTransaction outputs;
  if (!args.outputs.csv.empty()) outputs.open(args.outputs.csv) << app::modes_toml(r);
  if (!args.outputs.json.empty()) io::write_json(outputs.open(args.outputs.json), app::to_json(r));
  if (!args.outputs.plot.empty()) io::write_plot(app::figure(r), args.outputs.plot, outputs);
  commit_outputs(outputs, args.outputs, out);
  return 0;
}

}  // namespace cutdyn::cli
