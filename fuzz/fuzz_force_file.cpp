// Force files for `cutdyn identify` (mean forces, a force record, the monitor's estimate):
// parse_force_file, then the fit of the coefficients to what it read (a slot with two teeth),
// which takes the file's numbers as they are.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "cutdyn/forces/identify.hpp"
#include "cutdyn/io/force_file.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  cutdyn::fuzz::expect_invalid_input_only([&] {
    const std::vector<cutdyn::MeanForce> samples =
        cutdyn::io::parse_force_file(cutdyn::fuzz::text_of(data, size), "fuzz");
    (void)cutdyn::identify_coefficients(cutdyn::IdentifyCut{}, samples);
  });
  return 0;
}
