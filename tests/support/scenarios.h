#pragma once
// Scenarios the placement tests and benchmarks share (namespace losmimo::test_support).

#include "losmimo/placement/scenario.h"

namespace losmimo::test_support {

// The paper's scenario with a side x side BS array and side^2 UAVs (Nt = Nr = side^2).
inline placement::Scenario square_array_scenario(int side) {
  placement::Scenario s;
  s.bs_rows = side;
  s.bs_cols = side;
  s.num_uavs = side * side;
  return s;
}

}  // namespace losmimo::test_support
