// Is a cut stable, and by how much? The `check` job of the library on a built-in example case
// (or a case file given as the first argument), as `cutdyn check` runs it.
#include <cstdio>

#include "cutdyn/app/case_models.hpp"
#include "cutdyn/app/stability.hpp"

int main(int argc, char** argv) {
  using namespace cutdyn;
  const io::Case c = app::load_case(argc > 1 ? argv[1] : "", "milling-insperger");
  app::CheckRequest request;
  request.rpm = 5000.0;
  request.depth_m = 0.04e-3;
  const app::CheckJobReport r = app::run_check(c, request);
  std::printf("%s\n%s at %.0f rpm and %.3f mm: critical depth %.4f mm (%s), margin %.3f\n",
              r.description.c_str(), r.stable ? "stable" : "unstable", r.rpm, r.depth_m * 1e3,
              r.boundary.depth_m * 1e3, r.method.c_str(), r.margin.value_or(0.0));
  return 0;
}
