#pragma once
// Minimum-cost assignment (Hungarian method with potentials, O(n^2 m)).
// cost is n x m with n <= m; returns for each row the column assigned to it, all distinct,
// minimising the total cost. Throws std::invalid_argument if n > m or a cost is not finite.
// (Written here: Debian 12 has no Eigen-only assignment library; dlib's needs integer costs.)

#include <Eigen/Core>
#include <vector>

namespace losmimo::placement {

std::vector<int> min_cost_assignment(const Eigen::MatrixXd& cost);

}  // namespace losmimo::placement
