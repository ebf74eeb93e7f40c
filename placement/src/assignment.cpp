#include "losmimo/placement/assignment.h"

#include <limits>
#include <stdexcept>

namespace losmimo::placement {

std::vector<int> min_cost_assignment(const Eigen::MatrixXd& cost) {
  const int n = static_cast<int>(cost.rows());
  const int m = static_cast<int>(cost.cols());
  if (n > m) throw std::invalid_argument("assignment: more rows than columns");
  if (!cost.allFinite()) throw std::invalid_argument("assignment: non-finite cost");
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // 1-based shortest augmenting paths with row potentials u and column potentials v;
  // match_col[j] is the row matched to column j (0 = none).
  std::vector<double> u(n + 1, 0.0), v(m + 1, 0.0);
  std::vector<int> match_col(m + 1, 0), way(m + 1, 0);
  for (int i = 1; i <= n; ++i) {
    match_col[0] = i;
    int j0 = 0;
    std::vector<double> min_slack(m + 1, kInf);
    std::vector<bool> used(m + 1, false);
    do {
      used[j0] = true;
      const int i0 = match_col[j0];
      double delta = kInf;
      int j1 = 0;
      for (int j = 1; j <= m; ++j) {
        if (used[j]) continue;
        const double reduced = cost(i0 - 1, j - 1) - u[i0] - v[j];
        if (reduced < min_slack[j]) {
          min_slack[j] = reduced;
          way[j] = j0;
        }
        if (min_slack[j] < delta) {
          delta = min_slack[j];
          j1 = j;
        }
      }
      for (int j = 0; j <= m; ++j) {
        if (used[j]) {
          u[match_col[j]] += delta;
          v[j] -= delta;
        } else {
          min_slack[j] -= delta;
        }
      }
      j0 = j1;
    } while (match_col[j0] != 0);
    do {
      const int j1 = way[j0];
      match_col[j0] = match_col[j1];
      j0 = j1;
    } while (j0 != 0);
  }
  std::vector<int> row_to_col(n, -1);
  for (int j = 1; j <= m; ++j) {
    if (match_col[j] != 0) row_to_col[match_col[j] - 1] = j - 1;
  }
  return row_to_col;
}

}  // namespace losmimo::placement
