#pragma once
// The error every reader of user input throws: it names where (file, line, key or field) and
// the offending value, so an app can print it and exit with code 2.

#include <stdexcept>
#include <string>

namespace losmimo::common {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Parses a whole string as a finite double; throws InputError("<where>: ...") otherwise.
double parse_double(const std::string& text, const std::string& where);
// Parses a whole string as an int in [lo, hi]; throws InputError otherwise.
long long parse_integer(const std::string& text, const std::string& where, long long lo, long long hi);
// Parses true/false/1/0/yes/no/on/off.
bool parse_bool(const std::string& text, const std::string& where);

}  // namespace losmimo::common
