// Cases with [[frf]] tables: the lobes from a measured FRF agree with the lobes from the modes
// it was made of, the three file formats give the same lobes, tool and workpiece tables add,
// and a bad file is refused naming the file and its line.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "cutdyn/app/case_models.hpp"
#include "cutdyn/app/stability.hpp"
#include "cutdyn/core/error.hpp"
#include "cutdyn/core/units.hpp"
#include "cutdyn/io/frf_file.hpp"
#include "cutdyn/modal/measured_frf.hpp"
#include "cutdyn/stability/milling.hpp"
#include "support/textbook_zero_order.hpp"

namespace cutdyn::app {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// The structure of examples/frf/README.md: two modes in x, two in y.
ModalModel four_modes() {
  const auto mode = [](Direction d, double hz, double zeta, double k) {
    return Mode{d, units::hz_to_rad_per_s(hz), zeta, k};
  };
  return ModalModel{
      {mode(Direction::kX, 520.0, 0.035, 1.8e7), mode(Direction::kX, 1380.0, 0.020, 4.5e7),
       mode(Direction::kY, 610.0, 0.030, 2.2e7), mode(Direction::kY, 1450.0, 0.025, 6.0e7)}};
}

std::string modes_toml(const ModalModel& m) {
  std::string s;
  for (const Mode& mode : m.modes)
    s += "[[modes]]\ndirection = \"" + std::string(to_string(mode.direction)) +
         "\"\nnatural_hz = " + std::to_string(units::rad_per_s_to_hz(mode.natural_rad_s)) +
         "\ndamping_ratio = " + std::to_string(mode.damping_ratio) +
         "\nstiffness_n_per_m = " + std::to_string(mode.stiffness_n_per_m) + "\n";
  return s;
}

constexpr const char* kMilling =
    "process = \"milling\"\n[cutting]\nkt_n_per_mm2 = 1500\nkr_n_per_mm2 = 450\n"
    "[tool]\nteeth = 4\ndiameter_mm = 20\n[operation]\nradial_immersion = 1.0\n"
    "direction = \"down\"\n[lobes]\nrpm_min = 4000\nrpm_max = 20000\nrpm_steps = 60\n"
    "depth_max_mm = 3\nrefine = false\n";

class MeasuredFrfJobs : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("cutdyn-frf-jobs-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
            "-" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes the receptance of `model` in `d` (0…3000 Hz by 1 Hz, noise-free) as `name`.
  void write_table(const ModalModel& model, Direction d, const std::string& name,
                   FrfFormat format) {
    write_frf(dir_ / name, sample_frf(model, d, linear_frequencies(0.0, 3000.0, 3001)), format);
  }
  io::Case case_with(const std::string& text) {
    const fs::path file = dir_ / "case.toml";
    std::ofstream(file) << text;
    return io::load_case_file(file);
  }
  static std::string frf_table(const char* direction, const std::string& file) {
    return "[[frf]]\ndirection = \"" + std::string(direction) + "\"\nfile = \"" + file + "\"\n";
  }
  static std::vector<LobePoint> lobes(const io::Case& c, const char* method) {
    LobesRequest r;
    r.method = method;
    r.threads = 2;
    return run_lobes(c, r).lobes.points;
  }

  fs::path dir_;
};

// Largest |a/b − 1| over speeds where both found a boundary (and both must find one).
double worst_ratio(const std::vector<LobePoint>& a, const std::vector<LobePoint>& b) {
  EXPECT_EQ(a.size(), b.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    EXPECT_EQ(a[i].rpm, b[i].rpm);
    EXPECT_EQ(a[i].boundary.found, b[i].boundary.found) << a[i].rpm;
    if (a[i].boundary.found && b[i].boundary.found)
      worst = std::max(worst, std::abs(a[i].boundary.depth_m / b[i].boundary.depth_m - 1.0));
  }
  return worst;
}

TEST_F(MeasuredFrfJobs, MillingLobesFromTheTablesAgreeWithTheModesInEveryFormat) {
  const ModalModel modes = four_modes();
  const io::Case exact = io::parse_case(std::string(kMilling) + modes_toml(modes), "modes");
  const auto zero_order = lobes(exact, "zero-order");
  const auto multi = lobes(exact, "multi-frequency");
  const auto fd = lobes(exact, "full-discretization");
  std::vector<LobePoint> first;
  for (const auto& [format, ext] :
       {std::pair{FrfFormat::kCutPro, ".frf"}, std::pair{FrfFormat::kCsv, ".csv"},
        std::pair{FrfFormat::kUff, ".uff"}}) {
    write_table(modes, Direction::kX, std::string("x") + ext, format);
    write_table(modes, Direction::kY, std::string("y") + ext, format);
    const io::Case measured =
        case_with(std::string(kMilling) + frf_table("x", std::string("x") + ext) +
                  frf_table("y", std::string("y") + ext));
    const auto z = lobes(measured, "zero-order");
    // Linear interpolation at 1 Hz against half-bandwidths of 18 Hz and more: 0.5 % (the
    // issue's tolerance); measured 0.05 %.
    EXPECT_LT(worst_ratio(z, zero_order), 5e-3) << ext;
    EXPECT_LT(worst_ratio(lobes(measured, "multi-frequency"), multi), 5e-3) << ext;
    // The fitted modes (noise-free data: recovered to rounding) in the full discretization.
    EXPECT_LT(worst_ratio(lobes(measured, "full-discretization"), fd), 1e-3) << ext;
    // The three formats: the same table (UFF to 1e-11), the same lobes.
    if (first.empty())
      first = z;
    else
      EXPECT_LT(worst_ratio(z, first), 1e-8) << ext;
  }
}

TEST_F(MeasuredFrfJobs, ToolAndWorkpieceTablesAddAndModesAddToTables) {
  // The x modes split: the first in a "tool" file, the second in a "workpiece" file; y from
  // [[modes]] beside the tables. The lobes equal those of all four modes.
  const ModalModel all = four_modes();
  const ModalModel tool{{all.modes[0]}}, workpiece{{all.modes[1]}}, y{{all.modes[2], all.modes[3]}};
  write_table(tool, Direction::kX, "tool.csv", FrfFormat::kCsv);
  write_table(workpiece, Direction::kX, "work.csv", FrfFormat::kCsv);
  const io::Case mixed = case_with(std::string(kMilling) + modes_toml(y) +
                                   frf_table("x", "tool.csv") + frf_table("x", "work.csv"));
  const io::Case exact = io::parse_case(std::string(kMilling) + modes_toml(all), "modes");
  EXPECT_LT(worst_ratio(lobes(mixed, "zero-order"), lobes(exact, "zero-order")), 5e-3);
  EXPECT_LT(worst_ratio(lobes(mixed, "full-discretization"), lobes(exact, "full-discretization")),
            1e-3);
  // The description names both.
  CheckRequest r;
  r.rpm = 9000.0;
  r.depth_m = 0.5e-3;
  EXPECT_THAT(run_check(mixed, r).description, HasSubstr("2 modes and measured FRF (x;"));
}

TEST_F(MeasuredFrfJobs, TurningClosedFormOnTheTableIsTlusty) {
  const ModalModel x{{four_modes().modes[0], four_modes().modes[1]}};
  write_table(x, Direction::kX, "x.frf", FrfFormat::kCutPro);
  const std::string turning =
      "process = \"turning\"\n[cutting]\nkf_n_per_mm2 = 1200\n[lobes]\nrpm_min = 500\n"
      "rpm_max = 4000\nrpm_steps = 40\ndepth_max_mm = 20\nrefine = false\n";
  const io::Case measured = case_with(turning + frf_table("x", "x.frf"));
  const io::Case exact = io::parse_case(turning + modes_toml(x), "modes");
  EXPECT_LT(worst_ratio(lobes(measured, "closed-form"), lobes(exact, "closed-form")), 5e-3);
  EXPECT_LT(
      worst_ratio(lobes(measured, "full-discretization"), lobes(exact, "full-discretization")),
      2e-3);
  // Turning takes x only.
  EXPECT_THROW(case_with(turning + frf_table("y", "x.frf")), InvalidInput);
}

TEST(MeasuredStructure, TheFrequencyDomainMethodsSeeTheTablesNotTheFittedModes) {
  // Tables from the four modes; "fitted" modes deliberately elsewhere (one 900 Hz mode per
  // direction): the system's response is the tables' (plus the given modes'), and its state
  // space the fitted modes'.
  const ModalModel truth = four_modes();
  const auto f = linear_frequencies(0.0, 3000.0, 3001);
  MillingProcess p;
  p.tool.teeth = 2;
  p.cutting.kt_pa = 6e8;
  p.measured.emplace();
  p.measured->xx = sample_frf(truth, Direction::kX, f);
  p.measured->yy = sample_frf(truth, Direction::kY, f);
  p.measured->fitted.modes = {Mode{Direction::kX, units::hz_to_rad_per_s(900.0), 0.05, 1e7},
                              Mode{Direction::kY, units::hz_to_rad_per_s(900.0), 0.05, 1e7}};
  const DelayedSystem s = milling_system(p, 6000.0);
  EXPECT_EQ(s.states(), 4);  // the fitted modes
  for (double hz : {100.0, 520.0, 610.5, 1380.0, 2999.0}) {
    const double w = units::hz_to_rad_per_s(hz);
    const Eigen::MatrixXcd g = s.frequency_response(w);
    EXPECT_LT(std::abs(g(0, 0) - frf(truth, Direction::kX, w)), 1e-3 * std::abs(g(0, 0))) << hz;
    EXPECT_LT(std::abs(g(1, 1) - frf(truth, Direction::kY, w)), 1e-3 * std::abs(g(1, 1))) << hz;
    EXPECT_EQ(g(0, 1), std::complex<double>(0.0, 0.0));  // no cross table
    // Negative frequencies (the Hill matrix' lower harmonics): the conjugate.
    EXPECT_EQ(s.frequency_response(-w)(0, 0), std::conj(g(0, 0)));
  }
  // Outside the measured band: nothing.
  EXPECT_EQ(s.frequency_response(units::hz_to_rad_per_s(3500.0)).norm(), 0.0);
}

TEST_F(MeasuredFrfJobs, ZeroOrderOnTheTablesAgreesWithTheTextbookFrequencySweep) {
  // The example FRFs (1 % noise) through the case; the same tables swept the textbook way.
  const io::Case c =
      io::load_case_file(fs::path(CUTDYN_EXAMPLES_DIR) / "frf" / "milling-measured.toml");
  const MillingProcess p = milling_process(c, "lobes");
  LobesRequest r;
  r.method = "zero-order";
  r.threads = 2;
  const std::vector<LobePoint> ours = run_lobes(c, r).lobes.points;
  std::vector<double> rpm;
  for (const LobePoint& q : ours) rpm.push_back(q.rpm);
  const std::vector<double> theirs = testing::textbook_zero_order_lobes(p, rpm);
  std::vector<double> diff;
  for (std::size_t n = 0; n < ours.size(); ++n)
    if (ours[n].boundary.found && theirs[n] < c.lobes.depth_max_m)
      diff.push_back(std::abs(ours[n].boundary.depth_m / theirs[n] - 1.0));
  ASSERT_GT(diff.size(), ours.size() / 2);
  std::sort(diff.begin(), diff.end());
  // The sweep interpolates between 1 Hz points and across cusps: a few speeds differ by more.
  EXPECT_LT(diff[diff.size() / 2], 1e-3);
  EXPECT_LT(diff[diff.size() * 9 / 10], 1e-2);
}

TEST_F(MeasuredFrfJobs, ABadFileIsRefusedNamingTheFileAndItsLine) {
  std::ofstream(dir_ / "bad.csv") << "frequency_hz,real_m_per_n,imag_m_per_n\n10,1e-8,0\n"
                                  << "20,1e-8,0\n20,2e-8,0\n30,1e-8,0\n";
  try {
    case_with(std::string(kMilling) + frf_table("x", "bad.csv"));
    FAIL() << "accepted";
  } catch (const InvalidInput& e) {
    EXPECT_THAT(e.where(), HasSubstr("bad.csv"));
    ASSERT_FALSE(e.problems().empty());
    EXPECT_THAT(e.problems()[0], HasSubstr("frf[0].file = \"bad.csv\": line 4"));
  }
  // A missing file, and an unknown key in [[frf]].
  EXPECT_THROW(case_with(std::string(kMilling) + frf_table("x", "missing.csv")), InvalidInput);
  EXPECT_THROW(case_with(std::string(kMilling) + frf_table("x", "bad.csv") + "fiel = 3\n"),
               InvalidInput);
}

}  // namespace
}  // namespace cutdyn::app
