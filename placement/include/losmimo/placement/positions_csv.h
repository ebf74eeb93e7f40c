#pragma once
// UAV positions as CSV: one UAV per row, `x,y,z` in metres in the BS frame (scenario.h).
// An optional header row `x,y,z`, blank lines, `#` comment lines and a leading UTF-8 byte-order
// mark are allowed. Anything else (a missing file, a file above common::kMaxPositionsBytes or a
// line above kMaxPositionsLineBytes, a wrong field count, a non-finite number or one beyond
// +-1e9 m, more than max_rows rows, no rows)
// throws common::InputError naming the file, line and field.

#include <Eigen/Core>
#include <iosfwd>
#include <string>

#include "losmimo/placement/common/input_error.h"

namespace losmimo::placement {

Eigen::Matrix3Xd read_positions_csv(const std::string& path, int max_rows = 65536);
Eigen::Matrix3Xd parse_positions_csv(std::istream& in, const std::string& origin, int max_rows = 65536);

}  // namespace losmimo::placement
