#pragma once
// Position EKF through mrpt::bayes::CKalmanFilterCapable<3, 3, 0, 3> (state q, beacon z, no map,
// action d). Models and robustness rules: filter.h and beacon_model.h.
//
// Prediction:  q = q + d,  F = J_q'_q = I,  P = P + sigma_d(|d|)^2 I.
// Update:      y = z - h(q) with wrapped angles (OnSubstractObservationVectors), H = J_z_q,
//              S = H P H^T + R, K = P H^T S^-1, q = q + K y.
// Covariance: MRPT's kfEKFNaive applies P = (I - K H) P; OnPostIteration replaces it by the
// Joseph form (I - K H) P (I - K H)^T + K R K^T, computed from the same predicted P, H and S,
// then symmetrises it and floors its eigenvalues (make_spd). The EKF draws no random numbers.
// The MRPT class lives in ekf_filter.cpp only (one heavy template instantiation per build).

#include <memory>

#include "losmimo/localization/position/filter.h"

namespace losmimo::localization {

class EkfPositionFilter final : public PositionFilter {
 public:
  EkfPositionFilter(const FilterConfig& config, const Belief& initial);
  ~EkfPositionFilter() override;
  EkfPositionFilter(const EkfPositionFilter&) = delete;
  EkfPositionFilter& operator=(const EkfPositionFilter&) = delete;

  void step(const Eigen::Vector3d& measured_displacement_m, const std::optional<BeaconMeasurement>& beacon) override;
  Belief belief() const override;
  const FilterCounters& counters() const override;
  FilterKind kind() const override { return FilterKind::kEkf; }

 private:
  class Mrpt;
  std::unique_ptr<Mrpt> kf_;
};

}  // namespace losmimo::localization
