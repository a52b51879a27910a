// Errors and input validation.
//
// Three kinds of failure, handled the same way everywhere: programming errors are assertions;
// invalid input throws cutdyn::InvalidInput listing every problem found; numerical trouble in a
// valid run is reported in a result's status, never thrown.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace cutdyn {

/// Invalid input. `problems()` lists each problem as "field = value [unit]: must be ...".
/// `where()` names the input as a whole (a file, a command) and may be empty.
class InvalidInput : public std::runtime_error {
 public:
  explicit InvalidInput(std::vector<std::string> problems, std::string where = {});
  const std::vector<std::string>& problems() const noexcept { return problems_; }
  const std::string& where() const noexcept { return where_; }

 private:
  std::vector<std::string> problems_;
  std::string where_;
};

/// Collects validation problems; `throw_if_any` throws them together.
class Validator {
 public:
  explicit Validator(std::string prefix = {}) : prefix_(std::move(prefix)) {}

  /// Records "prefix.field = value unit: rule" unless `ok`.
  void require(bool ok, std::string_view field, double value, std::string_view unit,
               std::string_view rule);
  /// Requires lo < value < hi (open bounds) and finiteness.
  void require_in_open(std::string_view field, double value, std::string_view unit, double lo,
                       double hi);
  /// Requires value > 0 and finite.
  void require_positive(std::string_view field, double value, std::string_view unit);
  /// Records a free-form problem.
  void add(std::string problem);
  /// Appends another validator's problems.
  void merge(const std::vector<std::string>& problems);

  bool ok() const noexcept { return problems_.empty(); }
  const std::vector<std::string>& problems() const noexcept { return problems_; }
  void throw_if_any(std::string where = {}) const;

 private:
  std::string prefix_;
  std::vector<std::string> problems_;
};

/// Formats a double for messages: shortest round-trip form, "nan"/"inf" spelled out.
std::string format_value(double value);

/// Runs `work`; an InvalidInput it throws is rethrown naming `where` and with `key` before
/// each problem ("simulate: …", "axis x: …").
template <typename F>
void rethrow_as(const std::string& where, const std::string& key, F&& work) {
  try {
    work();
  } catch (const InvalidInput& e) {
    std::vector<std::string> problems;
    for (const std::string& p : e.problems()) problems.push_back(key + ": " + p);
    throw InvalidInput(problems, where);
  }
}

}  // namespace cutdyn
