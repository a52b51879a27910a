// cutdyn from C++: the cutting force on a feed axis from its servo-motor currents, estimated
// as the log arrives (docs/models/monitor.md). The log is made here: the x axis of the
// source's machine (the zheng2012 preset: KT for the RMS current, J, friction, KBlf) at
// 60 rad/s under a 2500 N cut, sampled at 1 kHz, the phase currents its torque balance needs.
// It is fed to the estimate job in chunks of 4 KiB, as from a pipe; the job calls back once
// per estimated sample. Prints the number of samples, the mean force over the last 0.1 s
// (N) and the estimate's −3 dB frequency (Hz). Built by the tests against the build tree and
// against an installed cutdyn (target_link_libraries(monitor_estimate PRIVATE cutdyn::app)).
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>

#include "cutdyn/app/monitor.hpp"
#include "cutdyn/core/units.hpp"

int main() {
  using namespace cutdyn;
  try {
    // The log: time_s (s), axis, iu_a iv_a iw_a (A), speed_rad_s (rad/s).
    const AxisModel x = zheng2012_axis('x');
    const double force_n = 2500.0, speed_rad_s = 60.0, dt_s = 1e-3;
    const double peak_a = std::sqrt(2.0) * x.equivalent_current_a(force_n, speed_rad_s, 0.0);
    std::string log = "time_s,axis,iu_a,iv_a,iw_a,speed_rad_s\n";
    for (int k = 0; k < 300; ++k) {
      const double t = k * dt_s, angle = 4.0 * speed_rad_s * t;  // 4 pole pairs
      char line[160];
      std::snprintf(line, sizeof line, "%.3f,x,%.9g,%.9g,%.9g,%.9g\n", t,
                    peak_a * std::cos(angle), peak_a * std::cos(angle - units::kTwoPi / 3),
                    peak_a * std::cos(angle + units::kTwoPi / 3), speed_rad_s);
      log += line;
    }

    app::EstimateOptions options;  // the estimate's filter at f_b = 50 Hz
    double sum_n = 0.0;
    int n = 0;
    app::EstimateJob::Sinks sinks;
    sinks.row = [&](const app::EstimatedRow& r) {
      if (r.row.time_s < 0.2) return;
      sum_n += r.estimate.force_n;
      ++n;
    };
    app::EstimateJob job(app::zheng2012_preset(), "zheng2012", options, std::nullopt, {}, "log",
                         sinks);
    for (std::size_t at = 0; at < log.size(); at += 4096)
      job.feed(std::string_view(log).substr(at, 4096));
    const app::EstimateReport report = job.finish();

    std::printf("samples,mean_force_n,minus_3db_hz\n%zu,%.1f,%.2f\n", report.samples, sum_n / n,
                report.axes.at(0).filter.minus_3db_hz);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "monitor_estimate: %s\n", e.what());
    return 2;
  }
}
