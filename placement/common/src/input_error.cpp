#include "losmimo/placement/common/input_error.h"

#include "losmimo/placement/common/text.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace losmimo::common {

double parse_double(const std::string& text, const std::string& where, const std::string& field) {
  const std::string t = trim(text);
  char* end = nullptr;
  errno = 0;
  const double v = t.empty() ? 0.0 : std::strtod(t.c_str(), &end);
  if (t.empty() || end != t.c_str() + t.size() || errno == ERANGE || !std::isfinite(v)) {
    throw InputError(where + ": '" + text + "' is not a finite number", field);
  }
  return v;
}

long long parse_integer(const std::string& text, const std::string& where, long long lo, long long hi,
                        const std::string& field) {
  const std::string t = trim(text);
  char* end = nullptr;
  errno = 0;
  const long long v = t.empty() ? 0 : std::strtoll(t.c_str(), &end, 10);
  if (t.empty() || end != t.c_str() + t.size() || errno == ERANGE) {
    throw InputError(where + ": '" + text + "' is not an integer", field);
  }
  if (v < lo || v > hi) {
    throw InputError(where + ": " + t + " is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]",
                     field);
  }
  return v;
}

bool parse_bool(const std::string& text, const std::string& where, const std::string& field) {
  std::string t = trim(text);
  std::transform(t.begin(), t.end(), t.begin(), [](unsigned char c) { return std::tolower(c); });
  if (t == "true" || t == "1" || t == "yes" || t == "on") return true;
  if (t == "false" || t == "0" || t == "no" || t == "off") return false;
  throw InputError(where + ": '" + text + "' is not a boolean (true/false)", field);
}

}  // namespace losmimo::common
