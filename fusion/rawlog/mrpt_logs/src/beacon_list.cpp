#include "losmimo/fusion/rawlog/mrpt_logs/beacon_list.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "losmimo/placement/common/input_error.h"

namespace losmimo::mrpt_logs {

localization::BeaconMap parse_beacon_list(const std::string& text, const std::string& where) {
  localization::BeaconMap map;
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  static const char* kNames[] = {"ID", "x", "y", "z"};
  while (std::getline(in, line)) {
    ++line_no;
    std::istringstream fields(line);
    std::vector<std::string> cols;
    std::string f;
    while (cols.size() < 4 && fields >> f) cols.push_back(f);
    if (cols.empty() || cols[0][0] == '#' || cols[0][0] == '%' || cols[0].rfind("//", 0) == 0) continue;
    const std::string at = where + ":" + std::to_string(line_no);
    if (cols.size() < 4) {
      throw common::InputError(at + ": expected 'ID x y z', got " + std::to_string(cols.size()) + " column(s)");
    }
    const long long id = common::parse_integer(cols[0], at, 0, 2147483647LL, kNames[0]);
    Eigen::Vector3d p;
    for (int k = 0; k < 3; ++k) {
      p(k) = common::parse_double(cols[k + 1], at, kNames[k + 1]);
      if (!std::isfinite(p(k)))
        throw common::InputError(at + ": " + kNames[k + 1] + " '" + cols[k + 1] + "' is not finite");
    }
    if (map.find(static_cast<std::int32_t>(id))) {
      throw common::InputError(at + ": ID " + cols[0] + " listed twice");
    }
    map.add(static_cast<std::int32_t>(id), p);
  }
  if (map.empty()) throw common::InputError(where + ": no beacon (expected lines 'ID x y z')");
  return map;
}

localization::BeaconMap read_beacon_list(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error(path + ": cannot open beacon list");
  std::ostringstream s;
  s << f.rdbuf();
  return parse_beacon_list(s.str(), path);
}

}  // namespace losmimo::mrpt_logs
