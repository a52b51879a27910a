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
#include "support/reference_cases.hpp"
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
         "\nstiffness_n_per_m = " + std::to_string(mode.stiffness_n_per_m) + "\n" +
         (mode.residue_phase_rad != 0.0
              ? "residue_phase_deg = " +
                    std::to_string(units::rad_to_deg(mode.residue_phase_rad)) + "\n"
              : std::string());
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

TEST_F(MeasuredFrfJobs, ComplexResidueTablesGiveEveryMethodOneStructure) {
  // The four modes with complex residues (non-proportional damping, as a peer's FRF files
  // hold them). The frequency-domain methods read the tables, full discretization and the
  // simulation the modes fitted to them: the fit keeps the residues' phases, so every method
  // sees the same structure, as the same modes given in [[modes]] (residue_phase_deg).
  ModalModel truth = four_modes();
  const double phases_deg[] = {25.0, -20.0, 6.4, -30.0};
  for (std::size_t i = 0; i < truth.modes.size(); ++i)
    truth.modes[i].residue_phase_rad = units::deg_to_rad(phases_deg[i]);
  write_table(truth, Direction::kX, "x.frf", FrfFormat::kCutPro);
  write_table(truth, Direction::kY, "y.frf", FrfFormat::kCutPro);
  const io::Case measured =
      case_with(std::string(kMilling) + frf_table("x", "x.frf") + frf_table("y", "y.frf"));
  const io::Case exact = io::parse_case(std::string(kMilling) + modes_toml(truth), "modes");

  // The model the time-domain methods use reproduces the tables (noise-free: to rounding).
  const MillingProcess p = milling_process(measured, "lobes");
  ASSERT_TRUE(p.measured);
  for (Direction d : {Direction::kX, Direction::kY}) {
    const MeasuredFrf& table = *p.measured->direct(d);
    double sum = 0.0;
    for (std::size_t k = 1; k < table.frequency_hz.size(); ++k) {
      const auto g = table.receptance_m_per_n[k];
      sum += std::norm((frf(p.measured->fitted, d, units::hz_to_rad_per_s(table.frequency_hz[k])) -
                        g) / g);
    }
    EXPECT_LT(std::sqrt(sum / static_cast<double>(table.frequency_hz.size() - 1)), 1e-2)
        << to_string(d);
  }

  const auto mf = lobes(measured, "multi-frequency");
  const auto fd = lobes(measured, "full-discretization");
  EXPECT_LT(worst_ratio(mf, lobes(exact, "multi-frequency")), 5e-3);
  EXPECT_LT(worst_ratio(fd, lobes(exact, "full-discretization")), 1e-3);
  EXPECT_LT(worst_ratio(lobes(measured, "zero-order"), lobes(exact, "zero-order")), 5e-3);
  // Multi-frequency (tables) and full discretization (fitted modes) as on modal cases: within
  // 5 % where both sit on the same lobe as their neighbours (away from cusps).
  int compared = 0;
  for (std::size_t i = 1; i + 1 < fd.size(); ++i) {
    if (!fd[i].boundary.found || fd[i - 1].lobe != fd[i].lobe || fd[i + 1].lobe != fd[i].lobe)
      continue;
    ASSERT_TRUE(mf[i].boundary.found) << fd[i].rpm;
    EXPECT_NEAR(mf[i].boundary.depth_m, fd[i].boundary.depth_m, 0.05 * fd[i].boundary.depth_m)
        << fd[i].rpm;
    ++compared;
  }
  EXPECT_GT(compared, 20);

  // The same structure with the phases dropped (real modes, what the fit used to hand on) is
  // a different one: its lobes are off by more than the tolerance above.
  MillingProcess real = p;
  for (Mode& m : real.measured->fitted.modes) m.residue_phase_rad = 0.0;
  double worst_real = 0.0;
  for (const LobePoint& q : fd) {
    MillingStabilityOptions o;
    o.method = MillingMethod::kFullDiscretization;
    o.depth_max_m = 3e-3;
    const MillingBoundary b = milling_critical_depth(real, q.rpm, o);
    if (b.boundary.found && q.boundary.found)
      worst_real = std::max(worst_real, std::abs(b.boundary.depth_m / q.boundary.depth_m - 1.0));
  }
  EXPECT_GT(worst_real, 0.05);

  // The simulation of the measured case brackets the full discretization's boundary.
  int simulated = 0;
  for (std::size_t i = 10; i < fd.size() && simulated < 2; i += 17) {
    if (!fd[i].boundary.found || fd[i].boundary.depth_m > 2.5e-3) continue;
    const double rpm = fd[i].rpm, critical = fd[i].boundary.depth_m;
    EXPECT_LT(testing::simulate_model(p, rpm, 0.98 * critical).growth_per_period, 0.0) << rpm;
    EXPECT_GT(testing::simulate_model(p, rpm, 1.02 * critical).growth_per_period, 0.0) << rpm;
    ++simulated;
  }
  EXPECT_EQ(simulated, 2);
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
