#pragma once
// The error every reader of user input throws: its message names where (file, line, key or field)
// and the offending value, so an app can print it and refuse the input (kExitBadInput,
// apps/exit_codes.h); field() names the setting or field as data ("[scenario] snr_db", "x",
// "--shard"), empty when the error is not about one field (a file that cannot be opened, a
// malformed line).

#include <stdexcept>
#include <string>
#include <utility>

namespace losmimo::common {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message, std::string field = {})
      : std::runtime_error(message), field_(std::move(field)) {}
  const std::string& field() const { return field_; }

 private:
  std::string field_;
};

// Parse a whole string; otherwise throw InputError("<where>: ...", field).
// A finite double.
double parse_double(const std::string& text, const std::string& where, const std::string& field = {});
// An integer in [lo, hi].
long long parse_integer(const std::string& text, const std::string& where, long long lo, long long hi,
                        const std::string& field = {});
// true/false/1/0/yes/no/on/off.
bool parse_bool(const std::string& text, const std::string& where, const std::string& field = {});

}  // namespace losmimo::common
