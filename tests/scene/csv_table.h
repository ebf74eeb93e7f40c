#pragma once
// A CSV output read by column name (the runs' own outputs, to check a scene against).
#include <cstdlib>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "support/files.h"

namespace losmimo::test_support {

struct CsvTable {
  std::map<std::string, std::size_t> column;
  std::vector<std::vector<std::string>> rows;
  const std::string& text(std::size_t row, const std::string& name) const { return rows.at(row).at(column.at(name)); }
  double number(std::size_t row, const std::string& name) const {
    return std::strtod(text(row, name).c_str(), nullptr);
  }
};

inline CsvTable read_csv_table(const std::string& path) {
  CsvTable t;
  std::istringstream in(read_file(path));
  std::string line;
  bool header = true;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::istringstream cs(line);
    std::string cell;
    while (std::getline(cs, cell, ',')) cells.push_back(cell);
    if (header) {
      for (std::size_t i = 0; i < cells.size(); ++i) t.column[cells[i]] = i;
      header = false;
    } else {
      t.rows.push_back(cells);
    }
  }
  return t;
}

// How many ellipsoids a track of n beliefs shows (docs/scenes.md): beliefs 0, s, 2s, ... with
// s = ceil(n / 10), and the last.
inline std::size_t expected_ellipsoids(std::size_t n) {
  if (n == 0) return 0;
  const std::size_t s = (n + 9) / 10;
  const std::size_t on_stride = (n - 1) / s + 1;
  return on_stride + ((n - 1) % s == 0 ? 0 : 1);
}

}  // namespace losmimo::test_support
