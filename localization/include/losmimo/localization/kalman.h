#pragma once
// What both EKFs (position/ekf.h, pose/ekf.h) ask of MRPT's CKalmanFilterCapable: the naive EKF
// update (each filter's OnPostIteration then replaces MRPT's (I - K H) P by the Joseph form and
// repairs it, filter_health.h; the pose EKF drives its own iterations), analytic transition and
// observation Jacobians, no profiler.

#include <mrpt/bayes/CKalmanFilterCapable.h>

namespace losmimo::localization {

template <class KalmanOptions>
void configure_ekf(KalmanOptions& options) {
  options.method = mrpt::bayes::kfEKFNaive;
  options.use_analytic_transition_jacobian = true;
  options.use_analytic_observation_jacobian = true;
  options.enable_profiler = false;
}

}  // namespace losmimo::localization
