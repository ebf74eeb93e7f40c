#include "losmimo/common/key_table.h"

#include <algorithm>
#include <cmath>

namespace losmimo::common {

bool Range::contains(double value) const {
  const bool above_lo = lo_open ? value > lo : value >= lo;
  const bool below_hi = hi_open ? value < hi : value <= hi;
  return above_lo && below_hi;
}

std::string Range::describe() const {
  const bool has_lo = std::isfinite(lo);
  const bool has_hi = std::isfinite(hi);
  if (has_lo && has_hi) {
    return std::string("in ") + (lo_open ? "(" : "[") + format_double(lo) + ", " + format_double(hi) +
           (hi_open ? ")" : "]");
  }
  if (has_lo) return (lo_open ? "> " : ">= ") + format_double(lo);
  if (has_hi) return (hi_open ? "< " : "<= ") + format_double(hi);
  return "";
}

std::vector<double> Range::outside() const {
  std::vector<double> values;
  if (std::isfinite(lo)) values.push_back(lo_open ? lo : lo - std::max(1.0, std::abs(lo)));
  if (std::isfinite(hi)) values.push_back(hi_open ? hi : hi + std::max(1.0, std::abs(hi)));
  return values;
}

void require_in(const Range& range, double value, const std::string& text, const std::string& where) {
  if (!range.contains(value)) throw InputError(where + ": " + text + ": must be " + range.describe());
}

bool field_covers(const std::string& field, const std::string& failed_field) {
  if (failed_field.compare(0, field.size(), field) != 0) return false;
  if (failed_field.size() == field.size()) return true;
  const char next = failed_field[field.size()];
  return next == '.' || next == '[';
}

void require_valid_table(const std::vector<std::pair<std::string, std::string>>& section_keys) {
  std::set<std::pair<std::string, std::string>> seen;
  std::set<std::string> closed_sections;
  for (std::size_t i = 0; i < section_keys.size(); ++i) {
    const auto& [section, key] = section_keys[i];
    if (!seen.insert(section_keys[i]).second) throw std::logic_error("key table: [" + section + "] " + key + " twice");
    if (i > 0 && section_keys[i - 1].first != section) {
      closed_sections.insert(section_keys[i - 1].first);
      if (closed_sections.count(section)) {
        throw std::logic_error("key table: the keys of [" + section + "] are not consecutive");
      }
    }
  }
}

}  // namespace losmimo::common
