// cutdyn from C++: the milling stability lobes of the Insperger–Stépán benchmark (two straight
// teeth, one 922 Hz mode in x and in y, slotting, down-milling) at ten speeds, with the full
// discretization, printed as CSV. Built by the tests (against the build tree) and, as a
// consumer of an installed cutdyn, by the install test:
//     find_package(cutdyn REQUIRED)
//     target_link_libraries(milling_lobes PRIVATE cutdyn::cutdyn)
#include <cstdio>
#include <exception>

#include "cutdyn/core/units.hpp"
#include "cutdyn/stability/lobes.hpp"
#include "cutdyn/stability/milling.hpp"

int main() {
  using namespace cutdyn;
  try {
    MillingProcess m;
    const double wn = units::hz_to_rad_per_s(922.0), mass = 0.03993;
    for (Direction d : {Direction::kX, Direction::kY})
      m.modal.modes.push_back(Mode{d, wn, 0.011, mass * wn * wn});
    m.cutting.kt_pa = 600e6;
    m.cutting.kr_pa = 200e6;
    m.tool.teeth = 2;
    m.engagement.radial_immersion = 1.0;
    m.engagement.down_milling = true;

    MillingStabilityOptions stability;  // full discretization
    stability.depth_max_m = 1e-3;
    LobesOptions grid;
    grid.rpm_min = 5000.0;
    grid.rpm_max = 25000.0;
    grid.rpm_steps = 10;
    grid.refine = false;
    const LobesReport lobes = trace_lobes(
        [&](double rpm) {
          const MillingBoundary b = milling_critical_depth(m, rpm, stability);
          return LobePoint{rpm, b.boundary, 1.0, b.lobe};
        },
        grid);
    std::printf("spindle_rpm,critical_depth_mm,chatter_hz,bifurcation\n");
    for (const LobePoint& p : lobes.points)
      std::printf("%.1f,%.6f,%.2f,%s\n", p.rpm, units::m_to_mm(p.boundary.depth_m),
                  p.boundary.chatter_hz, to_string(p.boundary.bifurcation));
    return lobes.status == LobesStatus::kSuccess ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "milling_lobes: %s\n", e.what());
    return 2;
  }
}
