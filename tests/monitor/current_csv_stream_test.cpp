// The monitor's CSV reader on hostile streams (docs/models/monitor.md §6): line ends of every
// kind, NUL bytes and binary data, lines far beyond the length limit, and its fast number
// parsing and formatting against std::from_chars and std::to_chars, value for value.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "cutdyn/core/error.hpp"
#include "cutdyn/monitor/current_csv.hpp"

namespace cutdyn {
namespace {

struct Parsed {
  std::vector<CurrentRow> rows;
  std::vector<CsvLineError> errors;
  bool stopped = false;  // feed or finish returned false
};

// Whole text at once (piece 0), or `piece` bytes at a time.
Parsed parse(std::string_view text, bool stop, std::size_t piece = 0) {
  CurrentCsvParser p("log.csv");
  Parsed r;
  if (piece == 0) piece = text.size() + 1;
  bool ok = true;
  for (std::size_t at = 0; ok && at < text.size(); at += piece)
    ok = p.feed(text.substr(at, piece), r.rows, r.errors, stop);
  if (ok) ok = p.finish(r.rows, r.errors, stop);
  r.stopped = !ok;
  return r;
}

// Rows equal to the bit, and on the same lines.
void expect_same_rows(const std::vector<CurrentRow>& a, const std::vector<CurrentRow>& b,
                      const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].line, b[i].line) << what << " row " << i;
    EXPECT_EQ(a[i].axis, b[i].axis) << what << " row " << i;
    for (const auto field : {&CurrentRow::time_s, &CurrentRow::iu_a, &CurrentRow::iv_a,
                             &CurrentRow::iw_a, &CurrentRow::speed_rad_s,
                             &CurrentRow::rotor_angle_rad})
      EXPECT_EQ(std::bit_cast<std::uint64_t>(a[i].*field),
                std::bit_cast<std::uint64_t>(b[i].*field))
          << what << " row " << i;
  }
}

std::vector<std::string> texts(const std::vector<CsvLineError>& errors) {
  std::vector<std::string> t;
  for (const CsvLineError& e : errors) t.push_back(e.text());
  return t;
}

const std::string kHeader = "time_s,axis,iu_a,iv_a,iw_a,speed_rad_s";

// ---- line ends ------------------------------------------------------------------------------

// Lines 1..6 joined by `ends` in turn: header, 3 good lines, a bad one (line 5), a good one.
std::string log_with_ends(const std::vector<std::string>& ends, bool last_end = true) {
  const std::vector<std::string> lines = {kHeader,
                                          "0,x,1,-0.5,-0.5,10",
                                          "0.001,x,2,-1,-1,11",
                                          "0,y,3,-1.5,-1.5,-12",
                                          "0.002,x,ten,1,1,13",
                                          "0.003,x,4,-2,-2,14"};
  std::string text;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    text += lines[i];
    if (i + 1 < lines.size() || last_end) text += ends[i % ends.size()];
  }
  return text;
}

TEST(MonitorCsvStream, EveryKindOfLineEndGivesTheSameRowsAndLineNumbers) {
  const Parsed lf = parse(log_with_ends({"\n"}), false);
  ASSERT_EQ(lf.rows.size(), 4u);
  EXPECT_EQ(lf.rows[3].line, 6u);
  EXPECT_EQ(lf.rows[2].speed_rad_s, -12.0);
  ASSERT_EQ(texts(lf.errors), std::vector<std::string>{"line 5: iu_a = \"ten\": not a number"});
  const std::vector<std::vector<std::string>> kinds = {
      {"\r\n"}, {"\r"}, {"\n", "\r\n", "\r"}, {"\r", "\r\n"}, {"\r\n", "\r", "\n"}};
  for (const auto& ends : kinds) {
    for (const bool last_end : {true, false}) {
      const std::string text = log_with_ends(ends, last_end);
      for (const std::size_t piece : {0, 1, 2, 3, 5, 7, 64}) {
        const std::string what = "ends " + std::to_string(ends.size()) + " first \"" +
                                 (ends[0] == "\r"   ? "CR"
                                  : ends[0] == "\n" ? "LF"
                                                    : "CRLF") +
                                 "\" piece " + std::to_string(piece);
        const Parsed r = parse(text, false, piece);
        expect_same_rows(r.rows, lf.rows, what);
        EXPECT_EQ(texts(r.errors), texts(lf.errors)) << what;
      }
    }
  }
}

TEST(MonitorCsvStream, ACarriageReturnSplitFromItsLineFeedIsOneLineEnd) {
  // "\r" ends one piece, "\n" begins the next: one line end, not a blank line between (the
  // line numbers after it would be off by one).
  const std::string text = kHeader + "\r\n0,x,1,1,1,5\r\n0.001,x,1,1,1,5\r\n0.002,x,1,1,1,5";
  const std::size_t cut = text.find("\r\n0.001") + 1;
  CurrentCsvParser p("log.csv");
  std::vector<CurrentRow> rows;
  std::vector<CsvLineError> errors;
  ASSERT_TRUE(p.feed(std::string_view(text).substr(0, cut), rows, errors, true));
  ASSERT_TRUE(p.feed(std::string_view(text).substr(cut), rows, errors, true));
  ASSERT_TRUE(p.finish(rows, errors, true));
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[1].line, 3u);
  EXPECT_EQ(rows[2].line, 4u);
  // Two CRs are two line ends (a blank line between), as are CR and CR LF.
  const Parsed r = parse(kHeader + "\r\r0,x,1,1,1,5\r\r\n0.001,x,1,1,1,5\r", true);
  ASSERT_EQ(r.rows.size(), 2u);
  EXPECT_EQ(r.rows[0].line, 3u);
  EXPECT_EQ(r.rows[1].line, 5u);
}

TEST(MonitorCsvStream, AByteOrderMarkBeforeTheHeaderIsSkipped) {
  const Parsed r = parse("\xef\xbb\xbf" + kHeader + "\r\n0,x,1,1,1,5\r\n", true, 1);
  ASSERT_EQ(r.rows.size(), 1u);
  EXPECT_TRUE(r.errors.empty());
}

// ---- NUL bytes and binary data ----------------------------------------------------------

TEST(MonitorCsvStream, NulAndControlBytesMakeABadLineNamingTheByte) {
  using namespace std::string_literals;
  const std::string text = kHeader + "\n0,x,1,1,1,5\n" +
                           "0.001,x,1\0,1,1,5\n"s +     // line 3: in a number
                           "0.002,x\0,1,1,1,5\n"s +     // line 4: in the axis
                           "0.003,x,1,1,1,5,\0\n"s +    // line 5: in a column nobody reads
                           "\0\0\0\0\n"s +              // line 6: nothing else
                           "0.004,x,1,1,1,\x1b[0m\n" +  // line 7: an escape sequence
                           "0.005,x,1,1,1,5\x7f\n" +    // line 8: DEL
                           "0.006,x,1,1,1,5\n";         // line 9: good
  for (const std::size_t piece : {0, 1, 4, 9}) {
    const Parsed r = parse(text, false, piece);
    ASSERT_EQ(r.rows.size(), 2u) << piece;
    EXPECT_EQ(r.rows[1].line, 9u);
    EXPECT_EQ(r.rows[1].time_s, 0.006);
    EXPECT_EQ(texts(r.errors),
              (std::vector<std::string>{
                  "line 3: a NUL byte at byte 10 of the line: binary data, not text",
                  "line 4: a NUL byte at byte 8 of the line: binary data, not text",
                  "line 5: a NUL byte at byte 17 of the line: binary data, not text",
                  "line 6: a NUL byte at byte 1 of the line: binary data, not text",
                  "line 7: a control byte 0x1b at byte 15 of the line: binary data, not text",
                  "line 8: a control byte 0x7f at byte 16 of the line: binary data, not text"}))
        << piece;
  }
  // stop: the first one ends the run.
  const Parsed s = parse(text, true, 4);
  EXPECT_TRUE(s.stopped);
  ASSERT_EQ(s.errors.size(), 1u);
  EXPECT_EQ(s.errors[0].line, 3u);
  EXPECT_EQ(s.rows.size(), 1u);
  // A tab is a blank, not binary.
  EXPECT_TRUE(parse(kHeader + "\n0,\tx\t,1,1,1,5\t\n", true).errors.empty());
  // Before the header it is an error of the input.
  try {
    parse("time_s,axis\0,iu_a\n"s, false);
    ADD_FAILURE() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.problems().at(0),
              "line 1: a NUL byte at byte 12 of the line: binary data, not text (before the "
              "header)");
  }
}

// Universal line ends, the reference: the numbers of the non-blank lines of `text`.
std::vector<std::size_t> non_blank_lines(const std::string& text) {
  std::vector<std::size_t> numbers;
  std::string line;
  std::size_t number = 0;
  const auto end_line = [&] {
    ++number;
    if (line.find_first_not_of(" \t") != std::string::npos) numbers.push_back(number);
    line.clear();
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\n') {
      end_line();
    } else if (text[i] == '\r') {
      end_line();
      if (i + 1 < text.size() && text[i + 1] == '\n') ++i;
    } else {
      line += text[i];
    }
  }
  if (!line.empty()) end_line();
  return numbers;
}

TEST(MonitorCsvStream, ABinaryBlobIsSkippedLineByLineAndTheStreamGoesOn) {
  std::mt19937 rng(7);
  std::string blob(64 * 1024, '\0');
  for (char& c : blob) c = static_cast<char>(rng() & 0xff);
  std::string before = kHeader + "\n", after;
  for (int k = 0; k < 50; ++k) {
    before += std::to_string(k) + "e-3,x," + std::to_string(k) + ",-1,-1,50\n";
    after += std::to_string(100 + k) + "e-3,x," + std::to_string(k) + ",-1,-1,50\n";
  }
  const std::string text = before + blob + "\n" + after;
  const std::vector<std::size_t> lines = non_blank_lines(text);
  const std::size_t blob_lines = lines.size() - 101;  // all but the header and the good lines
  ASSERT_GT(blob_lines, 300u);  // 64 KiB of random bytes: about 1 line end in 128 bytes
  for (const std::size_t piece : {0, 4096, 65536}) {
    const Parsed r = parse(text, false, piece);
    ASSERT_EQ(r.rows.size(), 100u) << piece;
    EXPECT_EQ(r.rows[50].time_s, 0.1);
    EXPECT_EQ(r.rows[99].iu_a, 49.0);
    EXPECT_EQ(r.errors.size(), blob_lines) << piece;
    // Every message is text: valid UTF-8, so that it can go into JSON.
    for (const CsvLineError& e : r.errors) EXPECT_NO_THROW((void)nlohmann::json(e.text()).dump());
  }
  const Parsed s = parse(text, true, 4096);
  EXPECT_TRUE(s.stopped);
  ASSERT_EQ(s.errors.size(), 1u);
  EXPECT_EQ(s.errors[0].line, lines.at(51));  // the blob's first (non-blank) line
  EXPECT_EQ(s.rows.size(), 50u);
}

TEST(MonitorCsvStream, MessagesShowOtherBytesEscaped) {
  const Parsed r =
      parse(kHeader + "\n0,x,1,\xff\xfe,1,5\n0,\xc3\xa9,1,1,1,5\n0,\xff,1,1,1,5\n", false);
  ASSERT_EQ(r.errors.size(), 2u);
  EXPECT_EQ(r.errors[0].text(), "line 2: iv_a = \"\\xff\\xfe\": not a number");
  EXPECT_EQ(r.errors[1].text(), "line 4: axis = \"\\xff\": not UTF-8 text");
  ASSERT_EQ(r.rows.size(), 1u);  // "é" is an axis name like any other
  EXPECT_EQ(r.rows[0].line, 3u);
}

// ---- long lines ---------------------------------------------------------------------------

TEST(MonitorCsvStream, ALineOfTenMegabytesIsSkippedWithItsLength) {
  const std::string head = kHeader + "\n0,x,1,1,1,5\n";
  const std::string tail = "0.001,x,1,1,1,5\n0.002,x,1,1,1,5\n";
  const std::string huge = "0.0005,x,1,1,1," + std::string(10'000'000, '7');  // 10 000 015 bytes
  for (const std::size_t piece : {0, 65536, 1000003}) {
    const Parsed r = parse(head + huge + "\n" + tail, false, piece);
    ASSERT_EQ(r.rows.size(), 3u) << piece;
    EXPECT_EQ(r.rows[2].line, 5u);
    EXPECT_EQ(texts(r.errors),
              std::vector<std::string>{"line 3: the line is 10000015 bytes long, longer than the "
                                       "limit of 1048576 bytes (1 MiB)"})
        << piece;
  }
  // With CR LF, and as the last line without a line end.
  EXPECT_EQ(texts(parse(head + huge + "\r\n" + tail, false, 65536).errors),
            texts(parse(head + huge + "\n" + tail, false, 65536).errors));
  EXPECT_EQ(texts(parse(head + huge, false, 65536).errors),
            std::vector<std::string>{"line 3: the line is 10000015 bytes long, longer than the "
                                     "limit of 1048576 bytes (1 MiB)"});
  // stop: refused as soon as it passes the limit, not at its end (which may never come).
  CurrentCsvParser p("log.csv");
  std::vector<CurrentRow> rows;
  std::vector<CsvLineError> errors;
  const std::string text = head + huge;
  std::size_t fed = 0;
  bool ok = true;
  while (ok && fed < text.size()) {
    ok = p.feed(std::string_view(text).substr(fed, 65536), rows, errors, true);
    fed += 65536;
  }
  EXPECT_FALSE(ok);
  EXPECT_EQ(fed, 17u * 65536);  // the piece in which the line passed 1 MiB
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].text(),
            "line 3: the line is longer than the limit of 1048576 bytes (1 MiB): " +
                std::to_string(17 * 65536 - head.size()) + " bytes without a line end so far");
}

TEST(MonitorCsvStream, TheLimitIsOneMebibyteExactly) {
  // A good line padded with blanks to the limit is read; one byte more is a bad line.
  const std::string line = "0.001,x,1,1,1,5";
  const std::string at_limit = line + std::string(kMaxCurrentLineBytes - line.size(), ' ');
  for (const std::size_t piece : {0, 65536}) {
    const Parsed r = parse(kHeader + "\n" + at_limit + "\n" + at_limit + " \n", false, piece);
    ASSERT_EQ(r.rows.size(), 1u);
    EXPECT_EQ(r.rows[0].speed_rad_s, 5.0);
    EXPECT_EQ(texts(r.errors), std::vector<std::string>{"line 3: the line is 1048577 bytes long, "
                                                        "longer than the limit of 1048576 bytes "
                                                        "(1 MiB)"});
  }
  // A header beyond the limit is an error of the input.
  try {
    parse(kHeader + std::string(kMaxCurrentLineBytes, ',') + "\n0,x,1,1,1,5\n", false, 65536);
    ADD_FAILURE() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.problems().at(0).rfind("line 1: the line is longer than the limit", 0), 0u)
        << e.problems().at(0);
  }
}

// ---- the fast path and the general one give the same rows -------------------------------------

TEST(MonitorCsvStream, FastAndGeneralPathsReadTheSameNumbers) {
  // The same values written plainly (the fast path) and with blanks around each field (the
  // general path): the same rows to the bit. Numbers of every form the logs use.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> digits(1, 17), exponent(-30, 30);
  std::string plain = kHeader + "\n", blanks = kHeader + "\n";
  char buffer[64];
  for (int k = 0; k < 20000; ++k) {
    std::string fields[4];
    for (std::string& f : fields) {
      const double v = u(rng) * std::pow(10.0, exponent(rng));
      const char* form = k % 3 == 0 ? "%.*g" : k % 3 == 1 ? "%.*e" : "%.*f";
      std::snprintf(buffer, sizeof buffer, form, digits(rng), v);
      f = buffer;
    }
    const std::string t = std::to_string(k) + "e-4";
    plain += t + ",x," + fields[0] + "," + fields[1] + "," + fields[2] + "," + fields[3] + "\n";
    blanks += " " + t + " , x ,\t" + fields[0] + " ," + fields[1] + " , " + fields[2] + "\t, " +
              fields[3] + " \n";
  }
  const Parsed a = parse(plain, true, 65536), b = parse(blanks, true, 65536);
  ASSERT_TRUE(a.errors.empty());
  ASSERT_TRUE(b.errors.empty());
  expect_same_rows(a.rows, b.rows, "plain against blanks");
  // And each is what std::from_chars gives.
  std::size_t at = plain.find('\n') + 1;
  for (const CurrentRow& row : a.rows) {
    const std::size_t end = plain.find('\n', at);
    std::vector<double> expect;
    for (std::size_t p = at; p <= end;) {
      const std::size_t stop = std::min(plain.find(',', p), end);
      double v = 0.0;
      if (plain.compare(p, stop - p, "x") != 0) {
        std::from_chars(plain.data() + p, plain.data() + stop, v);
        expect.push_back(v);
      }
      p = stop + 1;
    }
    ASSERT_EQ(expect.size(), 5u);
    EXPECT_EQ(std::bit_cast<std::uint64_t>(row.time_s), std::bit_cast<std::uint64_t>(expect[0]));
    EXPECT_EQ(std::bit_cast<std::uint64_t>(row.iu_a), std::bit_cast<std::uint64_t>(expect[1]));
    EXPECT_EQ(std::bit_cast<std::uint64_t>(row.iv_a), std::bit_cast<std::uint64_t>(expect[2]));
    EXPECT_EQ(std::bit_cast<std::uint64_t>(row.iw_a), std::bit_cast<std::uint64_t>(expect[3]));
    EXPECT_EQ(std::bit_cast<std::uint64_t>(row.speed_rad_s),
              std::bit_cast<std::uint64_t>(expect[4]));
    at = end + 1;
  }
}

TEST(MonitorCsvStream, TheFastPathAgreesWithTheGeneralOneOnDamagedLines) {
  // Fed a byte at a time every line goes through the general path (it spans two pieces); fed
  // whole, the good ones take the fast path. On 20 000 lines of every damage — numbers of
  // every form and length, signs, exponents, points, blanks, stray bytes, missing and extra
  // fields, times out of order, two axes — both give the same rows and the same errors.
  std::mt19937_64 rng(17);
  const auto pick = [&](std::size_t n) { return static_cast<std::size_t>(rng() % n); };
  const std::vector<std::string> numbers = {"1",
                                            "-2",
                                            "0",
                                            "-0",
                                            "12.5",
                                            "-0.125",
                                            "3.14159265",
                                            "123456789.5",
                                            "1.23456789012",
                                            "1e3",
                                            "-2.5E-3",
                                            "1.",
                                            ".5",
                                            "-.5",
                                            "+4",
                                            "+-4",
                                            "--4",
                                            "1.2.3",
                                            "0x10",
                                            "inf",
                                            "nan",
                                            "99999999.99999999",
                                            "12345678901234567890",
                                            "0.00000000000000000001",
                                            "1e400",
                                            "7,",
                                            "",
                                            " 5",
                                            "5 ",
                                            "\t6",
                                            "8\x01",
                                            "9\x80"};
  std::string text = "time_s,axis,iu_a,iv_a,iw_a,speed_rad_s\n";
  for (int k = 0; k < 20000; ++k) {
    std::string line =
        std::to_string(k / 2) + "." + std::to_string(pick(1000)) + "e-3," + (k % 2 ? "x" : "y");
    for (int f = 0; f < 4; ++f)
      line += "," + (pick(4) == 0
                         ? numbers[pick(numbers.size())]
                         : std::to_string(static_cast<double>(rng() % 2000000) / 1000.0 - 1000.0));
    if (pick(20) == 0) line += ",extra";
    if (pick(20) == 0) line.erase(pick(line.size() + 1));
    if (!line.empty() && pick(30) == 0) line[pick(line.size())] = ',';
    text += line + (pick(10) == 0 ? "\r\n" : "\n");
  }
  const Parsed general = parse(text, false, 1), fast = parse(text, false);
  EXPECT_GT(fast.rows.size(), 5000u);
  EXPECT_GT(fast.errors.size(), 2000u);
  expect_same_rows(fast.rows, general.rows, "whole against a byte at a time");
  EXPECT_EQ(texts(fast.errors), texts(general.errors));
}

TEST(MonitorCsvStream, TheSeparatedLineReaderAgreesWithTheGeneralOne) {
  // Lines of plain decimals, the form loggers write, are read with all their separators found
  // at once and their numbers side by side. On lines of every digit count on either side of
  // the point (0 to 10), signs, CR LF, and one damaged byte, field or line end in five, with
  // and without the rotor angle column: the same rows (to the bit, each what std::from_chars
  // reads) and the same errors as a byte at a time through the general path.
  std::mt19937_64 rng(29);
  const auto pick = [&](std::size_t n) { return static_cast<std::size_t>(rng() % n); };
  const auto digits = [&](std::size_t n) {
    std::string d;
    for (std::size_t i = 0; i < n; ++i) d += static_cast<char>('0' + pick(10));
    return d;
  };
  const std::string damage = "-+.,e \t\x01\x80x0";  // (a lone CR: the tests above)
  for (const bool angle : {false, true}) {
    std::string text = kHeader + (angle ? ",rotor_angle_rad\n" : "\n");
    for (int k = 0; k < 20000; ++k) {
      std::string line =
          std::to_string(k / 3) + "." + digits(1 + pick(4)) + "," + std::string(1, "xyz"[k % 3]);
      for (int f = 0; f < (angle ? 5 : 4); ++f) {
        const std::size_t whole = pick(4) == 0 ? pick(11) : 1 + pick(3);
        const std::size_t fraction = pick(4) == 0 ? pick(11) : 1 + pick(8);
        line += std::string(",") + (pick(2) ? "-" : "") + digits(whole) +
                (fraction > 0 || pick(8) == 0 ? "." : "") + digits(fraction);
      }
      if (pick(5) == 0) {  // after the time (a time damaged ahead would refuse the lines after)
        const std::size_t at = line.find(',') + 1;
        switch (pick(4)) {
          case 0:
            line[at + pick(line.size() - at)] = damage[pick(damage.size())];
            break;
          case 1:
            line.insert(at + pick(line.size() - at + 1), 1, damage[pick(damage.size())]);
            break;
          case 2:
            line += ",5";
            break;
          default:
            line.erase(line.rfind(','));
            break;
        }
      }
      text += line + (pick(8) == 0 ? "\r\n" : "\n");
    }
    const std::string what = angle ? "with the rotor angle" : "without";
    const Parsed general = parse(text, false, 1), fast = parse(text, false);
    EXPECT_GT(fast.rows.size(), 12000u) << what;
    EXPECT_GT(fast.errors.size(), 500u) << what;
    expect_same_rows(fast.rows, general.rows, what + ": whole against a byte at a time");
    EXPECT_EQ(texts(fast.errors), texts(general.errors)) << what;
    // Each number is what std::from_chars reads from its field.
    std::vector<std::string> lines;
    for (std::size_t at = 0, end; (end = text.find('\n', at)) != std::string::npos; at = end + 1)
      lines.push_back(text.substr(at, end - at));
    for (const CurrentRow& row : fast.rows) {
      std::string line = lines.at(row.line - 1);
      if (!line.empty() && line.back() == '\r') line.pop_back();
      std::vector<double> expect;
      for (std::size_t at = 0;;) {
        const std::size_t stop = std::min(line.find(',', at), line.size());
        double v = 0.0;
        if (expect.size() != 1) {  // blanks around a number, and a '+', are allowed
          std::size_t a = at, b = stop;
          while (a < b && (line[a] == ' ' || line[a] == '\t')) ++a;
          while (b > a && (line[b - 1] == ' ' || line[b - 1] == '\t')) --b;
          if (a < b && line[a] == '+') ++a;
          std::from_chars(line.data() + a, line.data() + b, v);
        }
        expect.push_back(v);
        if (stop == line.size()) break;
        at = stop + 1;
      }
      ASSERT_EQ(expect.size(), angle ? 7u : 6u) << line;
      const double got[] = {row.time_s,         0.0, row.iu_a, row.iv_a, row.iw_a, row.speed_rad_s,
                            row.rotor_angle_rad};
      for (std::size_t f = 0; f < expect.size(); ++f)
        EXPECT_EQ(std::bit_cast<std::uint64_t>(got[f]), std::bit_cast<std::uint64_t>(expect[f]))
            << line << " field " << f;
    }
  }
}

TEST(MonitorCsvStream, TheSeparatedLineReaderIsExactAtTheEdgesOfItsForm) {
  // The line reader values [-]W.F with 1 to 8 digits on each side as (W·10^8 + F·10^(8 − n))/10^8,
  // exact below 2^53 = 9007199254740992; at and above it the general reader takes the number.
  // Each value is what std::from_chars reads, to the bit: 8 + 8 digits on either side of 2^53,
  // all nines, zeros and negative zeros, leading zeros, one digit on each side; in every column,
  // with and without the rotor angle, and the rows the same through the general path.
  const std::vector<std::string> numbers = {
      "90071992.54740991", "90071992.54740992", "90071992.54740993", "99999999.99999999",
      "-99999999.99999999", "12345678.12345678", "0.0", "-0.0", "00000000.00000000",
      "-00000000.00000001", "00000001.10000000", "9.9", "-9.99999999", "0.00000001",
      "1.5", "-1.5", "9007199.2547409921", "4503599.62737049"};
  for (const bool angle : {false, true}) {
    const std::size_t columns = angle ? 6 : 5;
    std::string text = kHeader + (angle ? ",rotor_angle_rad\n" : "\n");
    std::vector<std::vector<std::string>> fields;
    for (std::size_t k = 0; k < numbers.size() * columns; ++k) {
      std::vector<std::string> f;
      for (std::size_t c = 0; c < columns; ++c)
        f.push_back(c == 0 ? std::to_string(k) + ".5" : numbers[(k + 7 * c) % numbers.size()]);
      std::string line = f[0] + ",x";
      for (std::size_t c = 1; c < columns; ++c) line += "," + f[c];
      text += line + "\n";
      fields.push_back(f);
    }
    const Parsed fast = parse(text, true), general = parse(text, true, 1);
    ASSERT_EQ(fast.rows.size(), fields.size());
    ASSERT_TRUE(fast.errors.empty());
    expect_same_rows(fast.rows, general.rows, angle ? "with the angle" : "without");
    for (std::size_t k = 0; k < fields.size(); ++k) {
      const CurrentRow& row = fast.rows[k];
      const double got[] = {row.time_s,         row.iu_a, row.iv_a, row.iw_a,
                            row.speed_rad_s, row.rotor_angle_rad};
      for (std::size_t c = 0; c < columns; ++c) {
        const std::string& f = fields[k][c];
        double expect = 0.0;
        std::from_chars(f.data(), f.data() + f.size(), expect);
        EXPECT_EQ(std::bit_cast<std::uint64_t>(got[c]), std::bit_cast<std::uint64_t>(expect))
            << f << " in column " << c;
      }
      if (!angle) {
        EXPECT_EQ(std::bit_cast<std::uint64_t>(row.rotor_angle_rad), 0u);
      }
    }
  }
}

// ---- numbers: the same as std::from_chars and std::to_chars -----------------------------------

// Alone, and followed by more of a line (the reader then looks at whole words of it).
void expect_parse_like_from_chars(const std::string& number) {
  for (const std::string& s : {number, number + ",x,12.5,-3,4.25e1,0.5,7\n0.001,x,1,2"}) {
    double mine = -7.0, theirs = -7.0;
    const auto a = parse_double(s.data(), s.data() + s.size(), mine);
    const auto b = std::from_chars(s.data(), s.data() + s.size(), theirs);
    ASSERT_EQ(a.ec, b.ec) << '"' << s << '"';
    ASSERT_EQ(a.ptr - s.data(), b.ptr - s.data()) << '"' << s << '"';
    ASSERT_EQ(std::bit_cast<std::uint64_t>(mine), std::bit_cast<std::uint64_t>(theirs))
        << '"' << s << '"';
  }
}

TEST(MonitorCsvNumbers, ParseDoubleIsFromChars) {
  // Known answers first.
  double v = 0.0;
  const std::string tenth = "0.1";
  parse_double(tenth.data(), tenth.data() + 3, v);
  EXPECT_EQ(v, 0.1);
  for (const char* s : {"0",
                        "-0",
                        "0.0",
                        "-0.000",
                        "00012",
                        "12.",
                        ".5",
                        "-.5",
                        "5.e3",
                        "1e22",
                        "1e23",
                        "1e-22",
                        "1e-23",
                        "9007199254740992",
                        "9007199254740993",
                        "9007199254740993e-5",
                        "1234567890123456789",
                        "12345678901234567890",
                        "0.1234567890123456789",
                        "1e",
                        "1e+",
                        "1e-",
                        "1ex",
                        "1e400",
                        "-1e400",
                        "1e-400",
                        "4.9e-324",
                        "2.2250738585072011e-308",
                        "inf",
                        "-inf",
                        "nan",
                        "NaN",
                        "infinity",
                        "-",
                        "",
                        ".",
                        "0x10",
                        "1.5x",
                        "1e5x",
                        "1,2",
                        "1 ",
                        " 1",
                        "+1",
                        "--1",
                        "1e00000000000000000005",
                        "000000000000000000000000001.5",
                        "0.00000000000000000000000000015",
                        "123456.7890e-3",
                        "1E5",
                        "1e+05",
                        "8.5e-2"})
    expect_parse_like_from_chars(s);
  // Random values in every form the logs write.
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<int> digits(1, 20), exponent(-40, 40), form(0, 4);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  char buffer[96];
  for (int k = 0; k < 300000; ++k) {
    const double x = u(rng) * std::pow(10.0, exponent(rng));
    const int d = digits(rng);
    switch (form(rng)) {
      case 0:
        std::snprintf(buffer, sizeof buffer, "%.*g", d, x);
        break;
      case 1:
        std::snprintf(buffer, sizeof buffer, "%.*e", d, x);
        break;
      case 2:
        std::snprintf(buffer, sizeof buffer, "%.*f", d % 12, x);
        break;
      case 3:
        std::snprintf(buffer, sizeof buffer, "%.*E", d, x);
        break;
      default:
        std::snprintf(buffer, sizeof buffer, "%lld", static_cast<long long>(rng() >> d));
    }
    expect_parse_like_from_chars(buffer);
  }
}

void expect_format_like_to_chars(double x) {
  std::string shortest, seven;
  append_number(shortest, x);
  append_number(seven, x, 7);
  char buffer[64];
  auto r = std::to_chars(buffer, buffer + sizeof buffer, x);
  ASSERT_EQ(shortest, std::string(buffer, r.ptr)) << std::hexfloat << x;
  r = std::to_chars(buffer, buffer + sizeof buffer, x, std::chars_format::general, 7);
  ASSERT_EQ(seven, std::string(buffer, r.ptr)) << std::hexfloat << x;
}

TEST(MonitorCsvNumbers, AppendNumberIsToChars) {
  // Known answers first.
  std::string s;
  append_number(s, 1234.56789012, 7);
  append_number(s += ' ', 0.001);
  append_number(s += ' ', 1e-5);
  append_number(s += ' ', 123456789.0, 7);
  append_number(s += ' ', -0.000123456789, 7);
  append_number(s += ' ', 1e22);
  append_number(s += ' ', 9999999.5, 7);
  EXPECT_EQ(s, "1234.568 0.001 1e-05 1.234568e+08 -0.0001234568 1e+22 1e+07");
  for (const double x : {0.0,
                         -0.0,
                         1.0,
                         -1.0,
                         0.5,
                         1e-5,
                         1e-4,
                         1e15,
                         1e16,
                         1e17,
                         1e21,
                         1e22,
                         1e23,
                         123456789012345.0,
                         1234567890123456.0,
                         0.1,
                         0.2,
                         0.3,
                         1.0 / 3.0,
                         5e-324,
                         2.2250738585072014e-308,
                         1.7976931348623157e308,
                         1234567.5,
                         1234568.5,
                         0.00012345675,
                         9999999.5,
                         999999.95,
                         99999995.0,
                         // Up to 7 digits, where the fixed and the scientific forms compete.
                         10000.0,
                         100000.0,
                         120000.0,
                         1000000.0,
                         9999999.0,
                         0.00012,
                         0.0001234567,
                         333.333,
                         -2.5})
    expect_format_like_to_chars(x);
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<int> exponent(-30, 40), digits(1, 17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 400000; ++k) {
    // Noisy values of every magnitude, and short decimals (times) of every length.
    expect_format_like_to_chars(u(rng) * std::pow(10.0, exponent(rng)));
    const int d = digits(rng);
    const double m = std::floor(std::fabs(u(rng)) * std::pow(10.0, d));
    expect_format_like_to_chars(m * std::pow(10.0, exponent(rng) - d));
    expect_format_like_to_chars(std::stod(std::to_string(k) + "e-" + std::to_string(k % 9)));
    // Ties and near ties of the 7th digit.
    const double tie =
        (std::floor(std::fabs(u(rng)) * 9e6) + 1e6 + 0.5) * std::pow(10.0, k % 7 - 6);
    expect_format_like_to_chars(tie);
    expect_format_like_to_chars(std::nextafter(tie, 0.0));
    expect_format_like_to_chars(std::nextafter(tie, 1e300));
    // Random bit patterns (every exponent).
    const double bits = std::bit_cast<double>(rng());
    if (std::isfinite(bits)) expect_format_like_to_chars(bits);
  }
}

TEST(MonitorCsvNumbers, EstimateRowsAreToCharsColumnByColumn) {
  // A row's four numbers are made side by side (their digits four at a time in SSE2 registers)
  // where each lies in 1e-4..1e7 and is not near a tie; the text must be std::to_chars(x,
  // general, 7) in every column whatever the mix: values of every magnitude and sign, ties and
  // their neighbours, zeros, values just below powers of ten (rounding up to 10^7), 7-digit
  // integers whose 4-digit groups take every value 0..9999, and σ known or not.
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto to_chars7 = [](double x) {
    char buffer[64];
    return std::string(buffer,
                       std::to_chars(buffer, buffer + 64, x, std::chars_format::general, 7).ptr);
  };
  const auto value = [&](int k) {
    switch (k % 6) {
      case 0:  // every magnitude in and around the fast range
        return u(rng) * std::pow(10.0, static_cast<double>(static_cast<int>(rng() % 16) - 6));
      case 1: {  // a tie of the 7th digit and its neighbours
        const double tie =
            (std::floor(std::fabs(u(rng)) * 9e6) + 1e6 + 0.5) * std::pow(10.0, k % 11 - 8);
        return std::nextafter(tie, rng() % 3 == 0 ? 0.0 : rng() % 2 ? 1e300 : tie);
      }
      case 2:  // just below a power of ten: rounds up to the next
        return std::nextafter(std::pow(10.0, static_cast<double>(k % 12 - 5)), 0.0);
      case 3:  // a 7-digit integer: its 4-digit groups in turn through 0..9999
        return static_cast<double>(1'000'000 + (k / 6) % 10'000 * 100 + (k / 6) % 10'000 % 90) *
               (k % 4 == 0 ? -1.0 : 1.0) * std::pow(10.0, k % 9 - 4);
      case 4:
        return k % 4 == 0 ? -0.0 : 0.0;
      default:
        return std::bit_cast<double>(rng() >> 2 | (rng() % 2 ? 0x8000000000000000 : 0));
    }
  };
  for (int k = 0; k < 240'000; ++k) {
    const ForceEstimate e{value(k), std::fabs(value(k + 1)), value(k + 3), value(k + 5), false,
                          k % 5 != 0};
    std::string row;
    append_estimate_row(row, 0.5, "x", e);
    const std::string expect = "0.5,x," + to_chars7(e.force_n) + "," +
                               (e.sigma_known ? to_chars7(e.force_sigma_n) : "") + "," +
                               to_chars7(e.speed_rad_s) + "," + to_chars7(e.accel_rad_s2);
    ASSERT_EQ(row, expect) << k;
  }
  // Every 4-digit group of a 7-digit number (the constants of the digit lanes), in each column.
  for (int g = 0; g < 10'000; ++g) {
    const double a = 1'000'000.0 + g, b = 9'990'000.0 + g, c = (1000.0 + g % 1000) * 1000.0 + g / 10;
    std::string row;
    append_estimate_row(row, 1.0, "x", ForceEstimate{a, b, c, -a / 1000.0, false});
    ASSERT_EQ(row, "1,x," + to_chars7(a) + "," + to_chars7(b) + "," + to_chars7(c) + "," +
                       to_chars7(-a / 1000.0))
        << g;
  }
}

TEST(MonitorCsvNumbers, RowsWithTheSameTimeWriteTheSameText) {
  // Interleaved axes share their times; the writer copies a repeated time instead of
  // formatting it again: the text must be the time's own every time, also when the bits change
  // only a little (the next double, the other zero).
  const double times[] = {0.001, 0.001, 0.001, std::nextafter(0.001, 1.0),
                          0.001, -0.0,  0.0,   0.0,
                          1e300, 1e300, 0.125, 0.125};
  for (const double t : times) {
    std::string row;
    append_estimate_row(row, t, "x", ForceEstimate{1.0, 2.0, 3.0, 4.0, false});
    char buffer[64];
    const auto r = std::to_chars(buffer, buffer + sizeof buffer, t);
    EXPECT_EQ(row, std::string(buffer, r.ptr) + ",x,1,2,3,4") << t;
  }
}

}  // namespace
}  // namespace cutdyn
