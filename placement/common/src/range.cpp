#include "losmimo/placement/common/range.h"

#include <algorithm>
#include <cmath>

#include "losmimo/placement/common/field_error.h"
#include "losmimo/placement/common/format.h"

namespace losmimo::common {

namespace {
// Whole numbers in full (a count reads "100000", not "1e+05"), others as format_double.
std::string number_text(double v) {
  if (std::abs(v) < 1e15 && v == std::floor(v)) return std::to_string(static_cast<long long>(v));
  return format_double(v);
}
}  // namespace

bool Range::contains(double value) const {
  if (!std::isfinite(value)) return false;
  const bool above_lo = lo_open ? value > lo : value >= lo;
  const bool below_hi = hi_open ? value < hi : value <= hi;
  return above_lo && below_hi;
}

std::string Range::describe() const {
  const bool has_lo = std::isfinite(lo);
  const bool has_hi = std::isfinite(hi);
  if (has_lo && has_hi) {
    return std::string("in ") + (lo_open ? "(" : "[") + number_text(lo) + ", " + number_text(hi) +
           (hi_open ? ")" : "]");
  }
  if (has_lo) return (lo_open ? "> " : ">= ") + number_text(lo);
  if (has_hi) return (hi_open ? "< " : "<= ") + number_text(hi);
  return "";
}

std::vector<double> Range::outside() const {
  std::vector<double> values;
  if (std::isfinite(lo)) values.push_back(lo_open ? lo : lo - std::max(1.0, std::abs(lo)));
  if (std::isfinite(hi)) values.push_back(hi_open ? hi : hi + std::max(1.0, std::abs(hi)));
  return values;
}

void require_field_in(const Range& range, double value, const std::string& owner, const std::string& field) {
  if (!range.contains(value)) {
    const std::string rule = range.describe();
    throw FieldError(field, owner + "." + field + " = " + number_text(value) + ": must be " +
                                (rule.empty() ? "a finite number" : rule));
  }
}

}  // namespace losmimo::common
