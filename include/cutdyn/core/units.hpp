// Unit conversions. The library is SI inside (m, s, kg, N, rad); these are used at the
// edges (io, cli) and in tests. A name ending in a unit says what it takes or gives.
#pragma once

#include <numbers>

namespace cutdyn::units {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kTwoPi = 2.0 * std::numbers::pi;

constexpr double rpm_to_rad_per_s(double rpm) { return rpm * kTwoPi / 60.0; }
constexpr double rad_per_s_to_rpm(double w) { return w * 60.0 / kTwoPi; }
constexpr double rpm_to_rev_period_s(double rpm) { return 60.0 / rpm; }
constexpr double hz_to_rad_per_s(double hz) { return hz * kTwoPi; }
constexpr double rad_per_s_to_hz(double w) { return w / kTwoPi; }
// Divisions, not products with 1e-3, so that e.g. 30 mm is exactly the double nearest 0.03 m.
constexpr double mm_to_m(double mm) { return mm / 1e3; }
constexpr double m_to_mm(double m) { return m * 1e3; }
constexpr double um_to_m(double um) { return um / 1e6; }
constexpr double m_to_um(double m) { return m * 1e6; }
constexpr double n_per_mm2_to_pa(double n_per_mm2) { return n_per_mm2 * 1e6; }
constexpr double pa_to_n_per_mm2(double pa) { return pa / 1e6; }
constexpr double m_per_min_to_m_per_s(double v) { return v / 60.0; }
constexpr double m_per_s_to_m_per_min(double v) { return v * 60.0; }
constexpr double deg_to_rad(double deg) { return deg * kPi / 180.0; }
constexpr double rad_to_deg(double rad) { return rad * 180.0 / kPi; }

}  // namespace cutdyn::units
