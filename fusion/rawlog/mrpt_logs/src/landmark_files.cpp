#include "losmimo/fusion/rawlog/mrpt_logs/landmark_files.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "losmimo/placement/common/input_error.h"

namespace losmimo::mrpt_logs {

namespace {

bool is_comment(const std::string& first) { return first[0] == '#' || first[0] == '%' || first.rfind("//", 0) == 0; }

std::vector<std::string> columns(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> cols;
  std::string c;
  while (in >> c) cols.push_back(c);
  return cols;
}

double finite(const std::string& text, const std::string& at, const std::string& name) {
  const double v = common::parse_double(text, at, name);
  if (!std::isfinite(v)) throw common::InputError(at + ": " + name + " '" + text + "' is not finite", name);
  return v;
}

std::string slurp(const std::string& path, const char* what) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error(path + ": cannot open " + what);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

// Calls row(columns, "where:line") for every line of `text` that is neither blank nor a comment.
template <typename Row>
void for_each_row(const std::string& text, const std::string& where, Row row) {
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::vector<std::string> cols = columns(line);
    if (cols.empty() || is_comment(cols[0])) continue;
    row(cols, where + ":" + std::to_string(line_no));
  }
}

}  // namespace

localization::BeaconMap parse_landmark_file(const std::string& text, const std::string& where) {
  localization::BeaconMap map;
  for_each_row(text, where, [&](const std::vector<std::string>& cols, const std::string& at) {
    if (cols.size() < 4) {
      throw common::InputError(at + ": expected 'x y z ... ID', got " + std::to_string(cols.size()) + " column(s)");
    }
    const Eigen::Vector3d p(finite(cols[0], at, "x"), finite(cols[1], at, "y"), finite(cols[2], at, "z"));
    const auto id = static_cast<std::int32_t>(common::parse_integer(cols.back(), at, 0, 2147483647LL, "ID"));
    if (map.find(id)) throw common::InputError(at + ": ID " + cols.back() + " listed twice", "ID");
    map.add(id, p);
  });
  if (map.empty()) throw common::InputError(where + ": no landmark (expected lines 'x y z ... ID')");
  return map;
}

localization::BeaconMap read_landmark_file(const std::string& path) {
  return parse_landmark_file(slurp(path, "landmark file"), path);
}

std::vector<localization::Pose6> parse_robot_path(const std::string& text, const std::string& where) {
  static const char* kNames[] = {"x", "y", "z", "yaw", "pitch", "roll"};
  std::vector<localization::Pose6> rows;
  for_each_row(text, where, [&](const std::vector<std::string>& cols, const std::string& at) {
    if (cols.size() < 6) {
      throw common::InputError(at + ": expected 'x y z yaw pitch roll', got " + std::to_string(cols.size()) +
                               " column(s)");
    }
    localization::Pose6 p;
    for (int k = 0; k < 6; ++k) p(k) = finite(cols[static_cast<std::size_t>(k)], at, kNames[k]);
    rows.push_back(p);
  });
  if (rows.empty()) throw common::InputError(where + ": no row (expected 'x y z yaw pitch roll')");
  return rows;
}

std::vector<localization::Pose6> read_robot_path(const std::string& path) {
  return parse_robot_path(slurp(path, "robot path file"), path);
}

}  // namespace losmimo::mrpt_logs
