// The monitor's calibration file (`monitor calibrate` writes it; `estimate` and `teach` read
// it): read_calibration on the input as a file (its JSON, then calibration_from_json, which the
// Python module calls on a dict), and what was accepted written and read again (the writer's
// file must load).
#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "cutdyn/app/monitor_files.hpp"
#include "fuzz_common.hpp"
#include "fuzz_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string& path = cutdyn::fuzz::write_input(data, size, ".json");
  cutdyn::app::Calibration calibration;
  try {
    calibration = cutdyn::app::read_calibration(path);
  } catch (const cutdyn::InvalidInput&) {
    return 0;
  }
  try {
    (void)cutdyn::app::calibration_from_json(cutdyn::app::calibration_json(calibration), "again");
  } catch (const cutdyn::InvalidInput&) {
    cutdyn::fuzz::fail("a calibration that was read, written again, is refused");
  }
  return 0;
}
