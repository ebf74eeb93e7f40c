#pragma once
// A seeded simulated refinement window, shared by the fusion tests and the benchmark.
//
// A UAV starts uniformly in the default start cube (1 km, side 50 m) and flies placement-sized
// steps (uniform 0.1 - 1 m, random direction). Every sensor is drawn from the model the
// refinement assumes (refinement.h), with the config's sigmas:
//   prior (every epoch's filter_belief): truth + N(0, diag(kPriorSigma_m^2)), that covariance;
//   dead reckoning: true displacement + N(0, sigma^2 I), sigma = floor + fraction * |d_true|;
//   beacon: range / azimuth / elevation of the truth + Gaussian noise;
//   CSI: simulate_csi with config.csi_noise_variance.
// noise_scale = 0 gives exact measurements and prior (the CSI noise scales as its variance).
#include <Eigen/Core>
#include <cmath>
#include <random>
#include <vector>

#include "losmimo/fusion/refinement.h"

namespace losmimo::test_support {

// Prior of the oldest epoch: a filter that has fused the beacon for a while [m].
inline const Eigen::Vector3d kPriorSigma_m(0.20, 0.15, 0.15);

struct DrawnWindow {
  std::vector<fusion::RefinementEpoch> epochs;
  Eigen::Matrix3Xd truth_m;
};

// num_epochs epochs as described above; truth_m holds the true positions (3 x num_epochs).
inline DrawnWindow draw_window(const placement::ChannelModel& model, const fusion::RefinementConfig& config,
                               int num_epochs, std::mt19937_64& rng, double noise_scale = 1.0) {
  std::normal_distribution<double> n01;
  std::uniform_real_distribution<double> cube(-25.0, 25.0);
  std::uniform_real_distribution<double> step_len(0.1, 1.0);
  DrawnWindow w;
  w.truth_m.resize(3, num_epochs);
  w.truth_m.col(0) = Eigen::Vector3d(1000.0 + cube(rng), cube(rng), cube(rng));
  for (int i = 1; i < num_epochs; ++i) {
    const Eigen::Vector3d dir = Eigen::Vector3d(n01(rng), n01(rng), n01(rng)).normalized();
    w.truth_m.col(i) = w.truth_m.col(i - 1) + step_len(rng) * dir;
  }
  const Eigen::Matrix3d prior_cov = kPriorSigma_m.cwiseAbs2().asDiagonal();
  for (int i = 0; i < num_epochs; ++i) {
    const Eigen::Vector3d q = w.truth_m.col(i);
    fusion::RefinementEpoch e;
    e.filter_belief.cov_m2 = prior_cov;
    e.filter_belief.mean_m =
        q + noise_scale * kPriorSigma_m.cwiseProduct(Eigen::Vector3d(n01(rng), n01(rng), n01(rng)));
    if (i > 0) {
      const Eigen::Vector3d d = q - w.truth_m.col(i - 1);
      const double sigma = config.dr_sigma_floor_m + config.dr_sigma_fraction * d.norm();
      e.displacement_m = d + noise_scale * sigma * Eigen::Vector3d(n01(rng), n01(rng), n01(rng));
    }
    localization::BeaconMeasurement z;
    z.range_m = q.norm() + noise_scale * config.beacon_sigma_range_m * n01(rng);
    z.azimuth_rad = std::atan2(q.y(), q.x()) + noise_scale * config.beacon_sigma_angle_rad * n01(rng);
    z.elevation_rad = std::atan2(q.z(), q.head<2>().norm()) + noise_scale * config.beacon_sigma_angle_rad * n01(rng);
    e.beacon = z;
    e.csi.push_back(fusion::simulate_csi(model, q, noise_scale * noise_scale * config.csi_noise_variance, rng));
    w.epochs.push_back(e);
  }
  return w;
}

}  // namespace losmimo::test_support
