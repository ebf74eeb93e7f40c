#pragma once
// Small file helpers shared by the tests.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace losmimo::test_support {

// The whole file as bytes ("" if it cannot be opened).
inline std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace losmimo::test_support
