#pragma once
// Small file helpers shared by the tests.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
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

// Compares two CSV texts cell by cell: cells that both parse as numbers by |a - b| / max(|b|, 1)
// (relative above 1, absolute below, so that values near 0 printed to 10 digits compare by
// their size), every other cell by its text. Returns the largest difference, or infinity when
// the shapes or a text cell differ.
inline double csv_max_relative_difference(const std::string& a, const std::string& b) {
  constexpr double kDiffer = std::numeric_limits<double>::infinity();
  std::istringstream la(a), lb(b);
  std::string row_a, row_b;
  double worst = 0.0;
  while (true) {
    const bool more_a = static_cast<bool>(std::getline(la, row_a));
    const bool more_b = static_cast<bool>(std::getline(lb, row_b));
    if (more_a != more_b) return kDiffer;
    if (!more_a) return worst;
    std::istringstream ca(row_a), cb(row_b);
    std::string cell_a, cell_b;
    while (true) {
      const bool cell_more_a = static_cast<bool>(std::getline(ca, cell_a, ','));
      const bool cell_more_b = static_cast<bool>(std::getline(cb, cell_b, ','));
      if (cell_more_a != cell_more_b) return kDiffer;
      if (!cell_more_a) break;
      if (cell_a == cell_b) continue;
      char* end_a = nullptr;
      char* end_b = nullptr;
      const double x = std::strtod(cell_a.c_str(), &end_a);
      const double y = std::strtod(cell_b.c_str(), &end_b);
      if (cell_a.empty() || cell_b.empty() || *end_a != '\0' || *end_b != '\0') return kDiffer;
      worst = std::max(worst, std::abs(x - y) / std::max(std::abs(y), 1.0));
    }
  }
}

}  // namespace losmimo::test_support
