// The monitor's band file (`monitor teach` writes it, `estimate --band` reads it): read_band on
// the input as a file (its JSON, then band_from_json, which the Python module calls on a dict);
// what was accepted must load again once written and must work in the alarm monitor (a few
// samples through each axis' AlarmMonitor).
#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "cutdyn/app/monitor_files.hpp"
#include "cutdyn/monitor/force_band.hpp"
#include "fuzz_common.hpp"
#include "fuzz_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string& path = cutdyn::fuzz::write_input(data, size, ".json");
  cutdyn::app::BandFile band;
  try {
    band = cutdyn::app::read_band(path);
  } catch (const cutdyn::InvalidInput&) {
    return 0;
  }
  try {
    (void)cutdyn::app::band_from_json(cutdyn::app::band_json(band), "again");
    for (const auto& [axis, b] : band.axes) {
      cutdyn::AlarmMonitor monitor(b);
      // Samples across more than one cycle, forces from zero to beyond the band.
      const double step = b.cycle_s > 0.0 ? b.cycle_s / 16.0 : 1e-3;
      for (int i = 0; i < 40; ++i) (void)monitor.update(i * step, 100.0 * (i % 7));
    }
  } catch (const cutdyn::InvalidInput&) {
    cutdyn::fuzz::fail("a band that was read is refused when written again or monitored");
  }
  return 0;
}
