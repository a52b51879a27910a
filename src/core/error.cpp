#include "cutdyn/core/error.hpp"

#include <charconv>
#include <cmath>
#include <utility>

namespace cutdyn {
namespace {

std::string join_problems(const std::vector<std::string>& problems, const std::string& where) {
  std::string text = where.empty() ? std::string{} : where + ": ";
  for (std::size_t i = 0; i < problems.size(); ++i) {
    if (i > 0) text += "; ";
    text += problems[i];
  }
  return text;
}

}  // namespace

InvalidInput::InvalidInput(std::vector<std::string> problems, std::string where)
    : std::runtime_error(join_problems(problems, where)),
      problems_(std::move(problems)),
      where_(std::move(where)) {}

std::string format_value(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[64];
  auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  return ec == std::errc{} ? std::string(buffer, end) : std::to_string(value);
}

void Validator::require(bool ok, std::string_view field, double value, std::string_view unit,
                        std::string_view rule) {
  if (ok && std::isfinite(value)) return;
  std::string problem = prefix_.empty() ? std::string(field) : prefix_ + "." + std::string(field);
  problem += " = ";  // appended piecewise: GCC 12 warns (-Wrestrict) on " = " + string
  problem += format_value(value);
  if (!unit.empty()) {
    problem += ' ';
    problem += unit;
  }
  problem += ": ";
  problem += std::isfinite(value) ? std::string(rule) : "must be a finite number";
  problems_.push_back(std::move(problem));
}

void Validator::require_in_open(std::string_view field, double value, std::string_view unit,
                                double lo, double hi) {
  require(value > lo && value < hi, field, value, unit,
          "must be greater than " + format_value(lo) + " and less than " + format_value(hi));
}

void Validator::require_positive(std::string_view field, double value, std::string_view unit) {
  require(value > 0.0, field, value, unit, "must be positive");
}

void Validator::add(std::string problem) { problems_.push_back(std::move(problem)); }

void Validator::merge(const std::vector<std::string>& problems) {
  problems_.insert(problems_.end(), problems.begin(), problems.end());
}

void Validator::throw_if_any(std::string where) const {
  if (!problems_.empty()) throw InvalidInput(problems_, std::move(where));
}

}  // namespace cutdyn
