// FRF files: every format written and read back, sloppy but valid files accepted, conversions
// checked against the receptance of known modes, every kind of bad input refused naming its
// line, and the examples in examples/frf compared with the modes they were made from.
#include "cutdyn/io/frf_file.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <numbers>
#include <random>

#include "cutdyn/core/error.hpp"
#include "support/temp_dir.hpp"

namespace cutdyn {
namespace {

namespace fs = std::filesystem;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

Mode mode(Direction d, double f_hz, double zeta, double k) {
  return Mode{d, kTwoPi * f_hz, zeta, k};
}

// The tool of examples/frf: two modes in x and two in y.
ModalModel tool_model() {
  return ModalModel{
      {mode(Direction::kX, 520.0, 0.035, 1.8e7), mode(Direction::kX, 1380.0, 0.020, 4.5e7),
       mode(Direction::kY, 610.0, 0.030, 2.2e7), mode(Direction::kY, 1450.0, 0.025, 6.0e7)}};
}

std::vector<double> every(double lo, double hi, double step) {
  std::vector<double> f;
  for (int i = 0; lo + i * step <= hi + 1e-9; ++i) f.push_back(lo + i * step);
  return f;
}

// |a − b| ≤ rel·|b| at every point, same frequencies to rel.
void expect_close(const MeasuredFrf& a, const MeasuredFrf& b, double rel, const std::string& what) {
  ASSERT_EQ(a.frequency_hz.size(), b.frequency_hz.size()) << what;
  double worst = 0.0;
  for (std::size_t i = 0; i < a.frequency_hz.size(); ++i) {
    EXPECT_LE(std::abs(a.frequency_hz[i] - b.frequency_hz[i]), rel * b.frequency_hz[i])
        << what << " f " << i;
    worst = std::max(worst, std::abs(a.receptance_m_per_n[i] - b.receptance_m_per_n[i]) /
                                std::abs(b.receptance_m_per_n[i]));
  }
  EXPECT_LE(worst, rel) << what;
}

// The problems of the InvalidInput that `work` throws, joined; "" if it throws none.
std::string refusal(const std::function<void()>& work, std::string* where = nullptr) {
  try {
    work();
  } catch (const InvalidInput& e) {
    if (where) *where = e.where();
    std::string s;
    for (const auto& p : e.problems()) s += p + "\n";
    return s;
  }
  return "";
}

std::string refusal_of(std::string_view content, std::string_view extension = {}) {
  return refusal([&] { parse_frf(content, "test", {}, extension); });
}

FrfWriteOptions uff(UffSpacing spacing, bool single = false, bool binary = false) {
  FrfWriteOptions o;
  o.uff_spacing = spacing;
  o.uff_single_precision = single;
  o.uff_binary = binary;
  return o;
}

FrfWriteOptions described(const std::string& text) {
  FrfWriteOptions o;
  o.description = text;
  return o;
}

FrfFileOptions dataset(int index) {
  FrfFileOptions o;
  o.dataset = index;
  return o;
}

#define EXPECT_HAS(text, part) EXPECT_NE((text).find(part), std::string::npos) << (text)

// ---- formats and round trips ----------------------------------------------------------

TEST(FrfFile, FormatNamesRoundTrip) {
  for (FrfFormat f : {FrfFormat::kCutPro, FrfFormat::kCsv, FrfFormat::kUff})
    EXPECT_EQ(parse_frf_format(to_string(f)), f);
  EXPECT_EQ(parse_frf_format("unv"), FrfFormat::kUff);
  EXPECT_FALSE(parse_frf_format("txt"));
  EXPECT_FALSE(parse_frf_format(""));
}

class FrfFileRoundTrip : public testing::TempDirTest {};

TEST_F(FrfFileRoundTrip, TextAndCsvAreExact) {
  const MeasuredFrf g =
      sample_frf(tool_model(), Direction::kX, linear_frequencies(0.0, 3000.0, 301));
  for (FrfFormat format : {FrfFormat::kCutPro, FrfFormat::kCsv}) {
    const fs::path file = dir_ / (std::string("g.") + to_string(format));
    EXPECT_TRUE(write_frf(file, g, format, described("x tool")).empty());
    const FrfReadResult r = read_frf_file(file);
    EXPECT_EQ(r.format, format);
    EXPECT_TRUE(r.warnings.empty());
    EXPECT_EQ(r.frf.frequency_hz, g.frequency_hz);  // shortest round-trip numbers: bit for bit
    EXPECT_EQ(r.frf.receptance_m_per_n, g.receptance_m_per_n);
  }
}

TEST_F(FrfFileRoundTrip, UffDoubleEvenAndUnevenWithin1e11) {
  const ModalModel m = tool_model();
  // Even: 1 Hz steps. Uneven: frequencies of at most 6 significant digits (the E13.5 abscissa).
  const MeasuredFrf even = sample_frf(m, Direction::kY, every(50.0, 3000.0, 1.0));
  const MeasuredFrf uneven = sample_frf(
      m, Direction::kY, {10.0, 12.5, 20.0, 33.25, 100.0, 250.125, 611.5, 1450.25, 2999.75});
  struct Case {
    const MeasuredFrf* g;
    UffSpacing spacing;
    bool written_even;
  };
  for (const Case& c :
       {Case{&even, UffSpacing::kAutomatic, true}, Case{&uneven, UffSpacing::kAutomatic, false},
        Case{&even, UffSpacing::kUneven, false}}) {
    const MeasuredFrf& g = *c.g;
    const fs::path file = dir_ / "g.uff";
    EXPECT_TRUE(write_frf(file, g, FrfFormat::kUff, uff(c.spacing)).empty());
    const std::string text = testing::read_file(file);
    EXPECT_HAS(text,
               c.written_even ? "         1  5.00000E+01  1.00000E+00" : "         0  0.00000E+00");
    const FrfReadResult r = read_frf_file(file);
    EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
    EXPECT_EQ(r.format, FrfFormat::kUff);
    EXPECT_EQ(r.units, "Hz, m/N");
    expect_close(r.frf, g, 1e-11, "uff double");
  }
}

TEST_F(FrfFileRoundTrip, UffSinglePrecisionWithinItsSixDigits) {
  // E13.5 keeps 6 significant digits: relative rounding ≤ 5e-6 per number.
  const MeasuredFrf g = sample_frf(tool_model(), Direction::kX, every(100.0, 2000.0, 10.0));
  for (UffSpacing s : {UffSpacing::kEven, UffSpacing::kUneven}) {
    const fs::path file = dir_ / "g.unv";
    write_frf(file, g, FrfFormat::kUff, uff(s, true));
    const FrfReadResult r = read_frf_file(file);
    expect_close(r.frf, g, 5e-6 * std::sqrt(2.0), "uff single");
    // ... and not better than single precision (the test would pass a double file too).
    double worst = 0.0;
    for (std::size_t i = 0; i < g.frequency_hz.size(); ++i)
      worst = std::max(worst, std::abs(r.frf.receptance_m_per_n[i] - g.receptance_m_per_n[i]) /
                                  std::abs(g.receptance_m_per_n[i]));
    EXPECT_GT(worst, 1e-8);
  }
}

TEST_F(FrfFileRoundTrip, UffUnevenAbscissaRoundedToSixDigitsIsWarned) {
  const MeasuredFrf g = sample_frf(tool_model(), Direction::kX, {100.0, 200.0001, 300.0, 400.0});
  const FrfText t = format_frf(g, FrfFormat::kUff);
  ASSERT_EQ(t.warnings.size(), 1u);
  EXPECT_HAS(t.warnings[0], "6 significant digits");
  const FrfReadResult r = parse_frf(t.text, "t");
  EXPECT_EQ(r.frf.frequency_hz[1], 200.0);  // 2.00000E+02
  // Frequencies that become equal are refused rather than written.
  const MeasuredFrf close = sample_frf(tool_model(), Direction::kX, {100.0, 1000.001, 1000.002});
  EXPECT_HAS(refusal([&] { format_frf(close, FrfFormat::kUff); }), "frequency_hz[2] = 1000.002 Hz");
  // Even spacing asked for frequencies that are not evenly spaced.
  EXPECT_HAS(refusal([&] { format_frf(close, FrfFormat::kUff, uff(UffSpacing::kEven)); }),
             "not evenly spaced");
}

TEST_F(FrfFileRoundTrip, Uff58bBinaryIsExactInDouble) {
  const MeasuredFrf g = sample_frf(tool_model(), Direction::kX, linear_frequencies(0.0, 3000.0, 7));
  for (UffSpacing s : {UffSpacing::kEven, UffSpacing::kUneven}) {
    const fs::path file = dir_ / "g.uff";
    write_frf(file, g, FrfFormat::kUff, uff(s, false, true));
    const std::string text = testing::read_file(file);
    EXPECT_EQ(text.substr(0, 14), "    -1\n    58b");
    const FrfReadResult r = read_frf_file(file);
    ASSERT_EQ(r.uff_datasets.size(), 1u);
    EXPECT_TRUE(r.uff_datasets[0].binary);
    if (s == UffSpacing::kUneven) {  // the abscissa is stored as a double in a 58b
      EXPECT_EQ(r.frf.frequency_hz, g.frequency_hz);
    }
    EXPECT_EQ(r.frf.receptance_m_per_n, g.receptance_m_per_n);
  }
  write_frf(dir_ / "s.uff", g, FrfFormat::kUff, uff(UffSpacing::kUneven, true, true));
  expect_close(read_frf(dir_ / "s.uff"), g, 1e-7, "58b single (float: 6e-8 relative)");
}

// The coherence goes through every format and back: text and CSV bit for bit, UFF double to
// its 12 digits, single to its 6, binary exactly; ASCII and 58b, even and uneven spacing.
TEST_F(FrfFileRoundTrip, CoherenceSurvivesEveryFormat) {
  MeasuredFrf g = sample_frf(tool_model(), Direction::kX, linear_frequencies(10.0, 3000.0, 300));
  for (std::size_t i = 0; i < g.frequency_hz.size(); ++i)
    g.coherence.push_back(0.5 + 0.49 * std::cos(0.01 * static_cast<double>(i * i)));
  for (FrfFormat format : {FrfFormat::kCutPro, FrfFormat::kCsv}) {
    const fs::path file = dir_ / (std::string("c.") + to_string(format));
    write_frf(file, g, format);
    const FrfReadResult r = read_frf_file(file);
    EXPECT_TRUE(r.warnings.empty()) << to_string(format);
    EXPECT_EQ(r.frf.coherence, g.coherence) << to_string(format);
    EXPECT_EQ(r.frf.receptance_m_per_n, g.receptance_m_per_n);
  }
  for (bool binary : {false, true}) {
    for (bool single : {false, true}) {
      for (UffSpacing spacing : {UffSpacing::kEven, UffSpacing::kUneven}) {
        const std::string what = std::string(binary ? "58b" : "58") + (single ? " single" : " double") +
                                 (spacing == UffSpacing::kEven ? " even" : " uneven");
        // Uneven ASCII stores the abscissa with 6 digits: frequencies that have no more.
        MeasuredFrf t = g;
        for (double& f : t.frequency_hz) f = std::round(f * 10.0) / 10.0;
        write_frf(dir_ / "c.uff", t, FrfFormat::kUff, uff(spacing, single, binary));
        const FrfReadResult r = read_frf_file(dir_ / "c.uff");
        ASSERT_EQ(r.uff_datasets.size(), 2u) << what;
        EXPECT_EQ(r.uff_datasets[1].function_type, 6) << what;
        ASSERT_EQ(r.frf.coherence.size(), t.coherence.size()) << what;
        // E13.5 keeps 6 digits (5e-6 relative), a float 6e-8, E20.12 13 digits; a double is exact.
        const double digits =
            single ? (binary ? 1e-7 : 5e-6) : (binary ? 0.0 : 1e-12);
        for (std::size_t i = 0; i < t.coherence.size(); ++i)
          EXPECT_NEAR(r.frf.coherence[i], t.coherence[i], digits * t.coherence[i]) << what << " " << i;
      }
    }
  }
}

TEST(FrfFileText, CoherenceColumnsAreReadAndCheckedNamingTheLine) {
  // CutPro text: a fourth number on the first data line is the coherence, on every line.
  const FrfReadResult text = parse_frf("% f re im coh\n100 -1e-8 -2e-8 0.9\n110 -1e-8 -3e-8 0.95\n"
                                       "120 -1e-8 -2e-8 0.5\n", "t");
  EXPECT_EQ(text.frf.coherence, (std::vector<double>{0.9, 0.95, 0.5}));
  EXPECT_TRUE(text.warnings.empty());
  // CutPro's trailer after four numbers.
  EXPECT_EQ(parse_frf("1 -1 -2 0.9 Freq Hz Real m/N Imag Real Coherence\n2 -1 -2 1\n3 -1 -2 0\n",
                      "t")
                .frf.coherence.size(),
            3u);
  EXPECT_HAS(refusal_of("100 1 2 0.9\n110 1 2\n120 1 2 0.9\n"),
             "line 2: 3 values; a data line has 4: frequency (Hz), real and imaginary part (m/N), "
             "coherence");
  EXPECT_HAS(refusal_of("100 1 2 0.9\n110 1 2 1.5\n120 1 2 0.9\n"),
             "line 2: coherence 1.5 is not 0 to 1");
  EXPECT_HAS(refusal_of("100 1 2 0.9\n110 1 2 -0.1\n120 1 2 nan\n"),
             "line 3: coherence nan is not 0 to 1");
  EXPECT_HAS(refusal_of("100 1 2 0.9\n110 1 2 95\n120 1 2 0.9\n"), "not a percentage");
  EXPECT_HAS(refusal_of("100 1 2 0.9\n110 1 2 x\n120 1 2 0.9\n"),
             "line 2: \"x\" is not a number (the coherence)");
  // CSV: an optional coherence column, anywhere.
  const FrfReadResult csv = parse_frf(
      "coherence,frequency_hz,real_m_per_n,imag_m_per_n\n0.99,1,-1,-2\n0.5,2,-1,-2\n0,3,-1,-2\n",
      "t");
  EXPECT_EQ(csv.frf.coherence, (std::vector<double>{0.99, 0.5, 0.0}));
  EXPECT_HAS(refusal_of("frequency_hz,real_m_per_n,imag_m_per_n,coherence\n1,2,3,0.9\n2,2,3\n"
                        "3,2,3,0.9\n"),
             "line 3: 3 fields, no coherence (column 4 of the header)");
  EXPECT_HAS(refusal_of("frequency_hz,real_m_per_n,imag_m_per_n,coherence\n1,2,3,0.9\n2,2,3,-3\n"
                        "3,2,3,0.9\n"),
             "line 3: coherence -3 is not 0 to 1");
  EXPECT_HAS(refusal_of("frequency_hz,real_m_per_n,imag_m_per_n,coherence\n1,2,3,0.9\n2,2,3,hi\n"
                        "3,2,3,0.9\n"),
             "line 3: coherence = \"hi\" is not a number");
}

// ---- hand-made files: UFF as test systems write it ------------------------------------

// Records 1-11 of a dataset 58.
std::string uff58_header(int function_type, int ordinate_type, std::size_t n, bool even,
                         double minimum, double increment, int abscissa_type,
                         const std::string& abscissa_units, int num_type,
                         const std::string& num_units, int den_type, const std::string& den_units) {
  std::string s = "H1 tool tip / hammer\nNONE\n14-Mar-24 10:21:07\nNONE\nNONE\n";
  s += fmt::format("{:5}{:10}{:5}{:10} {:<10}{:10}{:4} {:<10}{:10}{:4}\n", function_type, 1, 1, 0,
                   "NONE", 7, 2, "NONE", 7, 2);
  s += fmt::format("{:10}{:10}{:10}{:13.5E}{:13.5E}{:13.5E}\n", ordinate_type, n, even ? 1 : 0,
                   minimum, increment, 0.0);
  s += fmt::format("{:10}{:5}{:5}{:5} {:<20} {}\n", abscissa_type, 0, 0, 0, "Frequency",
                   abscissa_units);
  s += fmt::format("{:10}{:5}{:5}{:5} {:<20} {}\n", num_type, 0, 0, 0, "Response", num_units);
  s += fmt::format("{:10}{:5}{:5}{:5} {:<20} {}\n", den_type, 0, 0, 0, "Force", den_units);
  s += fmt::format("{:10}{:5}{:5}{:5} {:<20} {}\n", 0, 0, 0, 0, "NONE", "NONE");
  return s;
}

// Values as record 12 of a complex double dataset: 4 E20.12 per line (even) or E13.5,2E20.12.
std::string uff_double_values(const std::vector<double>& f,
                              const std::vector<std::complex<double>>& v, bool even) {
  std::string s;
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (!even) s += fmt::format("{:13.5E}", f[i]);
    s += fmt::format("{:20.12E}{:20.12E}", v[i].real(), v[i].imag());
    if (!even || i % 2 == 1 || i + 1 == f.size()) s += "\n";
  }
  return s;
}

std::string crlf(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '\n') out += '\r';
    out += c;
  }
  return out;
}

TEST(FrfFileUff, ImpactTestExportWithHeaderUnitsCoherenceAndCrlf) {
  // A single-precision accelerance A (m/s²/N) at 4 frequencies, preceded by a header (151),
  // SI units (164, D exponents) and a coherence; CRLF line ends. G = A/(−ω²).
  const std::string file = crlf(
      "    -1\n   151\nC:\\data\\tool.unv\nNONE\nNONE\nNONE\nNONE\nNONE\nNONE\n    -1\n"
      "    -1\n   164\n         1SI - mks (Newton)          2\n"
      "  1.00000000000000000D+00  1.00000000000000000D+00  1.00000000000000000D+00\n"
      "  2.73149999999999977D+02\n    -1\n"
      "    -1\n    58\n" +
      uff58_header(6, 5, 4, true, 100.0, 50.0, 18, "Hz", 0, "NONE", 0, "NONE") +
      "  9.90000E-01  0.00000E+00  9.80000E-01  0.00000E+00  9.70000E-01  0.00000E+00\n"
      "  9.60000E-01  0.00000E+00\n    -1\n"
      "    -1\n    58\n" +
      uff58_header(4, 5, 4, true, 100.0, 50.0, 18, "Hz", 12, "m/s^2", 13, "N") +
      " -1.00000E+01  2.00000E+00 -2.50000E+01 -5.00000E-01  3.00000E+00 -4.00000E+00\n"
      "  1.25000E+00  6.00000E-01\n    -1\n");
  const FrfReadResult r = parse_frf(file, "impact.unv", {}, ".unv");
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
  EXPECT_EQ(r.quantity, FrfQuantity::kAccelerance);
  ASSERT_EQ(r.uff_datasets.size(), 2u);
  EXPECT_EQ(r.uff_datasets[0].function_type, 6);
  EXPECT_EQ(r.uff_datasets[1].response_node, 7);
  EXPECT_EQ(r.uff_datasets[1].response_direction, 2);
  EXPECT_EQ(r.description, "H1 tool tip / hammer");
  const std::vector<std::complex<double>> a = {
      {-10.0, 2.0}, {-25.0, -0.5}, {3.0, -4.0}, {1.25, 0.6}};
  ASSERT_EQ(r.frf.frequency_hz, (std::vector<double>{100.0, 150.0, 200.0, 250.0}));
  // The coherence of the same DOF at the same frequencies (stored complex, as some systems do).
  EXPECT_EQ(r.frf.coherence, (std::vector<double>{0.99, 0.98, 0.97, 0.96}));
  for (std::size_t i = 0; i < 4; ++i) {
    const double w = kTwoPi * r.frf.frequency_hz[i];
    EXPECT_LE(std::abs(r.frf.receptance_m_per_n[i] - a[i] / (-w * w)),
              1e-15 * std::abs(a[i] / (w * w)));
  }
  // The coherence asked for by its index is refused; an index beyond the file too.
  EXPECT_HAS(
      refusal([&] { parse_frf(file, "t", dataset(0)); }),
      "line 24: dataset 58 index 0 (line 17, function type 6, coherence) is not a frequency");
  EXPECT_HAS(refusal([&] { parse_frf(file, "t", dataset(2)); }), "indices 0 to 1");
  EXPECT_EQ(parse_frf(file, "t", dataset(1)).frf.frequency_hz.size(), 4u);
  // A dataset index given for a file that is not a universal file is said to be ignored.
  const FrfReadResult text = parse_frf("1 1 2\n2 1 2\n3 1 2\n", "t", dataset(1));
  ASSERT_EQ(text.warnings.size(), 1u);
  EXPECT_HAS(text.warnings[0], "this is a frf file, ignored");
}

// A coherence of the same DOF at other frequencies is not used, with a warning; one of another
// DOF is not the FRF's; a value out of 0…1 is refused at its line.
TEST(FrfFileUff, CoherenceOfAnotherGridOrDofIsNotTakenAndBadValuesAreRefused) {
  const std::string frf = "    -1\n    58\n" +
                          uff58_header(4, 6, 3, true, 10, 10, 18, "Hz", 8, "m", 13, "N") +
                          "  1.000000000000E-08  2.000000000000E-08  3.000000000000E-08  "
                          "4.000000000000E-08\n  5.000000000000E-08  6.000000000000E-08\n    -1\n";
  const auto coherence = [](double minimum, const std::string& values) {
    return "    -1\n    58\n" +
           uff58_header(6, 4, 3, true, minimum, 10, 18, "Hz", 0, "NONE", 0, "NONE") + values +
           "    -1\n";
  };
  const std::string good = "  9.000000000000E-01  8.000000000000E-01  7.000000000000E-01\n";
  const FrfReadResult same = parse_frf(coherence(10, good) + frf, "t");
  EXPECT_EQ(same.frf.coherence, (std::vector<double>{0.9, 0.8, 0.7}));
  const FrfReadResult shifted = parse_frf(coherence(20, good) + frf, "t");
  EXPECT_TRUE(shifted.frf.coherence.empty());
  ASSERT_EQ(shifted.warnings.size(), 1u);
  EXPECT_HAS(shifted.warnings[0], "the coherence (dataset 58 index 0, line 1) has 3 points at "
                                  "other frequencies than the FRF's 3: not used");
  std::string other_dof = coherence(10, good);
  other_dof.replace(other_dof.find("         7   2"), 14, "         8   2");
  const FrfReadResult other = parse_frf(other_dof + frf, "t");
  EXPECT_TRUE(other.frf.coherence.empty());
  EXPECT_TRUE(other.warnings.empty());
  // A coherence in a form cutdyn does not read (data type 3) is left out, with the reason.
  std::string type3 = coherence(10, good);
  type3.replace(type3.find("         4         3         1"), 30, "         3         3         1");
  const FrfReadResult unread = parse_frf(type3 + frf, "t");
  EXPECT_TRUE(unread.frf.coherence.empty());
  ASSERT_EQ(unread.warnings.size(), 1u);
  EXPECT_HAS(unread.warnings[0], "the coherence (dataset 58 index 0, line 1) is not read (line 9: "
                                 "record 7: ordinate data type 3 must be 2 or 4");
  EXPECT_HAS(refusal_of(coherence(10, "  9.000000000000E-01  1.800000000000E+00  7.000000000000E-01\n") +
                        frf),
             "line 14: the coherence (dataset 58 index 0, line 1): 1.8 at 20 Hz is not 0 to 1");
}

TEST(FrfFileUff, AccelerationInGAndMobilityInMillimetresConvertToReceptance) {
  const ModalModel m = tool_model();
  const std::vector<double> f = {100.0, 400.0, 520.0, 700.0, 1380.0, 2000.0};
  const MeasuredFrf g = sample_frf(m, Direction::kX, f);
  std::vector<std::complex<double>> a_g, y_mm;  // A in g/N, Y in mm/s/N
  for (std::size_t i = 0; i < f.size(); ++i) {
    const double w = kTwoPi * f[i];
    a_g.push_back(-w * w * g.receptance_m_per_n[i] / 9.80665);
    y_mm.push_back(std::complex<double>(0.0, w) * g.receptance_m_per_n[i] * 1e3);
  }
  const std::string acc = "    -1\n    58\n" +
                          uff58_header(4, 6, f.size(), false, 0, 0, 18, "Hz", 12, "g", 13, "N") +
                          uff_double_values(f, a_g, false) + "    -1\n";
  const FrfReadResult ra = parse_frf(acc, "acc");
  EXPECT_EQ(ra.units, "Hz, g/N");
  expect_close(ra.frf, g, 1e-11, "accelerance in g");
  // Mobility, units from a dataset 164 in mm (length factor 1000: SI = file value / factor).
  const std::string mob =
      "    -1\n   164\n         5MM (milli newton)          2\n"
      "  1.00000000000000000D+03  1.00000000000000000D+00  1.00000000000000000D+00\n"
      "  2.73149999999999977D+02\n    -1\n    -1\n    58\n" +
      uff58_header(4, 6, f.size(), false, 0, 0, 18, "NONE", 11, "NONE", 13, "NONE") +
      uff_double_values(f, y_mm, false) + "    -1\n";
  const FrfReadResult rm = parse_frf(mob, "mob");
  EXPECT_EQ(rm.quantity, FrfQuantity::kMobility);
  EXPECT_TRUE(rm.warnings.empty());
  expect_close(rm.frf, g, 1e-11, "mobility in mm/s/N");
  // The same labelled mm/s per N, no dataset 164.
  const std::string mob2 =
      "    -1\n    58\n" +
      uff58_header(4, 6, f.size(), false, 0, 0, 18, "Hz", 11, "mm/s", 13, "N") +
      uff_double_values(f, y_mm, false) + "    -1\n";
  expect_close(parse_frf(mob2, "mob2").frf, g, 1e-11, "mobility labelled mm/s");
}

TEST(FrfFileUff, UnstatedUnitsAreAssumedAndSaid) {
  const MeasuredFrf g = sample_frf(tool_model(), Direction::kX, {100.0, 200.0, 300.0});
  const std::string body =
      uff_double_values(g.frequency_hz, g.receptance_m_per_n, true) + "    -1\n";
  const FrfReadResult unknown =
      parse_frf("    -1\n    58\n" +
                    uff58_header(4, 6, 3, true, 100, 100, 0, "NONE", 0, "NONE", 0, "NONE") + body,
                "u");
  ASSERT_EQ(unknown.warnings.size(), 1u);
  EXPECT_HAS(unknown.warnings[0], "line 11: the ordinate's quantity is not stated");
  expect_close(unknown.frf, g, 1e-11, "assumed m/N");
  const FrfReadResult si =
      parse_frf("    -1\n    58\n" +
                    uff58_header(4, 6, 3, true, 100, 100, 18, "NONE", 8, "NONE", 13, "NONE") + body,
                "s");
  ASSERT_EQ(si.warnings.size(), 1u);
  EXPECT_HAS(si.warnings[0], "no units label and no dataset 164");
  const FrfReadResult mm =
      parse_frf("    -1\n    58\n" +
                    uff58_header(4, 6, 3, true, 100, 100, 18, "Hz", 8, "mm/N", 13, "NONE") + body,
                "m");
  EXPECT_TRUE(mm.warnings.empty());
  EXPECT_NEAR(std::abs(mm.frf.receptance_m_per_n[0]), 1e-3 * std::abs(g.receptance_m_per_n[0]),
              1e-14 * std::abs(g.receptance_m_per_n[0]));
}

TEST(FrfFileUff, SeparatedAndGluedFieldsAreBothRead) {
  // Fields glued together (a 3-digit exponent fills E13.5) are cut at the fixed widths;
  // loosely spaced fields are split at blanks.
  const std::string glued =
      "    -1\n    58\n" + uff58_header(4, 5, 3, true, 10, 10, 18, "Hz", 8, "m", 13, "N") +
      "-1.00000E-100-2.00000E-101  1.00000E-08  2.00000E-08  3.00000E-08  4.00000E-08\n    -1\n";
  const FrfReadResult r = parse_frf(glued, "g");
  EXPECT_DOUBLE_EQ(r.frf.receptance_m_per_n[0].real(), -1e-100);
  EXPECT_DOUBLE_EQ(r.frf.receptance_m_per_n[0].imag(), -2e-101);
  EXPECT_DOUBLE_EQ(r.frf.receptance_m_per_n[2].imag(), 4e-8);
  const std::string loose =
      "    -1\n    58\nid\nNONE\nNONE\nNONE\nNONE\n 4 1 0 0 NONE 1 1 NONE 1 1\n"
      " 6 3 0 0 0 0\n 18 0 0 0 Frequency Hz\n 8 0 0 0 Displacement m\n"
      " 13 0 0 0 Force N\n 0 0 0 0 NONE NONE\n"
      "10 1e-8 2e-8\n 20  3e-8  4e-8\n30.5 5E-8 6D-8\n    -1\n";
  const FrfReadResult l = parse_frf(loose, "l");
  EXPECT_EQ(l.frf.frequency_hz, (std::vector<double>{10, 20, 30.5}));
  EXPECT_DOUBLE_EQ(l.frf.receptance_m_per_n[2].imag(), 6e-8);
  EXPECT_TRUE(l.warnings.empty());
}

std::string be_bytes(double x) {
  std::string s;
  const auto bits = std::bit_cast<std::uint64_t>(x);
  for (int k = 7; k >= 0; --k) s += static_cast<char>((bits >> (8 * k)) & 0xffu);
  return s;
}

TEST(FrfFileUff, BigEndian58bWithFloatAbscissaIsRead) {
  // 3 points uneven, complex double, abscissa as 4-byte float (20 bytes a point), big endian.
  const std::vector<double> f = {10.0, 20.5, 40.25};
  const std::vector<std::complex<double>> v = {{1e-8, -2e-8}, {3e-8, 4e-8}, {-5e-8, 6e-9}};
  std::string data;
  for (std::size_t i = 0; i < 3; ++i) {
    const auto fb = std::bit_cast<std::uint32_t>(static_cast<float>(f[i]));
    for (int k = 3; k >= 0; --k) data += static_cast<char>((fb >> (8 * k)) & 0xffu);
    data += be_bytes(v[i].real()) + be_bytes(v[i].imag());
  }
  const std::string file =
      "    -1\n    58b     2     2          11          60     0     0           0           0\n" +
      uff58_header(4, 6, 3, false, 0, 0, 18, "Hz", 8, "m", 13, "N") + data + "    -1\n";
  const FrfReadResult r = parse_frf(file, "be");
  EXPECT_EQ(r.frf.frequency_hz, f);
  EXPECT_EQ(r.frf.receptance_m_per_n, v);
  // A wrong byte count, a float format that is not IEEE.
  std::string wrong = file;
  wrong.replace(wrong.find("          60"), 12, "          64");
  EXPECT_HAS(refusal_of(wrong),
             "line 2: 3 points of data type 6 (uneven) take 72 bytes; the id line gives 64");
  std::string vms = file;
  vms.replace(vms.find("58b     2     2"), 15, "58b     2     1");
  EXPECT_HAS(refusal_of(vms), "line 2: 58b floating-point format 1 is not read");
}

// ---- column formats -------------------------------------------------------------------

TEST(FrfFileText, SloppyButValidCutProIsAccepted) {
  const std::string text =
      "% CutPro FRF export\r\n"
      "; measured 2024-03-14\r\n"
      "\r\n"
      "Frequency Real Imaginary\r\n"
      "# data\r\n"
      "  10\t1.5e-8\t-2e-9   Hz   m/N  \r\n"
      "20 1.25e-8 -3e-9\r\n"
      "\t30\t+1.0e-8\t-4.5E-09\t\r\n"
      "\r\n";
  const FrfReadResult r = parse_frf(text, "t.frf");
  EXPECT_EQ(r.format, FrfFormat::kCutPro);
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
  EXPECT_EQ(r.frf.frequency_hz, (std::vector<double>{10, 20, 30}));
  EXPECT_EQ(r.frf.receptance_m_per_n, (std::vector<std::complex<double>>{
                                          {1.5e-8, -2e-9}, {1.25e-8, -3e-9}, {1e-8, -4.5e-9}}));
  // Units stated in the header or after the first numbers are applied; unknown words warned.
  const FrfReadResult mm = parse_frf("f[Hz] re[mm/N] im[mm/N]\n1 1 2\n2 3 4\n3 5 6\n", "mm");
  EXPECT_EQ(mm.units, "Hz, mm/N");
  EXPECT_DOUBLE_EQ(mm.frf.receptance_m_per_n[2].imag(), 6e-3);
  const FrfReadResult um = parse_frf("1 1 2 Hz um/N\n2 3 4\n3 5 6\n", "um");
  EXPECT_DOUBLE_EQ(um.frf.receptance_m_per_n[1].real(), 3e-6);
  const FrfReadResult inch = parse_frf("1 1 2 Hz in/lbf\n2 3 4\n3 5 6\n", "in");
  EXPECT_DOUBLE_EQ(inch.frf.receptance_m_per_n[0].imag(), 2 * 0.0254 / 4.4482216152605);
  const FrfReadResult rad = parse_frf("w[rad/s] G[µm/N]\n1 1 2\n2 3 4\n3 5 6\n", "rad");
  EXPECT_DOUBLE_EQ(rad.frf.frequency_hz[2], 3 / kTwoPi);
  EXPECT_DOUBLE_EQ(rad.frf.receptance_m_per_n[2].real(), 5e-6);
  const FrfReadResult odd = parse_frf("1 1 2 furlongs\n2 3 4\n3 5 6\n", "odd");
  ASSERT_EQ(odd.warnings.size(), 1u);
  EXPECT_HAS(odd.warnings[0], "line 1: the word \"furlongs\"");
}

TEST(FrfFileText, UnitWordsCutdynDoesNotReadAreRefusedNamingTheLine) {
  const std::string data = "\n50 1e-8 -1e-9\n51 2e-8 -2e-9\n52 3e-8 -3e-9\n";
  // A unit in brackets after a column's label must be one cutdyn reads.
  EXPECT_HAS(refusal_of("Frequency[rpm] re[m/N] im[m/N]" + data),
             "line 1: \"rpm\" is a speed, not a frequency unit of an FRF");
  EXPECT_HAS(refusal_of("f[Hz] re[ft/N] im[ft/N]" + data),
             "line 1: \"ft/N\" is not a unit cutdyn knows");
  EXPECT_HAS(refusal_of("f[Hz] re[N/m] im[N/m]" + data),
             "line 1: \"N/m\" is a dynamic stiffness (force per displacement)");
  EXPECT_HAS(refusal_of("Freq[Hz] Mag[m/N] Phase[deg]" + data), "\"deg\" is a phase or level unit");
  // A word of its own that is written as a unit; after the first numbers too.
  EXPECT_HAS(refusal_of("Frequency Real Imaginary lbf/mm" + data), "\"lbf/mm\" is a dynamic stiffness");
  EXPECT_HAS(refusal_of("50 1e-8 -1e-9 Hz ft/N\n51 2e-8 -2e-9\n52 3e-8 -3e-9\n"),
             "line 1: \"ft/N\" is not a unit cutdyn knows");
  // Prose in a header, with a date and words in brackets, is not a unit.
  const FrfReadResult prose = parse_frf("tool (holder) tip 14/03/2024" + data, "prose");
  EXPECT_TRUE(prose.warnings.empty()) << prose.warnings.front();
  // The trailer CutPro writes after its first numbers is read silently.
  const FrfReadResult cutpro = parse_frf(
      "50\t1e-8\t-1e-9\tFreq Hz Real m/N Imag Real\n51 2e-8 -2e-9\n52 3e-8 -3e-9\n", "cutpro");
  EXPECT_TRUE(cutpro.warnings.empty()) << cutpro.warnings.front();
  EXPECT_EQ(cutpro.units, "Hz, m/N");

  // Units given from outside take the header's place (and its unknown words with it).
  FrfFileOptions given;
  given.units = "kHz, mm/N";
  const FrfReadResult r = parse_frf("f[rpm] re[ft/N] im[ft/N]" + data, "given", given);
  EXPECT_EQ(r.units, "kHz, mm/N");
  EXPECT_DOUBLE_EQ(r.frf.frequency_hz[1], 51e3);
  EXPECT_DOUBLE_EQ(r.frf.receptance_m_per_n[2].real(), 3e-11);
  given.units = "(m/s)/N";
  const FrfReadResult y = parse_frf("50 1 2\n51 3 4\n52 5 6\n", "given", given);
  EXPECT_EQ(y.quantity, FrfQuantity::kMobility);
  EXPECT_EQ(y.frf.receptance_m_per_n[0], std::complex<double>(1, 2) / std::complex<double>(0, kTwoPi * 50));
  given.units = "Hz, furlongs";
  EXPECT_HAS(refusal([&] { parse_frf(data, "given", given); }),
             "units = \"Hz, furlongs\": \"furlongs\" is not a frequency unit");
  given.units = "Hz";
  EXPECT_HAS(refusal([&] { parse_frf(data, "given", given); }), "no FRF unit");
  given.units = "mm/N";
  EXPECT_HAS(refusal([&] {
               parse_frf("frequency_hz,real_m_per_n,imag_m_per_n\n1,2,3\n2,2,3\n3,2,3\n", "c",
                         given);
             }),
             "this is a csv file, which states its own units");
}

TEST(FrfFileText, ATableThatIsNoDirectReceptanceIsToldWithTheEvidence) {
  // The tool's y receptance (two modes), and the same values as a mobility or accelerance
  // would store them. Each stored as what it is passes; each stored as another is named.
  const MeasuredFrf g = sample_frf(tool_model(), Direction::kY, every(5.0, 3000.0, 5.0));
  EXPECT_GT(negative_imaginary_share(g), 0.999);
  EXPECT_EQ(direct_receptance_problem(g, FrfQuantity::kReceptance), "");
  MeasuredFrf y = g, a = g;
  for (std::size_t i = 0; i < g.frequency_hz.size(); ++i) {
    const double w = kTwoPi * g.frequency_hz[i];
    y.receptance_m_per_n[i] *= std::complex<double>(0, w);
    a.receptance_m_per_n[i] *= -w * w;
  }
  // A mobility read as a receptance, and an accelerance.
  EXPECT_HAS(direct_receptance_problem(y, FrfQuantity::kReceptance),
             "The values behave like a mobility (velocity per force) stored as a receptance");
  EXPECT_HAS(direct_receptance_problem(a, FrfQuantity::kReceptance),
             "its imaginary part is positive over 100 %");
  EXPECT_HAS(direct_receptance_problem(a, FrfQuantity::kReceptance),
             "behave like an accelerance (acceleration per force)");
  // A receptance labelled mobility: the reader divided it by iω.
  MeasuredFrf divided = g;
  for (std::size_t i = 0; i < g.frequency_hz.size(); ++i)
    divided.receptance_m_per_n[i] /= std::complex<double>(0, kTwoPi * g.frequency_hz[i]);
  EXPECT_HAS(direct_receptance_problem(divided, FrfQuantity::kMobility),
             "behave like a receptance (displacement per force) stored as a mobility");
  // Complex residues of ±40° (a peer's FRFs) and 3 % noise are still a receptance.
  ModalModel complex = tool_model();
  for (std::size_t i = 0; i < complex.modes.size(); ++i)
    complex.modes[i].residue_phase_rad = (i % 2 ? -1.0 : 1.0) * 40.0 * kTwoPi / 360.0;
  MeasuredFrf noisy = sample_frf(complex, Direction::kX, every(5.0, 3000.0, 5.0));
  std::mt19937_64 rng(7);
  std::normal_distribution<double> e(0.0, 0.03);
  for (auto& v : noisy.receptance_m_per_n) v *= std::complex<double>(1 + e(rng), e(rng));
  EXPECT_EQ(direct_receptance_problem(noisy, FrfQuantity::kReceptance), "");
  // A cross receptance (modes of both signs) is not a direct one. (Where the negative modes
  // dominate, its phase is an accelerance's and the message says so.)
  MeasuredFrf cross = g;
  const MeasuredFrf other = sample_frf(tool_model(), Direction::kX, every(5.0, 3000.0, 5.0));
  for (std::size_t i = 0; i < g.frequency_hz.size(); ++i)
    cross.receptance_m_per_n[i] -= 2.0 * other.receptance_m_per_n[i];
  EXPECT_HAS(direct_receptance_problem(cross, FrfQuantity::kReceptance),
             "as a direct receptance its imaginary part is positive over");
  // Noise alone (no structure at all) is refused with the general reason.
  MeasuredFrf noise = g;
  std::mt19937_64 noise_rng(3);
  for (auto& v : noise.receptance_m_per_n) v = 1e-8 * std::complex<double>(e(noise_rng), e(noise_rng));
  EXPECT_HAS(direct_receptance_problem(noise, FrfQuantity::kReceptance),
             "a cross receptance belongs in direction = \"xy\"; or the table is mostly noise");
}

TEST(FrfFileText, CsvMobilityAndAccelerancePairsConvertToReceptance) {
  const MeasuredFrf g = sample_frf(tool_model(), Direction::kY, every(25.0, 3000.0, 25.0));
  std::string mobility =
      "\"imag_m_per_s_per_n\", \"frequency_hz\",coherence,\"real_m_per_s_per_n\"\r\n";
  std::string accelerance = "# exported\nfrequency_hz,real_m_per_s2_per_n,imag_m_per_s2_per_n\n";
  for (std::size_t i = 0; i < g.frequency_hz.size(); ++i) {
    const double f = g.frequency_hz[i], w = kTwoPi * f;
    const std::complex<double> y = std::complex<double>(0, w) * g.receptance_m_per_n[i];
    const std::complex<double> a = -w * w * g.receptance_m_per_n[i];
    mobility += fmt::format("{}, {},0.99,{}\r\n", y.imag(), f, y.real());
    accelerance += fmt::format("{},{},{}\n", f, a.real(), a.imag());
  }
  const FrfReadResult ry = parse_frf(mobility, "y.csv");
  EXPECT_EQ(ry.format, FrfFormat::kCsv);
  EXPECT_EQ(ry.quantity, FrfQuantity::kMobility);
  expect_close(ry.frf, g, 1e-14, "mobility");
  const FrfReadResult ra = parse_frf(accelerance, "a.csv");
  EXPECT_EQ(ra.quantity, FrfQuantity::kAccelerance);
  expect_close(ra.frf, g, 1e-14, "accelerance");
  // ω = 0 cannot be converted: the line is named.
  EXPECT_HAS(
      refusal_of("frequency_hz,real_m_per_s_per_n,imag_m_per_s_per_n\n0,1,2\n10,1,2\n20,1,2\n"),
      "line 2: the mobility at 0 Hz cannot be converted to receptance");
  // At 0 Hz a receptance is fine.
  EXPECT_EQ(parse_frf("frequency_hz,real_m_per_n,imag_m_per_n\n0,1,0\n10,1,2\n20,1,2\n", "r")
                .frf.min_hz(),
            0.0);
}

// ---- refusals -------------------------------------------------------------------------

TEST(FrfFileRefusal, TextTablesNameTheLine) {
  const std::string head = "% f re im\n";
  EXPECT_HAS(refusal_of(head + "100 1 2\n120 1 2\n120 1 2\n"),
             "line 4: frequency 120 Hz is not greater than the one before (120 Hz)");
  EXPECT_HAS(refusal_of(head + "100 1 2\n90 1 2\n120 1 2\n"),
             "line 3: frequency 90 Hz is not greater");
  EXPECT_HAS(refusal_of(head + "100 1 2\n110 nan 2\n120 1 2\n"),
             "line 3: the receptance (nan, 2) is not a finite");
  EXPECT_HAS(refusal_of(head + "100 1 2\n110 1 inf\n120 1 2\n"), "line 3: the receptance (1, inf)");
  EXPECT_HAS(refusal_of(head + "100 1 2\n1.2.3 1 2\n120 1 2\n"),
             "line 3: \"1.2.3\" is not a number (the frequency)");
  EXPECT_HAS(refusal_of(head + "100 1 2\n110 1,5 2\n120 1 2\n"),
             "line 3: \"1,5\" is not a number (the real part)");
  EXPECT_HAS(refusal_of(head + "100 1 2\n110 1\n120 1 2\n"), "line 3: 2 values; a data line has 3");
  EXPECT_HAS(refusal_of(head + "100 1 2\n110 1 2 3\n120 1 2\n"),
             "line 3: 4 fields; a data line has 3");
  EXPECT_HAS(refusal_of(head + "100 1 2\n110 1 2\n"), "2 data points: an FRF needs at least 3");
  EXPECT_HAS(refusal_of(head + "-1e3 1 2\n110 1 2\n120 1 2\n"),
             "line 2: frequency -1000 Hz is negative");
  EXPECT_HAS(refusal_of(head + "100 1 2\n110 1 2\nend of data\n"),
             "line 4: \"end\" is not a number");
  EXPECT_HAS(refusal_of("% only comments\n# here\n"), "no data line");
  EXPECT_HAS(refusal_of("1 1 2 Hz m/N\n2 1 2 Hz\n3 1 2\n"), "line 2: 4 fields");
  EXPECT_HAS(refusal_of("f[Hz] re[m/N] im[mm/N]\n1 1 2\n2 3 4\n3 5 6\n"),
             "line 1: a second FRF unit \"mm/N\" (m/N was stated on line 1)");
  // Many bad lines: the first twelve are listed, then a count.
  std::string many = head + "100 1 2\n";
  for (int i = 0; i < 20; ++i) many += "x 1 2\n";
  EXPECT_HAS(refusal_of(many), "... and 8 more lines like these");
}

TEST(FrfFileRefusal, CsvNamesColumnsAndLines) {
  EXPECT_HAS(refusal_of("frequency_hz,real_m_per_n\n1,2\n"), "line 1: missing column imag_m_per_n");
  EXPECT_HAS(refusal_of("freq,re,im\n1,2,3\n"),
             "missing columns frequency_hz, real_m_per_n and imag_m_per_n");
  EXPECT_HAS(refusal_of("1,2,3\n2,3,4\n"), "line 1: a CSV FRF file starts with a header");
  EXPECT_HAS(refusal_of("frequency_hz,real_m_per_n,imag_m_per_n\n1,2,3\n2,,3\n3,1,1\n"),
             "line 3: real_m_per_n is empty");
  EXPECT_HAS(refusal_of("frequency_hz,real_m_per_n,imag_m_per_n\n1,2,3\n2,3\n3,1,1\n"),
             "line 3: 2 fields, no imag_m_per_n (column 3 of the header)");
  EXPECT_HAS(refusal_of("frequency_hz,real_m_per_n,imag_m_per_n\n1,2,3\n2,x,3\n3,1,1\n"),
             "line 3: real_m_per_n = \"x\" is not a number");
  EXPECT_HAS(
      refusal_of("frequency_hz,real_m_per_n,imag_m_per_n,real_m_per_s_per_n,imag_m_per_s_per_n\n"),
      "columns of both receptance and mobility");
  EXPECT_HAS(refusal_of("frequency_hz,frequency_hz,real_m_per_n,imag_m_per_n\n"),
             "column frequency_hz appears twice");
  EXPECT_HAS(refusal_of("frequency_hz,real_m_per_n,imag_m_per_n\n"),
             "no data line after the header");
}

std::string good_uff(const std::string& header_override = {}) {
  return "    -1\n    58\n" +
         (header_override.empty() ? uff58_header(4, 6, 3, true, 10, 10, 18, "Hz", 8, "m", 13, "N")
                                  : header_override) +
         "  1.000000000000E-08  2.000000000000E-08  3.000000000000E-08  4.000000000000E-08\n"
         "  5.000000000000E-08  6.000000000000E-08\n    -1\n";
}

TEST(FrfFileRefusal, UffDatasetsThatAreNotAnFrf) {
  EXPECT_TRUE(refusal_of(good_uff()).empty()) << refusal_of(good_uff());
  EXPECT_HAS(refusal_of(good_uff(uff58_header(1, 6, 3, true, 10, 10, 17, "s", 8, "m", 13, "N"))),
             "no dataset 58 is a frequency response function (function type 4)");
  EXPECT_HAS(refusal_of(good_uff(uff58_header(4, 4, 3, true, 10, 10, 18, "Hz", 8, "m", 13, "N"))),
             "line 9: record 7: the ordinate is real (data type 4); an FRF is complex");
  EXPECT_HAS(refusal_of(good_uff(uff58_header(4, 6, 4, true, 10, 10, 18, "Hz", 8, "m", 13, "N"))),
             "line 9: record 7 announces 4 points (8 values), the data hold 6 values");
  EXPECT_HAS(refusal_of(good_uff(uff58_header(4, 6, 3, true, 10, 0, 18, "Hz", 8, "m", 13, "N"))),
             "the increment must be positive");
  EXPECT_HAS(refusal_of(good_uff(uff58_header(4, 6, 3, true, 10, 10, 17, "s", 8, "m", 13, "N"))),
             "line 10: record 8: the abscissa is time (specific data type 17), not frequency");
  EXPECT_HAS(refusal_of(good_uff(uff58_header(4, 6, 3, true, 10, 10, 18, "Hz", 13, "N", 8, "m"))),
             "line 11: record 9: the ordinate is excitation force (specific data type 13)");
  EXPECT_HAS(refusal_of(good_uff(uff58_header(4, 6, 3, true, 10, 10, 18, "Hz", 12, "mm", 13, "N"))),
             "record 9 says acceleration (specific data type 12) but its units label \"mm\" is a "
             "receptance unit");
  std::string unclosed = good_uff();
  unclosed.resize(unclosed.size() - 7);
  EXPECT_HAS(refusal_of(unclosed), "line 1: the dataset starting here has no closing -1 line");
  EXPECT_HAS(refusal_of("    -1\n   151\nx\n    -1\n"),
             "no dataset 58 (function at nodal DOF) in the file; its datasets are 151");
  EXPECT_HAS(refusal_of(good_uff() + "junk\n"),
             "line 17: expected a -1 line starting a dataset, found \"junk\"");
  std::string bad_number = good_uff();
  bad_number.replace(bad_number.find("3.000000000000E-08"), 18, "3.0000000000x0E-08");
  EXPECT_HAS(refusal_of(bad_number), "line 14: ");
  EXPECT_HAS(refusal_of(bad_number), "is not a line of numbers");
  EXPECT_HAS(refusal_of("100 1 2\n", ".uff"), "line 1: a universal file starts with a -1 line");
}

// Found by fuzz_frf (docs/fuzzing.md): a number where UFF has an integer field that no int
// holds (infinity, 1e300) was converted to int, which is undefined behaviour (x86 made it
// -2147483648, and the messages said so); such a field is now refused as the file writes it.
TEST(FrfFileRefusal, FuzzIntegerFieldsNoIntHoldsAreRefusedAsWritten) {
  const std::string good = good_uff();
  ASSERT_TRUE(refusal_of(good).empty());
  std::string type = good;  // record 7's first field: the ordinate data type
  type.replace(type.find("\n         6         3"), 21, "\n       inf         3");
  EXPECT_HAS(refusal_of(type),
             "line 9: record 7: ordinate data type inf must be 5 (complex single) or 6");
  std::string function = good;  // record 6's first field: the function type
  function.replace(function.find("\n    4         1"), 6, "\n1e300");
  EXPECT_HAS(refusal_of(function), "line 8: record 6 does not start with a function type");
}

class FrfFileRefusalOfFiles : public testing::TempDirTest {};

TEST_F(FrfFileRefusalOfFiles, MissingEmptyBinaryAndDirectoriesAreClear) {
  std::string where;
  EXPECT_HAS(refusal([&] { read_frf(dir_ / "none.frf"); }, &where), "no such file");
  EXPECT_EQ(where, (dir_ / "none.frf").string());
  EXPECT_HAS(refusal([&] { read_frf(dir_); }), "is a directory");
  std::ofstream(dir_ / "empty.csv").close();
  EXPECT_HAS(refusal([&] { read_frf(dir_ / "empty.csv"); }, &where), "the file is empty");
  EXPECT_EQ(where, (dir_ / "empty.csv").string());
  std::ofstream(dir_ / "blank.frf") << "  \n\n\t\n";
  EXPECT_HAS(refusal([&] { read_frf(dir_ / "blank.frf"); }), "only blank lines");
  std::string garbage = "PK\x03\x04";
  for (int i = 0; i < 256; ++i) garbage += static_cast<char>(i * 37);
  std::ofstream(dir_ / "g.frf", std::ios::binary) << garbage;
  EXPECT_HAS(refusal([&] { read_frf(dir_ / "g.frf"); }), "line 1: not a text file (byte 0x03");
  // Writing: an invalid table, a folder that does not exist.
  const MeasuredFrf two{{1.0, 2.0}, {{1, 0}, {1, 0}}, {}};
  EXPECT_HAS(refusal([&] { write_frf(dir_ / "two.frf", two, FrfFormat::kCutPro); }), "at least 3");
  FrfWriteOptions z;
  z.uff_response_direction = 7;
  EXPECT_HAS(
      refusal([&] {
        format_frf(sample_frf(tool_model(), Direction::kX, {1.0, 2.0, 3.0}), FrfFormat::kUff, z);
      }),
      "options.uff_response_direction = 7: must be a UFF direction from -6 to 6");
  const MeasuredFrf g = sample_frf(tool_model(), Direction::kX, {1.0, 2.0, 3.0});
  EXPECT_HAS(refusal([&] { write_frf(dir_ / "no" / "g.frf", g, FrfFormat::kCsv); }, &where),
             "cannot be opened");
  EXPECT_EQ(where, (dir_ / "no" / "g.frf").string());
}

// ---- the examples ---------------------------------------------------------------------

// The examples' table: the tool's receptance at 50, 51, ..., 3000 Hz plus complex Gaussian
// noise of standard deviation 1 % of |G| (σ/√2 on the real and on the imaginary part),
// drawn with mt19937_64 (fully specified by the standard) and Box–Muller.
MeasuredFrf example_table(Direction d, bool noisy) {
  MeasuredFrf g = sample_frf(tool_model(), d, every(50.0, 3000.0, 1.0));
  if (!noisy) return g;
  std::mt19937_64 bits(d == Direction::kX ? 520 : 610);
  const auto uniform = [&] { return (static_cast<double>(bits() >> 11) + 0.5) * 0x1p-53; };
  for (auto& v : g.receptance_m_per_n) {
    const double r = std::sqrt(-2.0 * std::log(uniform())), t = kTwoPi * uniform();
    v += 0.01 * std::abs(v) / std::sqrt(2.0) *
         std::complex<double>(r * std::cos(t), r * std::sin(t));
  }
  return g;
}

TEST(FrfExamples, AreTheirGeneratorsOutputAndAgreeWithTheirModes) {
  const fs::path dir = fs::path(CUTDYN_EXAMPLES_DIR) / "frf";
  const bool update = std::getenv("CUTDYN_UPDATE_EXAMPLES") &&
                      std::string(std::getenv("CUTDYN_UPDATE_EXAMPLES")) == "1";
  for (Direction d : {Direction::kX, Direction::kY}) {
    const std::string name = std::string("tool_") + to_string(d);
    const MeasuredFrf noisy = example_table(d, true), exact = example_table(d, false);
    if (update) {
      FrfWriteOptions o =
          described("cutdyn example " + name + ": the modes and noise of examples/frf/README.md");
      o.uff_response_direction = o.uff_reference_direction = d == Direction::kX ? 1 : 2;
      for (FrfFormat f : {FrfFormat::kCutPro, FrfFormat::kCsv, FrfFormat::kUff})
        EXPECT_TRUE(write_frf(dir / (name + "." + to_string(f)), noisy, f, o).empty());
    }
    const MeasuredFrf csv = read_frf(dir / (name + ".csv"));
    // The generator's table, to round-trip precision (the files hold what it writes).
    expect_close(csv, noisy, 1e-15, name + ".csv vs generator");
    // (a) the three formats give the same table.
    expect_close(read_frf(dir / (name + ".frf")), csv, 0.0, name + ".frf");
    const FrfReadResult uff = read_frf_file(dir / (name + ".uff"));
    EXPECT_TRUE(uff.warnings.empty());
    EXPECT_EQ(uff.uff_datasets.at(0).response_direction, d == Direction::kX ? 1 : 2);
    expect_close(uff.frf, csv, 1e-11, name + ".uff");
    // (b) within 5 % of the modes' receptance: 5σ of the noise, exceeded with probability
    // exp(−25) ≈ 1e-11 at a point (|n|²/σ² is exponential); and the noise is 1 % RMS.
    expect_close(csv, exact, 0.05, name + " vs modes");
    double sum = 0.0;
    for (std::size_t i = 0; i < csv.frequency_hz.size(); ++i)
      sum += std::norm((csv.receptance_m_per_n[i] - exact.receptance_m_per_n[i]) /
                       std::abs(exact.receptance_m_per_n[i]));
    const double rms = std::sqrt(sum / static_cast<double>(csv.frequency_hz.size()));
    EXPECT_GT(rms, 0.0095) << name;  // 2951 points: the mean square has 1.8 % standard error
    EXPECT_LT(rms, 0.0105) << name;
  }
}

}  // namespace
}  // namespace cutdyn
