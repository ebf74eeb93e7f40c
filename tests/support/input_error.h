#pragma once
// Expecting bad input to be refused with a message that names it.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "losmimo/placement/common/input_error.h"

namespace losmimo::test_support {

// Runs f, expecting an InputError whose message contains every fragment.
template <typename F>
void expect_input_error(F&& f, const std::vector<std::string>& fragments) {
  try {
    f();
    FAIL() << "no InputError";
  } catch (const common::InputError& e) {
    for (const auto& frag : fragments) EXPECT_NE(std::string(e.what()).find(frag), std::string::npos) << e.what();
  }
}

}  // namespace losmimo::test_support
