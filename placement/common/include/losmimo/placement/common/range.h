#pragma once
// The values a setting accepts, declared once beside the struct it belongs to (e.g.
// placement::gd_range::step) and used by both the struct's validate() and its INI key table, so
// that the check, the error and the key reference cannot drift apart.

#include <limits>
#include <string>
#include <vector>

namespace losmimo::common {

// lo .. hi, either end open; an infinite end is no bound. Only finite values are ever contained.
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;
  bool hi_open = false;

  static constexpr Range any() { return {}; }
  static constexpr Range at_least(double lo) { return {lo, std::numeric_limits<double>::infinity(), false, false}; }
  static constexpr Range above(double lo) { return {lo, std::numeric_limits<double>::infinity(), true, false}; }
  static constexpr Range closed(double lo, double hi) { return {lo, hi, false, false}; }
  static constexpr Range above_up_to(double lo, double hi) { return {lo, hi, true, false}; }  // (lo, hi]

  bool contains(double value) const;
  // "in [0, 1000]", ">= 0", "> 0", "in (0, 86400]"; "" for any value.
  std::string describe() const;
  // Values just outside, for tests: lo itself when open, else below it; likewise above hi.
  std::vector<double> outside() const;
};

// Throws FieldError(field, "<owner>.<field> = <value>: must be <range>") unless range contains
// value; owner names the struct as a user knows it ("gd", "closed_loop").
void require_field_in(const Range& range, double value, const std::string& owner, const std::string& field);

}  // namespace losmimo::common
