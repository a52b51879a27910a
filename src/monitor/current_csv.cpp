#include "cutdyn/monitor/current_csv.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "cutdyn/core/error.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace cutdyn {
namespace {

constexpr int kTime = 0, kAxis = 1, kExtra = 6;

__extension__ typedef unsigned __int128 u128;
constexpr u128 kZeros = (static_cast<u128>(0x3030303030303030) << 64) | 0x3030303030303030;

// The powers of ten that are exact doubles.
constexpr double kPow10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                               1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                               1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

constexpr char kDigitPairs[] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

bool blank(std::string_view s) { return trim(s).empty(); }

bool is_digit(char c) { return static_cast<unsigned char>(c - '0') < 10; }

// A control byte: binary data, not text (a tab is a blank).
bool is_control(unsigned char c) { return (c < 0x20 && c != '\t') || c == 0x7f; }

// The length of the valid UTF-8 sequence at s[0], or 0.
std::size_t utf8_sequence(std::string_view s) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(s[i]); };
  const unsigned char c = byte(0);
  if (c < 0x80) return 1;
  std::size_t n = 0;
  unsigned char low = 0x80, high = 0xbf;  // the range of the second byte
  if (c >= 0xc2 && c <= 0xdf) {
    n = 2;
  } else if (c >= 0xe0 && c <= 0xef) {
    n = 3;
    if (c == 0xe0) low = 0xa0;
    if (c == 0xed) high = 0x9f;  // no surrogates
  } else if (c >= 0xf0 && c <= 0xf4) {
    n = 4;
    if (c == 0xf0) low = 0x90;
    if (c == 0xf4) high = 0x8f;
  } else {
    return 0;
  }
  if (s.size() < n || byte(1) < low || byte(1) > high) return 0;
  for (std::size_t i = 2; i < n; ++i)
    if (byte(i) < 0x80 || byte(i) > 0xbf) return 0;
  return n;
}

bool valid_utf8(std::string_view s) {
  for (std::size_t at = 0; at < s.size();) {
    const std::size_t n = utf8_sequence(s.substr(at));
    if (n == 0) return false;
    at += n;
  }
  return true;
}

// `s` for a message: printable ASCII and valid UTF-8 as they are, any other byte as \xNN (tab,
// CR and LF as \t, \r, \n), so that a message is text, and valid in JSON, whatever the input.
std::string printable(std::string_view s) {
  std::string text;
  for (std::size_t at = 0; at < s.size();) {
    const auto c = static_cast<unsigned char>(s[at]);
    const std::size_t n = c >= 0x80 ? utf8_sequence(s.substr(at)) : 1;
    if (n > 1) {
      text.append(s.substr(at, n));
      at += n;
      continue;
    }
    ++at;
    if (c == '\t') {
      text += "\\t";
    } else if (c == '\r') {
      text += "\\r";
    } else if (c == '\n') {
      text += "\\n";
    } else if (c < 0x20 || c >= 0x7f) {
      constexpr char kHex[] = "0123456789abcdef";
      text += "\\x";
      text += kHex[c >> 4];
      text += kHex[c & 15];
    } else {
      text += static_cast<char>(c);
    }
  }
  return text;
}

// Shortens a field for a message.
std::string quoted(std::string_view s) {
  std::string text = printable(s.substr(0, 40));
  if (s.size() > 40) text += "...";
  return "\"" + text + "\"";
}

std::string bytes_text(std::size_t n) { return std::to_string(n) + " bytes"; }

// ---- numbers in -----------------------------------------------------------------------------

// The value of the eight digits 0..9 of a little-endian word, the first digit in the lowest
// byte (the SWAR step of fast_float, Lemire).
std::uint64_t value_of_eight(std::uint64_t v) {
  constexpr std::uint64_t kMask = 0x000000ff000000ff;
  constexpr std::uint64_t kMul1 = 0x000f424000000064;  // 100 + (1000000 << 32)
  constexpr std::uint64_t kMul2 = 0x0000271000000001;  // 1 + (10000 << 32)
  v = (v * 10) + (v >> 8);
  return (((v & kMask) * kMul1) + (((v >> 16) & kMask) * kMul2)) >> 32;
}

constexpr std::uint64_t kPow10Int[9] = {1,      10,      100,      1000,     10000,
                                        100000, 1000000, 10000000, 100000000};

// The digits 0..9 before the first other byte of x (x = a word of text ^ "00000000"), 0..8.
int leading_digits(std::uint64_t x) {
  // High nibble of each byte set unless it was a digit; a carry out of a non-digit byte can
  // only disturb the bytes after the first non-digit, which do not count.
  const std::uint64_t other = (x | (x + 0x0606060606060606)) & 0xf0f0f0f0f0f0f0f0;
  return other == 0 ? 8 : std::countr_zero(other) >> 3;
}

// The value of the first n (0..8) digits of x.
std::uint64_t value_of_first(std::uint64_t x, int n) {
  const int shift = 64 - 8 * n;  // 0..64, in two steps (a shift by 64 is undefined)
  return value_of_eight((x << (shift / 2)) << (shift - shift / 2));
}

// The digits at p appended to m (which may wrap: the caller counts the digits). Up to 16 of
// them found and valued from two words without a branch on their number (numbers of every
// length in turn cost no mispredicted loop exit); more, or near the end, one by one.
const char* digits(const char* p, const char* end, std::uint64_t& m) {
  if constexpr (std::endian::native == std::endian::little) {
    if (end - p >= 16) {
      std::uint64_t a, b;
      std::memcpy(&a, p, 8);
      std::memcpy(&b, p + 8, 8);
      a ^= 0x3030303030303030;
      b ^= 0x3030303030303030;
      const int na = leading_digits(a);
      const int nb = na == 8 ? leading_digits(b) : 0;  // a conditional move, not a branch
      m = m * kPow10Int[na] + value_of_first(a, na);
      m = m * kPow10Int[nb] + value_of_first(b, nb);
      p += na + nb;
      if (nb < 8) return p;
    }
  }
  for (; p != end && is_digit(*p); ++p) m = m * 10 + static_cast<unsigned>(*p - '0');
  return p;
}

// Clinger's fast path of std::from_chars: [-]digits[.digits][(e|E)[+|-]digits] with at least
// one digit on each side of a point, at most 19 digits (leading zeros included) making at most
// 2^53, and a decimal exponent within ±22: the significand and the power of ten are exact
// doubles, so the one correctly rounded multiplication or division is the correctly rounded
// value. Returns the end of the number, or nullptr for any other form (std::from_chars
// decides those).
const char* fast_number(const char* p, const char* end, double& value) {
  const bool negative = p != end && *p == '-';
  p += negative ? 1 : 0;  // no branch: the sign of a noisy current is anyone's guess
  std::uint64_t m = 0;
  const char* const first = p;
  p = digits(p, end, m);
  std::ptrdiff_t count = p - first;
  if (count == 0) return nullptr;
  int scale = 0;
  if (p != end && *p == '.') {
    const char* const fraction = ++p;
    p = digits(p, end, m);
    if (p == fraction) return nullptr;
    count += p - fraction;
    if (count > 19) return nullptr;
    scale = -static_cast<int>(p - fraction);
  }
  if (count > 19) return nullptr;
  if (p != end && (*p | 0x20) == 'e') {
    ++p;
    const bool down = p != end && *p == '-';
    if (p != end && (*p == '-' || *p == '+')) ++p;
    const char* const exponent = p;
    int e = 0;
    for (; p != end && is_digit(*p); ++p) {
      if (p - exponent == 4) return nullptr;
      e = e * 10 + (*p - '0');
    }
    if (p == exponent) return nullptr;
    scale += down ? -e : e;
  }
  if (m == 0) {
    value = negative ? -0.0 : 0.0;
    return p;
  }
  if (m > (std::uint64_t{1} << 53) || scale < -22 || scale > 22) return nullptr;
  double v = static_cast<double>(m);
  v = scale < 0 ? v / kPow10[-scale] : v * kPow10[scale];
  value = negative ? -v : v;
  return p;
}

// Bit i set where byte i of x (text ^ "00000000") is not a digit: exact up to and including
// the first byte that is neither a digit nor a point after digits (a carry out of a byte can
// only come from one that is neither).
unsigned other_bytes(std::uint64_t x) {
  const std::uint64_t other = (x | (x + 0x0606060606060606)) & 0xf0f0f0f0f0f0f0f0;
  const std::uint64_t high =
      (((other & 0x7f7f7f7f7f7f7f7f) + 0x7f7f7f7f7f7f7f7f) | other) & 0x8080808080808080;
  return static_cast<unsigned>((high * 0x0002040810204081) >> 56);  // the 8 high bits
}

// fast_number for [-]digits[.digits] with at most 8 digits on each side of the point, from
// two words (24 bytes must be readable at p): the point and the end found at once, the digits
// valued without a loop, the sign without a branch; nullptr for any other form (an exponent,
// more digits), which fast_number or std::from_chars take.
[[gnu::always_inline]] inline const char* window_number(const char* p, double& value) {
  const std::uint64_t negative = *p == '-' ? 1 : 0;
  p += negative;
  std::uint64_t a, b;
  std::memcpy(&a, p, 8);
  std::memcpy(&b, p + 8, 8);
  a ^= 0x3030303030303030;
  b ^= 0x3030303030303030;
  const unsigned other = other_bytes(a) | (other_bytes(b) << 8) | (1u << 16);
  const int point = std::countr_zero(other);  // the first non-digit: a point, or the end
  if (point == 0 || point > 8) return nullptr;
  std::uint64_t m = value_of_first(a, point);
  int end = point, fraction = 0;
  if (p[point] == '.') {
    end = std::countr_zero(other & ~((2u << point) - 1));  // 16: not within the window
    fraction = end - point - 1;
    if (fraction == 0 || fraction > 8 || end >= 16) return nullptr;
    std::uint64_t f;
    std::memcpy(&f, p + point + 1, 8);
    m = m * kPow10Int[fraction] + value_of_first(f ^ 0x3030303030303030, fraction);
    if (m > (std::uint64_t{1} << 53)) return nullptr;
  }
  if ((p[end] | 0x20) == 'e') return nullptr;  // an exponent follows
  double v = static_cast<double>(m);
  if (fraction > 0) v /= kPow10[fraction];
  value = std::bit_cast<double>(std::bit_cast<std::uint64_t>(v) | (negative << 63));
  return p + end;
}

// A number as std::from_chars reads it, by the fastest path that takes its form; nullptr
// where none does.
[[gnu::always_inline]] inline const char* plain_number(const char* p, const char* end,
                                                       double& value) {
  if constexpr (std::endian::native == std::endian::little)  // words read as text order
    if (end - p >= 24)
      if (const char* q = window_number(p, value)) return q;
  return fast_number(p, end, value);
}

#if defined(__SSE2__) && defined(__x86_64__)  // 64-bit moves between registers
// The index of the lowest set bit of x, 63 if there is none (x's bit 63 is never a position of
// a line's byte here): a plain bit scan, without the branch std::countr_zero needs for 0.
[[gnu::always_inline]] inline int lowest_bit(std::uint64_t x) {
  return __builtin_ctzll(x | (std::uint64_t{1} << 63));
}

// Where the 64 bytes at p are line ends, commas and points: bit i for byte i.
struct ByteClasses {
  std::uint64_t lf = 0, comma = 0, point = 0;
};

[[gnu::always_inline]] inline ByteClasses byte_classes(const char* p) {
  ByteClasses c;
  const __m128i lf = _mm_set1_epi8('\n'), comma = _mm_set1_epi8(','), point = _mm_set1_epi8('.');
  for (int i = 0; i < 4; ++i) {
    const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p + 16 * i));
    const auto bits = [i](__m128i m) {
      return static_cast<std::uint64_t>(static_cast<std::uint16_t>(_mm_movemask_epi8(m)))
             << (16 * i);
    };
    c.lf |= bits(_mm_cmpeq_epi8(v, lf));
    c.comma |= bits(_mm_cmpeq_epi8(v, comma));
    c.point |= bits(_mm_cmpeq_epi8(v, point));
  }
  return c;
}

// The bytes [0, n) of a word kept, for n = 0..15 (8 and more: all of it).
constexpr std::uint64_t kLowBytes[16] = {
    0,
    0xff,
    0xffff,
    0xffffff,
    0xffffffff,
    0xffffffffff,
    0xffffffffffff,
    0xffffffffffffff,
    ~std::uint64_t{0}, ~std::uint64_t{0}, ~std::uint64_t{0}, ~std::uint64_t{0},
    ~std::uint64_t{0}, ~std::uint64_t{0}, ~std::uint64_t{0}, ~std::uint64_t{0}};

// The digits of a number [-]W.F at p, W the bytes [s, q) and F the `fraction` bytes after q,
// as 16 byte values: W's from byte 0, F's from byte 8, zeros after each (each read as 8 digits
// padded on the right: W·10^(8 − whole) and F·10^(8 − fraction)); a byte that is not a digit
// is a value above 9 there. `whole` and `fraction` in 1..8 give the number; other counts keep
// every read in bounds (the caller refuses them). 8 bytes readable at p + s and at p + q + 1.
[[gnu::always_inline]] inline __m128i number_digits(const char* p, std::int64_t s, std::int64_t q,
                                                    int whole, int fraction) {
  std::uint64_t a, b;
  std::memcpy(&a, p + s, 8);
  std::memcpy(&b, p + q + 1, 8);
  a = (a ^ 0x3030303030303030) & kLowBytes[whole & 15];
  b = (b ^ 0x3030303030303030) & kLowBytes[fraction & 15];
  return _mm_unpacklo_epi64(_mm_cvtsi64_si128(static_cast<long long>(a)),
                            _mm_cvtsi64_si128(static_cast<long long>(b)));
}

// number_digits' 16 digits summed to four groups of four (32-bit lanes: W's first and last
// four, F's first and last four), by multiply-adds of neighbours: pairs, then quads.
[[gnu::always_inline]] inline __m128i digit_quads(__m128i d) {
  const __m128i zero = _mm_setzero_si128(), ten_one = _mm_set1_epi32(0x0001000a);
  const __m128i low = _mm_madd_epi16(_mm_unpacklo_epi8(d, zero), ten_one);
  const __m128i high = _mm_madd_epi16(_mm_unpackhi_epi8(d, zero), ten_one);
  return _mm_madd_epi16(_mm_packs_epi32(low, high), _mm_set1_epi32(0x00010064));  // ×100 + 1
}

// The values of two numbers from their digits (number_digits), the powers 10^whole and their
// sign bits. With W' = W·10^(8 − whole) and F' = F·10^(8 − fraction) the 8-digit integers of
// the two halves, W' · 10^whole = W·10^8 exactly (a product that is an exact double is
// computed exactly), m = W·10^8 + F' is exact below 2^53, and the value W + F/10^fraction is
// m/10^8 in one correctly rounded division of exact doubles: the value std::from_chars reads.
// `big` gets a bit where m is 2^53 or more (not exact).
[[gnu::always_inline]] inline __m128d two_numbers(__m128i dx, __m128i dy, double scale_x,
                                                  double scale_y, std::uint64_t sign_x,
                                                  std::uint64_t sign_y, int& big) {
  const __m128i wf = _mm_madd_epi16(_mm_packs_epi32(digit_quads(dx), digit_quads(dy)),
                                    _mm_set1_epi32(0x00012710));  // ×10000 + 1: W'x F'x W'y F'y
  const __m128i ww_ff = _mm_shuffle_epi32(wf, _MM_SHUFFLE(3, 1, 2, 0));  // W'x W'y F'x F'y
  const __m128d w = _mm_cvtepi32_pd(ww_ff), f = _mm_cvtepi32_pd(_mm_unpackhi_epi64(ww_ff, ww_ff));
  const __m128d m = _mm_add_pd(_mm_mul_pd(w, _mm_set_pd(scale_y, scale_x)), f);
  big |= _mm_movemask_pd(_mm_cmpge_pd(m, _mm_set1_pd(9007199254740992.0)));
  const __m128d v = _mm_div_pd(m, _mm_set1_pd(1e8));
  return _mm_or_pd(v, _mm_castsi128_pd(_mm_set_epi64x(static_cast<long long>(sign_y),
                                                      static_cast<long long>(sign_x))));
}

// A data line of the standard layout, kFields fields (time_s, axis, the currents, the speed
// and, with 7, the rotor angle), at p: its numbers in `value` (the slots of CurrentCsvParser),
// its axis field in `axis`, and the bytes up to the next line; 0 where the line is not one of
// LF- or CR LF-ended plain numbers within 63 bytes (the caller's other paths take it). The
// separators are found first, for all 64 bytes at once; then each number's digits are placed
// in a vector and two numbers are valued side by side (digit_quads, two_numbers), so that no
// number waits for the end of the one before. A number field is [-]d{1,8}.d{1,8} here; the
// form of every field is checked (its point, the lengths, each byte a digit) without a branch,
// and a line that fails goes field by field to the general reader of numbers. 96 bytes
// readable at p.
template <int kFields>
[[gnu::always_inline]] inline int separated_line(const char* p, double (&value)[8],
                                                 std::string_view& axis) {
  const ByteClasses c = byte_classes(p);
  const int length = lowest_bit(c.lf);  // the LF's position; 63: none before it
  if (length >= 63) return 0;
  std::uint64_t commas = c.comma & ((std::uint64_t{1} << length) - 1);
  int last[kFields];  // field f ends at last[f] (a comma, the CR or the LF)
#pragma GCC unroll 8
  for (int f = 0; f + 1 < kFields; ++f) {
    last[f] = lowest_bit(commas);  // 63 when they run out: refused below
    commas &= commas - 1;
  }
  if (commas != 0 || last[kFields - 2] >= length) return 0;  // more fields, or fewer
  const int cr = p[length - 1] == '\r' ? 1 : 0;              // length > 0: commas precede it
  last[kFields - 1] = length - cr;
  axis = std::string_view(p + last[0] + 1, static_cast<std::size_t>(last[1] - last[0] - 1));
  // The points of the number fields (one in each, if the form is right).
  const std::uint64_t axis_bytes =
      ((std::uint64_t{1} << last[1]) - 1) & ~((std::uint64_t{2} << last[0]) - 1);
  std::uint64_t points = c.point & ((std::uint64_t{1} << last[kFields - 1]) - 1) & ~axis_bytes;
  constexpr int kNumbers = kFields - 1;  // the fields but the axis
  unsigned lengths = 0;  // whole − 1 and fraction − 1 of every number, or-ed: in 0..7 if right
  __m128i not_digit = _mm_setzero_si128();
  int big = 0;
  // Number k's digits, sign bit and 10^whole (k: 0 the time, then the fields after the axis).
  const auto place = [&](int k, __m128i& digits, std::uint64_t& sign, double& scale) {
    const int f = k == 0 ? 0 : k + 1;
    const std::int64_t first = f == 0 ? 0 : last[f - 1] + 1, e = last[f];
    const std::int64_t q = lowest_bit(points);  // this field's point, if the form is right
    points &= points - 1;
    const std::int64_t negative = p[first] == '-' ? 1 : 0;  // no branch on a sign: a coin toss
    const std::int64_t s = first + negative;
    const auto whole = static_cast<int>(q - s), fraction = static_cast<int>(e - q - 1);
    lengths |= static_cast<unsigned>((whole - 1) | (fraction - 1));
    digits = number_digits(p, s, q, whole, fraction);
    not_digit = _mm_or_si128(not_digit, _mm_subs_epu8(digits, _mm_set1_epi8(9)));
    sign = static_cast<std::uint64_t>(negative) << 63;
    scale = kPow10[whole & 15];
  };
  // Numbers k and k + 1 placed and valued side by side, pair after pair (fewer values live at
  // once); slot of number k: 0 (time), then 2.. (7 for the angle). An odd count pairs the last
  // number with itself.
  constexpr int kSlot[] = {0, 2, 3, 4, 5, 7};
#pragma GCC unroll 4
  for (int k = 0; k < kNumbers; k += 2) {
    __m128i dx, dy;
    std::uint64_t sx, sy;
    double cx, cy;
    place(k, dx, sx, cx);
    if (k + 1 < kNumbers) {
      place(k + 1, dy, sy, cy);
    } else {
      dy = dx;
      sy = sx;
      cy = cx;
    }
    const __m128d v = two_numbers(dx, dy, cx, cy, sx, sy, big);
    _mm_storel_pd(&value[kSlot[k]], v);
    if (k + 1 < kNumbers) _mm_storeh_pd(&value[kSlot[k + 1]], v);  // not the odd count's copy
  }
  unsigned bad = lengths & ~7u;  // a length outside 1..8 (a negative one included)
  bad |= points != 0 ? 1u : 0u;  // a second point in the last field (elsewhere: the next's)
  bad |= static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(not_digit, _mm_setzero_si128())) ^
                               0xffff);
  if ((bad | static_cast<unsigned>(big)) != 0) {
    for (int f = 0; f < kFields; ++f) {
      if (f == 1) continue;
      const char* const first = p + (f == 0 ? 0 : last[f - 1] + 1);
      const char* const number = first + (*first == '+' ? 1 : 0);  // as the general path allows
      if (plain_number(number, p + 96, value[f < 6 ? f : 7]) != p + last[f]) return 0;
    }
  }
  return length + 1;
}
#endif

// ---- numbers out ----------------------------------------------------------------------------

// The 8 decimal digits of n < 10^8 as ASCII in a word, the first digit in the lowest byte
// (SWAR: 4 + 4 digits, then 2 + 2, then 1 + 1, by multiplications instead of divisions).
[[gnu::always_inline]] inline std::uint64_t eight_digits_text(std::uint32_t n) {
  std::uint64_t merged = (n / 10000) | (static_cast<std::uint64_t>(n % 10000) << 32);
  const std::uint64_t div100 = ((merged * 10486) >> 20) & 0x0000007f0000007f;
  merged = div100 | ((merged - 100 * div100) << 16);
  const std::uint64_t div10 = ((merged * 103) >> 10) & 0x000f000f000f000f;
  merged = div10 | ((merged - 10 * div10) << 8);
  return merged + 0x3030303030303030;
}

// The digits of a number as text in a 128-bit word, the first (not 0) in the lowest byte and
// '0' past the last; `count` of them without the trailing zeros; its decimal exponent e10
// (d0.d1... × 10^e10). Composed and written in registers: no byte is read back from memory.
struct Digits {
  u128 text = 0;
  int count = 0;
  int e10 = 0;
};

// The number of digits of `text` up to its last one that is not '0' (text holds one).
int significant(u128 text) {
  const u128 x = text ^ kZeros;
  const auto low = static_cast<std::uint64_t>(x), high = static_cast<std::uint64_t>(x >> 64);
  const auto last = [](std::uint64_t w) {  // the index of the last byte of w that is not 0
    const std::uint64_t nonzero =
        (((w & 0x7f7f7f7f7f7f7f7f) + 0x7f7f7f7f7f7f7f7f) | w) & 0x8080808080808080;
    return (63 - std::countl_zero(nonzero)) >> 3;
  };
  return high != 0 ? 9 + last(high) : 1 + last(low);
}

// The bytes [0, n) of t, n <= 16.
u128 first_bytes(u128 t, int n) {
  return n >= 16 ? t : t & ((static_cast<u128>(1) << (8 * n)) - 1);
}

// Writes the 16 bytes of t at p.
void store(char* p, u128 t) { std::memcpy(p, &t, 16); }

// floor(e2·log10 2), for |e2| < 1650.
constexpr int floor_log10_pow2(int e2) { return (e2 * 78913) >> 18; }

// floor(log10(x)) or one less, for a positive normal x.
int decimal_exponent_estimate(double x) {
  return floor_log10_pow2(static_cast<int>((std::bit_cast<std::uint64_t>(x) >> 52) & 0x7ff) -
                          1023);
}

// x·10^k in one correctly rounded operation (false if 10^|k| is not an exact double).
bool scale_by_pow10(double x, int k, double& y) {
  if (k > 22 || k < -22) return false;
  y = k >= 0 ? x * kPow10[k] : x / kPow10[-k];
  return true;
}

// y = |x|·10^(digits − 1 − e10) in [10^(digits−1), 10^digits), e10 the decimal exponent of x;
// false for 0, non-finite and subnormal x or where no exact power of ten does it.
bool scaled_to_digits(double ax, int digits, double& y, int& e10) {
  if (!(ax >= 2.2250738585072014e-308) || !(ax <= 1.7976931348623157e308)) return false;
  const double low = kPow10[digits - 1], high = kPow10[digits];
  e10 = decimal_exponent_estimate(ax);
  if (!scale_by_pow10(ax, digits - 1 - e10, y)) return false;
  if (y >= high) {
    ++e10;
    if (!scale_by_pow10(ax, digits - 1 - e10, y)) return false;
  }
  return y >= low && y < high;
}

// The digits in scientific form, as printf's %e writes them (up to 16 bytes beyond the end
// may be overwritten).
char* put_scientific(char* p, const Digits& g) {
  // d0 '.' d1..., the point dropped with nothing after it.
  store(p, (g.text & 0xff) | (static_cast<u128>('.') << 8) | ((g.text >> 8) << 16));
  p += g.count > 1 ? g.count + 1 : 1;
  *p++ = 'e';
  *p++ = g.e10 < 0 ? '-' : '+';
  const int a = g.e10 < 0 ? -g.e10 : g.e10;
  if (a >= 100) *p++ = static_cast<char>('0' + a / 100);
  std::memcpy(p, kDigitPairs + 2 * (a % 100), 2);
  return p + 2;
}

// The same in fixed form, as printf's %f writes it with no trailing zeros after a point, for
// -4 <= e10 <= 15 (up to 16 bytes beyond the end may be overwritten).
char* put_fixed(char* p, const Digits& g) {
  if (g.e10 < 0) {
    std::memcpy(p, "0.000000", 8);
    store(p + 1 - g.e10, g.text);
    return p + 1 - g.e10 + g.count;
  }
  const int whole = g.e10 + 1;  // the digits before the point, the zeros past count included
  if (g.count <= whole) {
    store(p, g.text);
    return p + whole;
  }
  store(p, first_bytes(g.text, whole) | (static_cast<u128>('.') << (8 * whole)) |
               ((g.text >> (8 * whole)) << (8 * whole + 8)));
  return p + g.count + 1;
}

// std::to_chars(p, ..., x, chars_format::general, 7) (printf's %.7g), or nullptr where this
// path cannot decide it. |x|·10^k is computed in one rounding (relative error 2^-53, under
// 1.2e-9 of a unit of the 7th digit), so rounding it to an integer is the correct rounding of
// x unless it lies within 1e-6 of a half; those, 0, and the far exponents go to to_chars.
char* general7_any(char* p, double x) {
  double y = 0.0;
  Digits g;
  if (!scaled_to_digits(x < 0 ? -x : x, 7, y, g.e10)) return nullptr;
  const auto whole = static_cast<std::uint32_t>(y);  // y >= 1e6 > 0: the floor
  const double fraction = y - whole;                 // exact
  if (fraction > 0.5 - 1e-6 && fraction < 0.5 + 1e-6) return nullptr;
  auto n = whole + (fraction > 0.5 ? 1u : 0u);
  if (n == 10'000'000) {
    n = 1'000'000;
    ++g.e10;
  }
  g.text = (eight_digits_text(n) >> 8) | (kZeros << 56);
  g.count = significant(g.text);
  if (x < 0) *p++ = '-';
  return g.e10 < -4 || g.e10 >= 7 ? put_scientific(p, g) : put_fixed(p, g);
}

// For the binary exponents of [1e-4, 1e7) (2^-14 .. 2^23, from 0): the decimal exponent
// estimate floor(e2·log10 2) (e10 or e10 − 1) and the powers of ten that scale a number of
// either exponent to 7 digits (10^(6 − estimate) and 10^(5 − estimate), exact doubles; the
// second 0.1 for the estimate 6, where it is never taken).
struct SevenScale {
  double estimated = 1.0, above = 1.0;
  int estimate = 0;
};
constexpr int kSevenLowestExponent = 1023 - 14;  // the biased exponent of 2^-14 (< 1e-4)
constexpr auto kSevenScale = [] {
  std::array<SevenScale, 38> t{};
  for (int i = 0; i < 38; ++i) {
    const int estimate = floor_log10_pow2(i - 14);
    t[static_cast<std::size_t>(i)] = {kPow10[6 - estimate],
                                      estimate == 6 ? 0.1 : kPow10[5 - estimate], estimate};
  }
  return t;
}();

// For 1e-4 <= ax < 1e7: its decimal exponent e10 (-4..6) and y = ax·10^(6 − e10) in
// [10^6, 10^7), in one correctly rounded multiplication; false outside that range, and where
// y rounds to 10^7 (then to general7_any, or shortest15).
[[gnu::always_inline]] inline bool seven_digit_scale(double ax, int& e10, double& y) {
  if (!(ax >= 1e-4 && ax < 1e7)) return false;
  // Both candidates at once, each one correctly rounded multiplication by an exact power of
  // ten, their powers looked up by the binary exponent (not the estimate computed, compared
  // with 10^(estimate + 1), then a scaling: a chain twice as long): ax·10^(6 − estimate)
  // reaches 10^7 where ax·10^(5 − estimate) is the one in range, or where it rounded up to
  // 10^7 (and the other is 10^6 rounded, or refused below).
  const SevenScale& s = kSevenScale[(std::bit_cast<std::uint64_t>(ax) >> 52) -
                                    static_cast<std::uint64_t>(kSevenLowestExponent)];
  const double y0 = ax * s.estimated, y1 = ax * s.above;
  const bool up = y0 >= 1e7;
  e10 = s.estimate + (up ? 1 : 0);
  y = up ? y1 : y0;
  return y >= 1e6 && y < 1e7;
}

// The 7 digits of n (10^6 <= n < 10^7) as text in a word, the first in the lowest byte and '0'
// in the last, and how many there are up to the last that is not 0.
struct SevenDigits {
  std::uint64_t text = 0;
  int count = 0;
};

// SevenDigits of a 7-digit number from its 8-digit text (a leading '0').
[[gnu::always_inline]] inline SevenDigits seven_of_eight(std::uint64_t text) {
  SevenDigits d;
  d.text = (text >> 8) | (std::uint64_t{'0'} << 56);
  const std::uint64_t nonzero_digits = d.text ^ 0x3030303030303030;
  const std::uint64_t flags =
      (((nonzero_digits & 0x7f7f7f7f7f7f7f7f) + 0x7f7f7f7f7f7f7f7f) | nonzero_digits) &
      0x8080808080808080;
  d.count = 1 + ((63 - std::countl_zero(flags)) >> 3);
  return d;
}

[[gnu::always_inline]] inline SevenDigits seven_digits(std::uint32_t n) {
  return seven_of_eight(eight_digits_text(n));
}

// The digits d × 10^(e10 − 6) in printf's fixed form, trailing zeros after the point dropped,
// '-' first if `negative` (-4 <= e10 <= 6; up to 16 bytes written).
[[gnu::always_inline]] inline char* put_fixed7(char* p, const SevenDigits& d, int e10,
                                               bool negative) {
  *p = '-';
  p += negative ? 1 : 0;
  if (e10 < 0) {
    std::memcpy(p, "0.000000", 8);
    std::memcpy(p + 1 - e10, &d.text, 8);
    return p + 1 - e10 + d.count;
  }
  const int before = e10 + 1;  // digits before the point
  if (d.count <= before) {
    std::memcpy(p, &d.text, 8);
    return p + before;
  }
  const std::uint64_t low = (std::uint64_t{1} << (8 * before)) - 1;  // before <= 6
  const std::uint64_t word =
      (d.text & low) | (std::uint64_t{'.'} << (8 * before)) | ((d.text & ~low) << 8);
  std::memcpy(p, &word, 8);
  return p + d.count + 1;
}

// |x| scaled to [10^6, 10^7) (seven_digit_scale) where its rounding to an integer is decided
// without a branch on the fraction (a coin toss): the floor of y + 0.5 (exact: y has no bit
// below 2^-29), since y is more than 1e-6 from a half (else refused: one predictable test),
// and below 10^7 (y < 9999999.5; else refused: it rounds up to 10^7).
[[gnu::always_inline]] inline bool seven_scaled(double x, int& e10, double& y) {
  if (!seven_digit_scale(std::fabs(x), e10, y)) return false;
  const auto whole = static_cast<std::uint32_t>(y);
  const double fraction = y - whole;
  if (std::abs(fraction - 0.5) < 1e-6) return false;
  return y < 9999999.5;
}

// general7_any for 1e-4 <= |x| < 1e7, printf's fixed form (the columns of an estimate), in one
// word: 7 digits and a point are 8 bytes. Anything else, to general7_any.
[[gnu::always_inline]] inline char* general7(char* p, double x) {
  int e10 = 0;
  double y = 0.0;
  if (!seven_scaled(x, e10, y)) return general7_any(p, x);  // outside, near a tie, or 10^7
  const auto n = static_cast<std::uint32_t>(y + 0.5);
  return put_fixed7(p, seven_digits(n), e10, std::signbit(x));  // not 0 here
}

#if defined(__SSE2__) && defined(__x86_64__)
// The 4 digits of each 16-bit lane's v < 10000 (its value × 4, as digit_texts prepares it),
// where each v fills four lanes: v/1000, v/100, v/10 and v by two high multiplications (the
// second one a right shift), less ten times the lane before (SSE2; Muła's scheme, the constants
// checked for every v < 10000 in the tests).
[[gnu::always_inline]] inline __m128i four_digit_lanes(__m128i v4) {
  const __m128i div = _mm_set_epi16(-32768, 13108, 5243, 8389, -32768, 13108, 5243, 8389);
  const __m128i shift = _mm_set_epi16(-32768, 1 << 13, 1 << 11, 1 << 7, -32768, 1 << 13, 1 << 11,
                                      1 << 7);
  const __m128i q = _mm_mulhi_epu16(_mm_mulhi_epu16(v4, div), shift);
  return _mm_sub_epi16(q, _mm_slli_epi64(_mm_mullo_epi16(q, _mm_set1_epi16(10)), 16));
}

// The 8 digits of each of the 32-bit lanes n0..n3 < 10^8 of v as text, the first digit in the
// lowest byte: n0 and n1 in the low and high half of `low`, n2 and n3 in `high`. Four numbers
// at once in SSE2 registers: n = 10000·h + l (h by a multiplication with the inverse of 10^4),
// then the four digits of h and of l side by side.
[[gnu::always_inline]] inline void digit_texts(__m128i v, __m128i& low, __m128i& high) {
  const __m128i inverse = _mm_set1_epi32(static_cast<int>(0xd1b71759));  // n/10^4 = n·it >> 45
  const __m128i even = _mm_srli_epi64(_mm_mul_epu32(v, inverse), 45);
  const __m128i odd = _mm_srli_epi64(_mm_mul_epu32(_mm_srli_epi64(v, 32), inverse), 45);
  const __m128i h = _mm_or_si128(even, _mm_slli_epi64(odd, 32));
  const __m128i l = _mm_sub_epi32(v, _mm_madd_epi16(h, _mm_set1_epi32(10000)));
  const __m128i hl4 = _mm_slli_epi16(_mm_or_si128(h, _mm_slli_epi32(l, 16)), 2);  // h0 l0 h1 ...
  const __m128i a = _mm_unpacklo_epi16(hl4, hl4), b = _mm_unpackhi_epi16(hl4, hl4);
  const __m128i zeros = _mm_set1_epi8('0');
  low = _mm_add_epi8(_mm_packus_epi16(four_digit_lanes(_mm_unpacklo_epi32(a, a)),
                                      four_digit_lanes(_mm_unpackhi_epi32(a, a))),
                     zeros);
  high = _mm_add_epi8(_mm_packus_epi16(four_digit_lanes(_mm_unpacklo_epi32(b, b)),
                                       four_digit_lanes(_mm_unpackhi_epi32(b, b))),
                      zeros);
}

#endif

// std::to_chars(p, ..., x) for an x with 1e-4 <= |x| < 1e7 that has a form of at most 7
// significant digits whose fixed form is not longer than its scientific one (times logged to
// the microsecond, say), or nullptr. Its 7-digit rounding reads back as x (one correctly
// rounded division by an exact power of ten), and two decimals of at most 15 digits never read
// as the same double (DBL_DIG): so it is the shortest form, trailing zeros dropped.
[[gnu::always_inline]] inline char* shortest7(char* p, double x) {
  const double ax = std::fabs(x);
  int e10 = 0;
  double y = 0.0;
  if (!seven_digit_scale(ax, e10, y)) return nullptr;
  const auto n = static_cast<std::uint32_t>(y + 0.5);  // any n that reads back as x will do
  if (n >= 10'000'000 || static_cast<double>(n) / kPow10[6 - e10] != ax) return nullptr;
  const SevenDigits d = seven_digits(n);
  const int fixed = e10 < 0 ? 1 - e10 + d.count : d.count <= e10 + 1 ? e10 + 1 : d.count + 1;
  const int scientific = d.count + (d.count > 1 ? 1 : 0) + 4;  // d[.ddd]e±dd
  if (fixed > scientific) return nullptr;                      // 100000 is 1e+05
  return put_fixed7(p, d, e10, std::signbit(x));
}

// std::to_chars(p, ..., x) (the shortest form that reads back as x), for an x that has a form
// of at most 15 significant digits, or nullptr. Two decimals of at most 15 digits never read
// as the same double (DBL_DIG), so such a form, once it reads back as x, is the shortest and
// the only one of its length. It is the integer nearest to |x|·10^(14 − e10) (within 0.2 of
// it), read back in one correctly rounded division or multiplication. Of the fixed and the
// scientific form the shorter is written, the fixed one on a tie (std::to_chars).
char* shortest15(char* p, double x) {
  const double ax = x < 0 ? -x : x;
  double y = 0.0;
  Digits g;
  if (!scaled_to_digits(ax, 15, y, g.e10)) return nullptr;
  auto n = static_cast<std::uint64_t>(y + 0.5);
  if (n == 1'000'000'000'000'000) {
    n = 100'000'000'000'000;
    ++g.e10;
  }
  double back = 0.0;
  if (!scale_by_pow10(static_cast<double>(n), g.e10 - 14, back) || back != ax) return nullptr;
  const std::uint64_t low = eight_digits_text(static_cast<std::uint32_t>(n % 100'000'000));
  g.text = (eight_digits_text(static_cast<std::uint32_t>(n / 100'000'000)) >> 8) |
           (static_cast<u128>(low) << 56) | (kZeros << 120);
  g.count = significant(g.text);
  const int count = g.count, e10 = g.e10;
  const int fixed = e10 >= count - 1 ? e10 + 1 : e10 >= 0 ? count + 1 : count - e10 + 1;
  const int scientific = count + (count > 1 ? 1 : 0) + 2 + (e10 >= 100 || e10 <= -100 ? 3 : 2);
  // The fixed form of an integer of 2^53 or more is its exact value (to_chars writes
  // 852445877104957952, not the digits padded with zeros): left to to_chars.
  if (fixed <= scientific && e10 >= count && ax >= 9007199254740992.0) return nullptr;
  if (fixed <= scientific && e10 > 15) return nullptr;  // past the 16 bytes of Digits
  if (x < 0) *p++ = '-';
  return fixed <= scientific ? put_fixed(p, g) : put_scientific(p, g);
}

// Writes `value` as append_number does, at p: room for 48 characters needed.
[[gnu::always_inline]] inline char* put_number(char* p, double value, int digits) {
  if constexpr (std::endian::native == std::endian::little) {  // words written as text order
    char* end = nullptr;
    if (digits == 0) {
      end = shortest7(p, value);
      if (!end) end = shortest15(p, value);
    } else if (digits == 7) {
      end = general7(p, value);
    }
    if (end) return end;
  }
  const auto r = digits > 0 ? std::to_chars(p, p + 32, value, std::chars_format::general, digits)
                            : std::to_chars(p, p + 32, value);
  return r.ptr;
}

}  // namespace

std::from_chars_result parse_double(const char* first, const char* last, double& value) {
  double v = 0.0;
  if (const char* end = plain_number(first, last, v)) {
    value = v;
    return {end, std::errc{}};
  }
  return std::from_chars(first, last, value);
}

const std::string* CsvComment::find(std::string_view key) const {
  for (const auto& [k, v] : fields)
    if (k == key) return &v;
  return nullptr;
}

void CurrentCsvParser::parse_comment(std::string_view line) {
  // `# key = value, key = value, ...`; a comment without any '=' is free text (ignored).
  std::string_view body = trim(line);
  body.remove_prefix(1);
  body = trim(body);
  if (body.find('=') == std::string_view::npos) return;
  CsvComment c;
  c.line = line_;
  const auto malformed = [&](std::string_view item, const char* why) {
    throw InvalidInput(
        {"line " + std::to_string(line_) + ": comment item " + quoted(trim(item)) + ": " + why +
         " (a comment before the header is `# key = value, key = "
         "value, ...`)"},
        source_);
  };
  for (std::size_t at = 0;;) {
    const std::size_t comma = body.find(',', at);
    const std::string_view item =
        body.substr(at, comma == std::string_view::npos ? body.npos : comma - at);
    const std::size_t eq = item.find('=');
    if (eq == std::string_view::npos) malformed(item, "no '='");
    if (item.find('=', eq + 1) != std::string_view::npos) malformed(item, "more than one '='");
    const std::string_view key = trim(item.substr(0, eq)), value = trim(item.substr(eq + 1));
    if (key.empty()) malformed(item, "empty key");
    if (value.empty()) malformed(item, "empty value");
    if (c.find(key)) malformed(item, "the key appears twice");
    c.fields.emplace_back(std::string(key), std::string(value));
    if (comma == std::string_view::npos) break;
    at = comma + 1;
  }
  if (const std::string* m = c.find("measure"); m && !parse_current_measure(*m))
    throw InvalidInput({"line " + std::to_string(line_) + ": measure = " + quoted(*m) +
                        ": must be rms or space-vector"},
                       source_);
  comments_.push_back(std::move(c));
}

std::optional<std::pair<CurrentMeasure, std::size_t>> CurrentCsvParser::recorded_measure(
    const std::string& axis) const {
  std::optional<std::pair<CurrentMeasure, std::size_t>> general;
  for (const CsvComment& c : comments_) {
    const std::string* m = c.find("measure");
    if (!m) continue;
    const std::string* a = c.find("axis");
    const std::pair<CurrentMeasure, std::size_t> found{*parse_current_measure(*m), c.line};
    if (a && *a == axis) return found;
    if (!a && !general) general = found;
  }
  return general;
}

std::string CsvLineError::text() const { return "line " + std::to_string(line) + ": " + what; }

CurrentCsvParser::CurrentCsvParser(std::string source, std::string extra_column)
    : source_(std::move(source)), extra_column_(std::move(extra_column)) {
  one_byte_axis_.fill(-1);
}

void CurrentCsvParser::parse_header(std::string_view line) {
  std::vector<std::string_view> fields;
  for (std::size_t at = 0;;) {
    const std::size_t comma = line.find(',', at);
    fields.push_back(
        trim(line.substr(at, comma == std::string_view::npos ? line.npos : comma - at)));
    if (comma == std::string_view::npos) break;
    at = comma + 1;
  }
  std::vector<std::string> names(std::begin(kCurrentColumns), std::end(kCurrentColumns));
  if (!extra_column_.empty()) names.push_back(extra_column_);
  Validator v;
  slot_of_field_.assign(fields.size(), -1);
  for (std::size_t f = 0; f < fields.size(); ++f) {
    header_names_.emplace_back(fields[f]);
    for (std::size_t s = 0; s < names.size(); ++s) {
      if (fields[f] != names[s]) continue;
      if (index_[s] >= 0) {
        v.add("line " + std::to_string(line_) + ": column " + names[s] + " appears twice");
        continue;
      }
      index_[s] = static_cast<int>(f);
      slot_of_field_[f] = static_cast<int>(s);
    }
  }
  for (std::size_t f = 0; f < fields.size(); ++f) {
    if (fields[f] != kRotorAngleColumn) continue;
    if (index_[kAngleSlot] >= 0) {
      v.add("line " + std::to_string(line_) + ": column " + kRotorAngleColumn + " appears twice");
      continue;
    }
    index_[kAngleSlot] = static_cast<int>(f);
    slot_of_field_[f] = kAngleSlot;
  }
  std::string missing;
  for (std::size_t s = 0; s < names.size(); ++s)
    if (index_[s] < 0) missing += (missing.empty() ? "" : ", ") + names[s];
  if (!missing.empty()) {
    std::string header = printable(trim(line).substr(0, 200));
    v.add("line " + std::to_string(line_) + ": missing column" +
          (missing.find(',') != std::string::npos ? "s " : " ") + missing + " (the header is \"" +
          header + "\"; required: time_s,axis,iu_a,iv_a,iw_a,speed_rad_s" +
          (extra_column_.empty() ? "" : "," + extra_column_) + ")");
  }
  v.throw_if_any(source_);
  header_fields_ = static_cast<int>(fields.size());
  for (std::size_t s = 0; s < names.size(); ++s)
    needed_fields_ = std::max(needed_fields_, index_[s] + 1);
  needed_fields_ = std::max(needed_fields_, index_[kAngleSlot] + 1);
  // The column order that cutdyn drive --currents and most loggers write: read straight on.
  standard_layout_ = needed_fields_ >= 6;
  for (int f = 0; f < needed_fields_; ++f)
    standard_layout_ =
        standard_layout_ && slot_of_field_[static_cast<std::size_t>(f)] == (f < 6 ? f : kAngleSlot);
  standard_layout_ = standard_layout_ && needed_fields_ <= 7 && index_[kExtra] < 0;
  header_done_ = true;
}

int CurrentCsvParser::axis_index(std::string_view name) {
  for (std::size_t i = 0; i < axes_.size(); ++i)
    if (axes_[i] == name) return static_cast<int>(i);
  if (name.size() == 1)
    one_byte_axis_[static_cast<unsigned char>(name[0])] = static_cast<int>(axes_.size());
  axes_.emplace_back(name);
  last_time_.push_back(0.0);
  last_line_.push_back(0);
  return static_cast<int>(axes_.size() - 1);
}

bool CurrentCsvParser::parse_line(std::string_view line, std::vector<CurrentRow>& rows,
                                  std::vector<CsvLineError>& errors) {
  if (blank(line)) return true;
  if (!header_done_) {
    if (trim(line).front() == '#')
      parse_comment(line);
    else
      parse_header(line);
    return true;
  }
  ++data_lines_;
  std::string_view field[8];
  int f = 0;
  const char* p = line.data();
  const char* end = p + line.size();
  bool more = true;  // fields after the last one read
  while (f < needed_fields_) {
    const char* comma =
        static_cast<const char*>(std::memchr(p, ',', static_cast<std::size_t>(end - p)));
    const char* stop = comma ? comma : end;
    const int slot = slot_of_field_[static_cast<std::size_t>(f)];
    if (slot >= 0) field[slot] = std::string_view(p, static_cast<std::size_t>(stop - p));
    ++f;
    if (!comma) {
      more = false;
      break;
    }
    p = comma + 1;
  }
  const auto bad = [&](std::string what) {
    errors.push_back({line_, std::move(what)});
    return false;
  };
  // A line with more fields than the header is not a line of this log (two lines run
  // together, a shifted column): refused, so that its time cannot stand for the axis'.
  if (more && f == needed_fields_) {
    const int total = f + 1 + static_cast<int>(std::count(p, end, ','));
    if (total > header_fields_)
      return bad("the line has " + std::to_string(total) + " fields, the header " +
                 std::to_string(header_fields_));
  }
  if (f < needed_fields_) {
    // Name the first required column the line does not reach.
    std::string missing;
    for (int s = 0; s < 8; ++s)
      if (index_[s] >= f)
        missing +=
            (missing.empty() ? "" : ", ") + header_names_[static_cast<std::size_t>(index_[s])];
    return bad("missing column " + missing + " (the line has " + std::to_string(f) +
               " fields, the header " + std::to_string(header_fields_) + ")");
  }
  CurrentRow row;
  row.line = line_;
  double* target[8] = {&row.time_s, nullptr,          &row.iu_a,  &row.iv_a,
                       &row.iw_a,   &row.speed_rad_s, &row.extra, &row.rotor_angle_rad};
  for (int s = 0; s < 8; ++s) {
    if (s == kAxis || index_[s] < 0) continue;
    std::string_view text = field[s];
    // Blanks around a number are allowed; nothing else.
    while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
    while (!text.empty() && (text.back() == ' ' || text.back() == '\t' || text.back() == '\r'))
      text.remove_suffix(1);
    const std::string& name = header_names_[static_cast<std::size_t>(index_[s])];
    if (text.empty()) return bad(name + " is empty");
    std::string_view digits = text;
    if (digits.front() == '+') digits.remove_prefix(1);
    double value = 0.0;
    const auto [ptr, ec] = parse_double(digits.data(), digits.data() + digits.size(), value);
    if (ec != std::errc{} || ptr != digits.data() + digits.size()) {
      if (ec == std::errc::result_out_of_range)
        return bad(name + " = " + quoted(text) + ": out of the range of a double");
      return bad(name + " = " + quoted(text) + ": not a number");
    }
    if (!std::isfinite(value))
      return bad(name + " = " + quoted(text) + ": must be a finite number");
    *target[s] = value;
  }
  const std::string_view axis = trim(field[kAxis]);
  if (axis.empty()) return bad("axis is empty");
  if (axis.find('"') != std::string_view::npos)
    return bad("axis = " + quoted(axis) + ": quotes are not allowed");
  if (!valid_utf8(axis)) return bad("axis = " + quoted(axis) + ": not UTF-8 text");
  row.axis = axis_index(axis);
  const auto a = static_cast<std::size_t>(row.axis);
  if (last_line_[a] != 0 && !(row.time_s > last_time_[a]))
    return bad("time_s = " + format_value(row.time_s) + " s on axis " + std::string(axis) +
               (row.time_s == last_time_[a] ? " repeats" : " goes backwards from") + " line " +
               std::to_string(last_line_[a]) + " (" + format_value(last_time_[a]) +
               " s): time must increase on each axis");
  last_time_[a] = row.time_s;
  last_line_[a] = line_;
  rows.push_back(row);
  ++good_;
  return true;
}

[[gnu::always_inline]] inline bool CurrentCsvParser::keep_row(const double* value,
                                                              std::string_view name,
                                                              std::vector<CurrentRow>& rows) {
  int a = -1;
  if (name.size() == 1) {
    a = one_byte_axis_[static_cast<unsigned char>(name[0])];
  } else {
    const auto it = std::find(axes_.begin(), axes_.end(), name);
    if (it != axes_.end()) a = static_cast<int>(it - axes_.begin());
  }
  if (a < 0) return false;  // a new axis: the general path makes it
  const auto i = static_cast<std::size_t>(a);
  const double t = value[kTime];
  if (last_line_[i] != 0 && !(t > last_time_[i])) return false;
  ++line_;
  last_time_[i] = t;
  last_line_[i] = line_;
  rows.push_back(
      {line_, a, t, value[2], value[3], value[4], value[5], value[kExtra], value[kAngleSlot]});
  ++data_lines_;
  ++good_;
  return true;
}

const char* CurrentCsvParser::separated_lines(const char* p, const char* const end,
                                              std::vector<CurrentRow>& rows) {
#if defined(__SSE2__) && defined(__x86_64__)
  if constexpr (std::endian::native == std::endian::little) {
    static_assert(kTime == 0 && kAxis == 1 && kAngleSlot == 7);  // separated_line's slots
    const auto lines = [&]<int kFields>() {
      while (end - p >= 96) {
        double value[8] = {};
        std::string_view axis;
        const int next = separated_line<kFields>(p, value, axis);
        if (next == 0 || !keep_row(value, axis, rows)) break;
        p += next;
      }
    };
    if (needed_fields_ == 6)
      lines.template operator()<6>();
    else if (needed_fields_ == 7)
      lines.template operator()<7>();
  }
#endif
  return p;
}

const char* CurrentCsvParser::fast_line(const char* p, const char* const end,
                                        std::vector<CurrentRow>& rows) {
  const char* const begin = p;
  double value[8] = {};
  const char* axis = p;
  std::size_t axis_size = 0;
  const auto read_axis = [&] {
    axis = p;
    for (; p != end; ++p) {
      const auto c = static_cast<unsigned char>(*p);
      if (c <= ' ' || c >= 0x7f || c == ',' || c == '"') break;
    }
    axis_size = static_cast<std::size_t>(p - axis);
    return axis_size > 0;
  };
  const auto read_number = [&](int slot) {
    if (p != end && *p == '+') ++p;  // as the general path allows
    p = plain_number(p, end, value[slot]);
    return p != nullptr;
  };
  const auto comma = [&] {
    if (p == end || *p != ',') return false;
    ++p;
    return true;
  };
  if (standard_layout_) {
    // time_s,axis,iu_a,iv_a,iw_a,speed_rad_s[,rotor_angle_rad]: straight on, no branch on
    // which column comes next.
    if (!read_number(kTime) || !comma() || !read_axis() || !comma() || !read_number(2) ||
        !comma() || !read_number(3) || !comma() || !read_number(4) || !comma() || !read_number(5))
      return nullptr;
    if (needed_fields_ == 7 && (!comma() || !read_number(kAngleSlot))) return nullptr;
  } else {
    for (int f = 0;; ++f) {
      const int slot = slot_of_field_[static_cast<std::size_t>(f)];
      if (slot == kAxis) {
        if (!read_axis()) return nullptr;
      } else if (slot >= 0) {
        if (!read_number(slot)) return nullptr;
      } else {
        for (; p != end && *p != ',' && *p != '\n' && *p != '\r'; ++p)
          if (is_control(static_cast<unsigned char>(*p))) return nullptr;
      }
      if (f + 1 == needed_fields_) break;
      if (!comma()) return nullptr;
    }
  }
  const std::string_view name(axis, axis_size);
  if (p != end && *p == ',') {  // the fields no column needs
    int fields = needed_fields_;
    for (; p != end && *p != '\n' && *p != '\r'; ++p) {
      if (*p == ',') ++fields;
      if (is_control(static_cast<unsigned char>(*p))) return nullptr;
    }
    if (fields > header_fields_) return nullptr;
  }
  // The line end: LF or CR LF (a lone CR, and a line the chunk does not end, to the general
  // path).
  const char* const stop = p;
  if (p != end && *p == '\r') ++p;
  if (p == end || *p != '\n') return nullptr;
  if (static_cast<std::size_t>(stop - begin) > kMaxCurrentLineBytes) return nullptr;
  return keep_row(value, name, rows) ? p + 1 : nullptr;
}

bool CurrentCsvParser::too_long(std::size_t number, std::size_t bytes, bool ended,
                                std::vector<CsvLineError>& errors) {
  const std::string limit = "the limit of " + bytes_text(kMaxCurrentLineBytes) + " (1 MiB)";
  std::string what = ended ? "the line is " + bytes_text(bytes) + " long, longer than " + limit
                           : "the line is longer than " + limit + ": " + bytes_text(bytes) +
                                 " without a line end so far";
  if (!header_done_)
    throw InvalidInput({"line " + std::to_string(number) + ": " + what + " (before the header)"},
                       source_);
  ++data_lines_;
  errors.push_back({number, std::move(what)});
  return false;
}

bool CurrentCsvParser::take_line(std::string_view line, std::vector<CurrentRow>& rows,
                                 std::vector<CsvLineError>& errors) {
  if (line_ == 1 && line.substr(0, 3) == "\xef\xbb\xbf") line.remove_prefix(3);  // UTF-8 BOM
  if (line.size() > kMaxCurrentLineBytes) return too_long(line_, line.size(), true, errors);
  for (std::size_t i = 0; i < line.size(); ++i) {
    const auto c = static_cast<unsigned char>(line[i]);
    if (!is_control(c)) continue;
    constexpr char kHex[] = "0123456789abcdef";
    std::string what = c == 0 ? std::string("a NUL byte")
                              : std::string("a control byte 0x") + kHex[c >> 4] + kHex[c & 15];
    what += " at byte " + std::to_string(i + 1) + " of the line: binary data, not text";
    if (!header_done_)
      throw InvalidInput({"line " + std::to_string(line_) + ": " + what + " (before the header)"},
                         source_);
    ++data_lines_;
    errors.push_back({line_, std::move(what)});
    return false;
  }
  return parse_line(line, rows, errors);
}

bool CurrentCsvParser::lines_with_cr(const char* begin, const char* end, bool stop_at_error,
                                     std::vector<CurrentRow>& rows,
                                     std::vector<CsvLineError>& errors) {
  bool ok = true;
  for (;;) {
    const char* cr =
        static_cast<const char*>(std::memchr(begin, '\r', static_cast<std::size_t>(end - begin)));
    const char* stop = cr ? cr : end;
    if (!take_line(std::string_view(begin, static_cast<std::size_t>(stop - begin)), rows, errors)) {
      ok = false;
      if (stop_at_error) return false;
    }
    if (!cr) return ok;
    begin = cr + 1;
    ++line_;
  }
}

bool CurrentCsvParser::hold(const char* begin, const char* end, bool stop_at_error,
                            std::vector<CsvLineError>& errors) {
  const auto n = static_cast<std::size_t>(end - begin);
  held_bytes_ += n;
  if (long_line_) return true;
  if (held_bytes_ <= kMaxCurrentLineBytes) {
    pending_.append(begin, n);
    return true;
  }
  // Too long: from here on only its length is kept.
  long_line_ = true;
  pending_.clear();
  if (!header_done_ || stop_at_error) return too_long(line_ + 1, held_bytes_, false, errors);
  return true;
}

bool CurrentCsvParser::feed(std::string_view chunk, std::vector<CurrentRow>& rows,
                            std::vector<CsvLineError>& errors, bool stop_at_error) {
  const char* p = chunk.data();
  const char* const end = p + chunk.size();
  if (p == end) return true;
  if (after_cr_) {  // the last chunk ended with a CR: an LF here is the rest of its line end
    after_cr_ = false;
    if (*p == '\n') ++p;
  }
  if (held_bytes_ > 0 && p != end) {
    // The end of the unfinished line of the previous chunks: its first LF or CR.
    const char* lf =
        static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
    const char* stop = lf ? lf : end;
    if (const void* cr = std::memchr(p, '\r', static_cast<std::size_t>(stop - p)))
      stop = static_cast<const char*>(cr);
    if (!hold(p, stop, stop_at_error, errors)) return false;
    if (stop == end) return true;
    ++line_;
    const bool ok =
        long_line_ ? too_long(line_, held_bytes_, true, errors) : take_line(pending_, rows, errors);
    pending_.clear();
    held_bytes_ = 0;
    long_line_ = false;
    p = stop + 1;
    if (*stop == '\r') {
      if (p == end)
        after_cr_ = true;
      else if (*p == '\n')
        ++p;
    }
    if (!ok && stop_at_error) return false;
  }
  while (p < end) {
    if (header_done_) {
      if (standard_layout_) {
        p = separated_lines(p, end, rows);
        if (p == end) break;
      }
      if (const char* next = fast_line(p, end, rows)) {
        p = next;
        continue;
      }
    }
    const char* lf =
        static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
    if (!lf) {
      // No LF: the lines ended by lone CRs, then the start of the next line.
      if (const char* cr =
              static_cast<const char*>(memrchr(p, '\r', static_cast<std::size_t>(end - p)))) {
        ++line_;
        if (!lines_with_cr(p, cr, stop_at_error, rows, errors) && stop_at_error) return false;
        p = cr + 1;
        if (p == end) {
          after_cr_ = true;
          return true;
        }
      }
      return hold(p, end, stop_at_error, errors);
    }
    ++line_;
    const char* stop = lf > p && lf[-1] == '\r' ? lf - 1 : lf;
    if (!lines_with_cr(p, stop, stop_at_error, rows, errors) && stop_at_error) return false;
    p = lf + 1;
  }
  return true;
}

bool CurrentCsvParser::finish(std::vector<CurrentRow>& rows, std::vector<CsvLineError>& errors,
                              bool stop_at_error) {
  bool ok = true;
  after_cr_ = false;
  if (held_bytes_ > 0) {
    ++line_;
    ok = (long_line_ ? too_long(line_, held_bytes_, true, errors)
                     : take_line(pending_, rows, errors)) ||
         !stop_at_error;
    pending_.clear();
    held_bytes_ = 0;
    long_line_ = false;
  }
  if (!header_done_)
    throw InvalidInput({"line 1: empty input: expected a header line with the columns "
                        "time_s,axis,iu_a,iv_a,iw_a,speed_rad_s" +
                        (extra_column_.empty() ? std::string() : "," + extra_column_)},
                       source_);
  if (data_lines_ == 0)
    throw InvalidInput(
        {"line " + std::to_string(line_ + 1) +
         ": no data after the header (the input ends at line " + std::to_string(line_) + ")"},
        source_);
  return ok;
}

char* write_number(char* p, double value, int digits) { return put_number(p, value, digits); }

void append_number(std::string& out, double value, int digits) {
  char buffer[kNumberRoom];
  out.append(buffer, put_number(buffer, value, digits));
}

namespace {

// The digits of an estimate's four numbers made side by side (digit_texts), where each is in
// general7's range (an unknown σ is not written: its lane holds 10^6); `fast` false otherwise
// (each number then by put_number).
struct RowDigits {
  int f = 0, s = 0, w = 0, a = 0;  // the decimal exponents of force, σ, speed, acceleration
  bool fast = false;
#if defined(__SSE2__) && defined(__x86_64__)
  __m128i low, high;
#endif
};

[[gnu::always_inline]] inline RowDigits row_digits(const ForceEstimate& e) {
  RowDigits d;
#if defined(__SSE2__) && defined(__x86_64__)
  if constexpr (std::endian::native == std::endian::little) {
    double f = 0.0, s = 1e6, w = 0.0, a = 0.0;  // an unknown σ's lane: 10^6, not written
    d.fast = seven_scaled(e.force_n, d.f, f) &&
             (!e.sigma_known || seven_scaled(e.force_sigma_n, d.s, s)) &&
             seven_scaled(e.speed_rad_s, d.w, w) && seven_scaled(e.accel_rad_s2, d.a, a);
    if (d.fast) {
      // Rounded two at a time, where the digits are made (not each number alone, then moved).
      const __m128d half = _mm_set1_pd(0.5);
      digit_texts(_mm_unpacklo_epi64(_mm_cvttpd_epi32(_mm_add_pd(_mm_set_pd(s, f), half)),
                                     _mm_cvttpd_epi32(_mm_add_pd(_mm_set_pd(a, w), half))),
                  d.low, d.high);
    }
  }
#endif
  return d;
}

[[gnu::always_inline]] inline char* put_row(char* p, double time_s, std::string_view axis,
                                            const ForceEstimate& e, const RowDigits& d) {
  // Room: the time's 32 bytes copied, two commas and the axis, then three numbers of at most
  // 14 characters and their commas before the last, which has kNumberRoom: 32 + 2 + 45 + 48,
  // within kEstimateRowRoom.
  static_assert(32 + 2 + 3 * 15 + kNumberRoom <= kEstimateRowRoom);
  // Axes logged side by side share their times: a time equal to the last one written (to the
  // bit) is copied rather than formatted again.
  thread_local std::uint64_t last_time = ~std::uint64_t{0};
  thread_local int last_size = 0;
  thread_local char last_text[48];
  if (const auto bits = std::bit_cast<std::uint64_t>(time_s); bits == last_time) {
    std::memcpy(p, last_text, 32);  // a shortest form is at most 24 characters
    p += last_size;
  } else {
    char* const start = p;
    p = put_number(p, time_s, 0);
    last_size = static_cast<int>(p - start);
    std::memcpy(last_text, start, 32);
    last_time = bits;
  }
  *p++ = ',';
  if (axis.size() == 1) {  // the usual x, y, z: no call to copy one byte
    *p++ = axis[0];
  } else {
    std::memcpy(p, axis.data(), axis.size());
    p += axis.size();
  }
  *p++ = ',';
#if defined(__SSE2__) && defined(__x86_64__)
  if (d.fast) {
    const auto word = [](__m128i t) { return static_cast<std::uint64_t>(_mm_cvtsi128_si64(t)); };
    p = put_fixed7(p, seven_of_eight(word(d.low)), d.f, std::signbit(e.force_n));
    *p++ = ',';
    if (e.sigma_known) {
      p = put_fixed7(p, seven_of_eight(word(_mm_unpackhi_epi64(d.low, d.low))), d.s,
                     std::signbit(e.force_sigma_n));
    }
    *p++ = ',';
    p = put_fixed7(p, seven_of_eight(word(d.high)), d.w, std::signbit(e.speed_rad_s));
    *p++ = ',';
    return put_fixed7(p, seven_of_eight(word(_mm_unpackhi_epi64(d.high, d.high))), d.a,
                      std::signbit(e.accel_rad_s2));
  }
#endif
  p = put_number(p, e.force_n, 7);
  *p++ = ',';
  if (e.sigma_known) p = put_number(p, e.force_sigma_n, 7);  // else empty: unknown
  *p++ = ',';
  p = put_number(p, e.speed_rad_s, 7);
  *p++ = ',';
  return put_number(p, e.accel_rad_s2, 7);
}

}  // namespace

char* write_estimate_row(char* p, double time_s, std::string_view axis, const ForceEstimate& e) {
  // The numbers' digits first: their chain of dependent operations (scaling, rounding, digits)
  // is the row's longest, and the time and the axis are written while it runs.
  const RowDigits digits = row_digits(e);
  return put_row(p, time_s, axis, e, digits);
}

void append_estimate_row(std::string& out, double time_s, std::string_view axis,
                         const ForceEstimate& e) {
  if (axis.size() <= 64) {  // one append per row
    char buffer[kEstimateRowRoom + 64];
    out.append(buffer, write_estimate_row(buffer, time_s, axis, e));
  } else {
    std::string buffer(kEstimateRowRoom + axis.size(), '\0');
    out.append(buffer.data(), write_estimate_row(buffer.data(), time_s, axis, e));
  }
}

}  // namespace cutdyn
