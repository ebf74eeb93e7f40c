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

}  // namespace losmimo::common
