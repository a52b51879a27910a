#include "cutdyn/core/fields.hpp"

#include <cmath>
#include <string>

namespace cutdyn {

bool FieldRange::contains(double v) const {
  return (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi) && !(nonzero && v == 0.0);
}

std::string FieldRange::rule() const {
  if (!rule_text.empty()) return std::string(rule_text);
  if (lo == 0.0 && lo_open && hi == kInf) return "must be positive";
  std::string text = "must be ";
  if (lo > -kInf) text += (lo_open ? "greater than " : "at least ") + format_value(lo);
  if (lo > -kInf && hi < kInf) text += " and ";
  if (hi < kInf) text += (hi_open ? "less than " : "at most ") + format_value(hi);
  return text;
}

std::string number_text(double value) {
  if (std::isfinite(value) && value == std::trunc(value) && std::abs(value) < 1e15)
    return std::to_string(static_cast<long long>(value));
  return format_value(value);
}

namespace {

// A number for the doc: "0.005", "−45" (a real minus sign), "100000", "1e6".
std::string doc_number(double v) {
  std::string text = number_text(v);
  if (v >= 1e6 && text.find_first_not_of('0', 1) == std::string::npos && text[0] == '1')
    text = "1e" + std::to_string(text.size() - 1);
  if (!text.empty() && text[0] == '-') text = "−" + text.substr(1);
  return text;
}

}  // namespace

std::string FieldRange::doc(bool integer) const {
  if (integer) return doc_number(lo) + " … " + doc_number(hi);
  if (nonzero && lo == -kInf && hi == kInf) return "≠ 0";
  const bool has_lo = lo > -kInf, has_hi = hi < kInf;
  if (has_lo && has_hi) {
    if (!lo_open && !hi_open) return doc_number(lo) + " … " + doc_number(hi);
    return doc_number(lo) + (lo_open ? " < . " : " ≤ . ") + (hi_open ? "< " : "≤ ") +
           doc_number(hi);
  }
  if (has_lo) return (lo_open ? "> " : "≥ ") + doc_number(lo);
  if (has_hi) return (hi_open ? "< " : "≤ ") + doc_number(hi);
  return {};
}

}  // namespace cutdyn
