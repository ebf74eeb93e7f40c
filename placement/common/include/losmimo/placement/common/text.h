#pragma once
// Text helpers shared by every reader and writer of user-facing text (INI files, --set values,
// lists, MRPT config files, messages, gnuplot scripts): the one definition of the white space a
// value may be padded with, and of a list written out.

#include <string>
#include <vector>

namespace losmimo::common {

// `text` without leading and trailing white space (std::isspace in the "C" locale: space, \t,
// \n, \v, \f, \r).
std::string trim(const std::string& text);

// The items with `separator` between them ("a, b, c"); "" for none.
std::string join(const std::vector<std::string>& items, const std::string& separator = ", ");
// The same of name(item) for each item: join_with(rows, [](const Row& r) { return r.name; }).
template <typename Range, typename Name>
std::string join_with(const Range& items, Name name, const std::string& separator = ", ") {
  std::string out;
  bool first = true;
  for (const auto& item : items) {
    if (!first) out += separator;
    first = false;
    out += name(item);
  }
  return out;
}

}  // namespace losmimo::common
