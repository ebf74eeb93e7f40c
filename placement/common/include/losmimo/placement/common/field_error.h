#pragma once
// The error a settings validator throws: what() says what is wrong in the validator's words
// ("gd.step = 0: must be a finite positive number"), field() names the field that failed, so that
// a loader can name the INI key that set it (key_table.h) without reading the message.

#include <stdexcept>
#include <string>
#include <utility>

namespace losmimo::common {

class FieldError : public std::invalid_argument {
 public:
  // `field`: the field as the validated struct names it, e.g. "step", "cube_center_x_m",
  // "faults[0].uav", or a path into a nested struct, "filter.noise.sigma_range_m".
  FieldError(std::string field, const std::string& message)
      : std::invalid_argument(message), field_(std::move(field)) {}
  const std::string& field() const { return field_; }

 private:
  std::string field_;
};

// Runs fn (e.g. a nested struct's validate()); a FieldError from it is re-thrown with
// `member` + "." in front of its field, so that the field is a path in the enclosing struct.
template <typename Fn>
void with_field_prefix(const std::string& member, Fn&& fn) {
  try {
    fn();
  } catch (const FieldError& e) {
    throw FieldError(member + "." + e.field(), e.what());
  }
}

}  // namespace losmimo::common
