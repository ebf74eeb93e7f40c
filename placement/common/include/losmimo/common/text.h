#pragma once
// Text helpers shared by every reader of user input (INI files, --set values, lists, MRPT
// config files): the one definition of the white space a value may be padded with.

#include <string>

namespace losmimo::common {

// `text` without leading and trailing white space (std::isspace in the "C" locale: space, \t,
// \n, \v, \f, \r).
std::string trim(const std::string& text);

}  // namespace losmimo::common
