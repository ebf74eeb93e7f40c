#pragma once
// Pose EKF through mrpt::bayes::CKalmanFilterCapable<4, 6, 0, 4> (state x = (x, y, z, yaw), up
// to kRangesPerUpdate ranges per update, no map in the state, action = odometry increment).
// Models: odometry_model.h and range_model.h; rules: pose/filter.h.
//
// Prediction:  x = x (+) u,  P = F P F^T + G Sigma_u G^T,  F = J_x'_x, G = J_x'_u (analytic).
// Update: the readings the gate passes (pose/robustness.h), kRangesPerUpdate at a time (MRPT's
// non-SLAM EKF takes one fixed-size observation per iteration; unused slots have zero H rows and
// zero innovation, so they change nothing; 6 because MRPT evaluates H P H^T with dynamic-size
// products whose cost grows fast with the size: 15 readings take 430 us per epoch as batches of
// 12, 80 us as batches of 6), as an iterated EKF (Gauss-Newton on the prior and the readings of
// a batch): from the predicted (x0, P0), with lin = x0,
//   H = J_h_x(lin),  y = z - h(lin) - H (x0 - lin),  S = H P0 H^T + R,  K = P0 H^T S^-1,
//   x = x0 + K y,  then lin = x, until lin stops moving (kMaxIekfIterations at most).
// Why iterated: a plain EKF update from a prior much wider than a range's noise (a 0.3 m prior,
// 1 mm ranges) linearises the range sphere far from the truth; the curvature error (~ spread^2 /
// 2 range = millimetres) is many sigmas and the filter becomes overconfident and gates forever
// (measured on tests/localization/pose/consistency_test.cpp: NEES ~1e4 at 1 mm, in band with
// the iterations). MRPT's kfIKFFull does not relinearise the observation model when FEAT_SIZE
// is 0, so the iterations are driven from here, each one an MRPT update of (x0, P0) with the
// model linearised at lin and expressed at x0.
// Covariance: OnPostIteration replaces MRPT's (I - K H) P by the Joseph form
// (I - K H) P0 (I - K H)^T + K R K^T with the last iteration's H, then symmetrises and floors it
// (make_spd); yaw is wrapped to (-pi, pi]. The EKF draws no random numbers.

#include <cstddef>
#include <memory>

#include "losmimo/localization/pose/filter.h"

namespace losmimo::localization {

inline constexpr std::size_t kRangesPerUpdate = 6;  // an observation size MRPT's math library instantiates
inline constexpr int kMaxIekfIterations = 10;

class EkfPoseFilter final : public PoseFilter {
 public:
  // `initial` starts the filter through its moments (initial_pose.h).
  EkfPoseFilter(const PoseFilterConfig& config, const BeaconMap& beacons, const InitialPose& initial);
  ~EkfPoseFilter() override;
  EkfPoseFilter(const EkfPoseFilter&) = delete;
  EkfPoseFilter& operator=(const EkfPoseFilter&) = delete;

  void step(const OdometryIncrement& odometry, const std::vector<BeaconRangeScan>& scans) override;
  PoseBelief belief() const override;
  const FilterCounters& counters() const override;
  FilterKind kind() const override { return FilterKind::kEkf; }
  const RangeInnovations& last_innovations() const override;

 private:
  class Mrpt;
  std::unique_ptr<Mrpt> kf_;
};

}  // namespace losmimo::localization
