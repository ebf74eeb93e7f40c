#pragma once
// --refine for the bearing-range replay: a batch Ceres smoother over the 6-D poses of every
// frame, with the same models as the landmark pose filters (localization/pose/landmark_filter.h)
// and the same data association (the readings the filter associated).
//
// Unknowns x_0..x_{n-1} (Pose6, CPose3D parameters). Cost (sum of squared whitened residuals):
//   prior     r = L0^-1 dev(x_0, m_0)                       start belief N(m_0, P_0 + floor)
//   odometry  r = Lk^-1 dev(x_{k-1} (+) u_k, x_k)           Q_k = odometry_noise() at x_{k-1}'s
//                                                           filter estimate, Q_k = Lk Lk^T
//   reading   r = diag(1/sigma) (z - range_az_el(p(x_k)))   landmark_predict(), angles wrapped
// dev() is pose6_deviation (angle differences wrapped). Jacobians: the pose
// composition's (compose_pose6) and landmark_predict's analytic J_z_x (range_az_el_jacobian
// chained through CPose3D::inverseComposePoint); dev(a, b) is taken with da = I, db = -I.
// Planar logs keep z, pitch, roll of every pose constant (ceres::SubsetManifold).
// Seeded by the filter's track; sparse normal Cholesky.

#include <vector>

#include "losmimo/localization/pose/landmark_filter.h"

namespace losmimo::fusion {

struct BearingSmootherFrame {
  localization::OdometryIncrement6 odometry;              // as the filter used it (frame 0: unused)
  std::vector<localization::AssociatedReading> readings;  // the filter's association
  localization::LandmarkBelief filter_belief;             // the seed
};

struct BearingSmootherResult {
  std::vector<localization::Pose6> track;
  int iterations = 0;
  bool converged = false;
  double initial_cost = 0.0, final_cost = 0.0;
  long readings_used = 0;
};

// Throws std::invalid_argument for an empty frame list.
BearingSmootherResult smooth_bearing_track(const localization::LandmarkFilterConfig& config,
                                           const localization::LandmarkBelief& start,
                                           const std::vector<BearingSmootherFrame>& frames, int max_iterations = 50);

}  // namespace losmimo::fusion
