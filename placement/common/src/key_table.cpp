#include "losmimo/placement/common/key_table.h"

#include <algorithm>
#include <cmath>

namespace losmimo::common {

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
