#pragma once
// UAV positions as CSV: one UAV per row, `x,y,z` in metres in the BS frame (scenario.h).
// An optional header row `x,y,z`, blank lines, `#` comment lines and a leading UTF-8 byte-order
// mark are allowed. Anything else (a missing file, a file above common::kMaxPositionsBytes or a
// line above kMaxPositionsLineBytes, a wrong field count, a non-finite number or one beyond
// +-1e9 m, more than max_rows rows, no rows)
// throws common::InputError naming the file, line and field.
//
// A table of many swarms, as losmimo-experiment's positions.csv (`sweep,value,algorithm,trial,
// uav,stage,x,y,z`): a header naming x, y, z among other columns. `selection` (column, value
// pairs; a value matches as text or as the same number) picks the rows of one swarm, in file
// order; every column but x, y, z and uav must be fixed by it or hold one value in the selected
// rows, else InputError lists the values to choose from. A selection on a plain x,y,z file, or of
// a column the header lacks, is refused naming the columns.

#include <Eigen/Core>
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

#include "losmimo/placement/common/input_error.h"

namespace losmimo::placement {

using PositionsSelection = std::vector<std::pair<std::string, std::string>>;
Eigen::Matrix3Xd read_positions_csv(const std::string& path, int max_rows = 65536,
                                    const PositionsSelection& selection = {});
Eigen::Matrix3Xd parse_positions_csv(std::istream& in, const std::string& origin, int max_rows = 65536,
                                     const PositionsSelection& selection = {});

}  // namespace losmimo::placement
