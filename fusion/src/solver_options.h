#pragma once
// The Ceres solver settings every refinement of this library shares: silent, one thread (the
// experiment parallelises over trials, and one thread keeps the results bit-reproducible), dense
// QR unless the caller picks another linear solver.

#include <ceres/ceres.h>

namespace losmimo::fusion {

inline ceres::Solver::Options quiet_solver_options(int max_iterations) {
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = max_iterations;
  options.logging_type = ceres::SILENT;
  options.minimizer_progress_to_stdout = false;
  options.num_threads = 1;
  return options;
}

}  // namespace losmimo::fusion
