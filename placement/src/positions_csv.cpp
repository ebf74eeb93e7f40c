#include "losmimo/placement/common/bounded_read.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/positions_csv.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

namespace losmimo::placement {

namespace {
constexpr double kMaxAbsCoordinate_m = 1e9;

std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

std::string strip(const std::string& s) {
  const std::size_t b = s.find_first_not_of(" \t\r");
  const std::size_t e = s.find_last_not_of(" \t\r");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}
}  // namespace

Eigen::Matrix3Xd parse_positions_csv(std::istream& in, const std::string& origin, int max_rows) {
  static const char* const kFieldNames[3] = {"x", "y", "z"};
  std::vector<Eigen::Vector3d> rows;
  std::string line;
  int line_no = 0;
  bool seen_data = false;
  while (
      common::getline_bounded(in, line, common::kMaxPositionsLineBytes, origin + ":" + std::to_string(line_no + 1))) {
    ++line_no;
    const std::string where = origin + ":" + std::to_string(line_no);
    // A UTF-8 byte-order mark (written by some editors) is not part of the first field.
    if (line_no == 1 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);
    const std::string content = strip(line);
    if (content.empty() || content.front() == '#') continue;
    const std::vector<std::string> fields = split_fields(content);
    if (!seen_data && fields.size() == 3 && strip(fields[0]) == "x" && strip(fields[1]) == "y" &&
        strip(fields[2]) == "z") {
      seen_data = true;  // the header
      continue;
    }
    seen_data = true;
    if (fields.size() != 3) {
      throw common::InputError(where + ": expected 3 fields x,y,z, got " + std::to_string(fields.size()));
    }
    if (static_cast<int>(rows.size()) >= max_rows) {
      throw common::InputError(where + ": more than " + std::to_string(max_rows) + " positions");
    }
    Eigen::Vector3d q;
    for (int i = 0; i < 3; ++i) {
      const std::string field_where = where + ": field " + kFieldNames[i];
      q(i) = common::parse_double(fields[i], field_where, kFieldNames[i]);
      // Beyond this, distances overflow (|q| ~ 1e154 m) or phases lose all precision.
      if (!(std::abs(q(i)) <= kMaxAbsCoordinate_m)) {
        throw common::InputError(field_where + ": " + strip(fields[i]) + " is out of range [-1e9, 1e9] m",
                                 kFieldNames[i]);
      }
    }
    rows.push_back(q);
  }
  if (in.bad()) throw common::InputError(origin + ": read error");
  if (rows.empty()) throw common::InputError(origin + ": no positions");
  Eigen::Matrix3Xd q(3, rows.size());
  for (std::size_t n = 0; n < rows.size(); ++n) q.col(n) = rows[n];
  return q;
}

Eigen::Matrix3Xd read_positions_csv(const std::string& path, int max_rows) {
  std::istringstream in(common::read_file_bounded(path, common::kMaxPositionsBytes, "positions file"));
  return parse_positions_csv(in, path, max_rows);
}

}  // namespace losmimo::placement
