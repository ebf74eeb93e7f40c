#pragma once
// Pose filters over a 6-D pose (landmark_model.h) with robot-frame odometry and bearing-range
// readings of landmarks at known positions: MRPT's kf-slam problem with the map given (known-map
// localization). The EKF (mrpt::bayes::CKalmanFilterCapable) and the particle filter
// (mrpt::bayes::CParticleFilter with optimal_proposal.h) share this interface and these rules.
//
// One step() is one frame: predict with the odometry, then fuse the frame's readings.
//  - odometry: x' = x (+) u, Q = J_x'_u (Sigma_u + diag(min_odometry_sigma^2)) J_x'_u^T; the floor
//    keeps Q invertible (the particle filter's proposal needs Q^-1).
//  - planar (2-D logs): z, pitch and roll are held at 0 (after every step the mean, the particles
//    and the covariance's rows and columns of those three are set to 0); the elevation then
//    carries no information and is fused harmlessly.
//  - reading noise: R = diag(sigma^2) per reading, sigma = the scan's sensor_std_* where given
//    (> 0) and use_scan_sigma, else `sigma`; floored at min_sigma.
//  - association (associate(), against the predicted moments, the same for both filters):
//    a reading with a landmark ID takes that landmark (an ID not in the map is counted in
//    unknown_id and skipped); one without (ID -1) goes through global nearest neighbour: every
//    (reading, landmark) pair with Mahalanobis distance d^2 = y^T S^-1 y <= gate_chi2
//    (y = z - h(mean), S = H P H^T + R, 3 dof) is a candidate; pairs are taken in increasing d^2,
//    each reading and each landmark at most once per scan. A reading with no candidate is
//    counted in gated; one with two or more candidate landmarks in ambiguous (it is still
//    assigned its nearest, but the count says whether a joint test such as JCBB could have
//    decided differently).
//  - a reading whose landmark lies within kMinLandmarkRho_m of the sensor's z axis is skipped
//    (counted in degenerate).
// The EKF fuses the readings of a frame one after the other (sequential updates; the readings
// are independent given the pose); the particle filter draws every particle from the
// linearised optimal proposal of all the frame's readings and resamples when ESS / N drops
// below ess_threshold.

#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "losmimo/localization/filter_config.h"
#include "losmimo/localization/pose/landmark_model.h"
#include "losmimo/localization/pose/range_model.h"

namespace losmimo::localization {

struct LandmarkFilterConfig {
  bool planar = false;
  bool use_scan_sigma = true;
  Eigen::Vector3d sigma = Eigen::Vector3d(0.01, 0.0017453292519943296, 0.0017453292519943296);  // m, rad, rad
  Eigen::Vector3d min_sigma = Eigen::Vector3d(1e-4, 1e-5, 1e-5);
  double gate_chi2 = 16.27;  // 3-dof chi-square quantile at p = 0.999
  Pose6 min_odometry_sigma = (Pose6() << 1e-4, 1e-4, 1e-4, 1e-5, 1e-5, 1e-5).finished();  // per step
  int num_particles = 200;
  ResamplingMethod resampling = ResamplingMethod::kSystematic;
  double ess_threshold = 0.5;
};

// Throws std::invalid_argument naming the first bad field and its value.
void validate(const LandmarkFilterConfig& config);

struct LandmarkBelief {
  Pose6 mean = Pose6::Zero();
  Matrix6d cov = Matrix6d::Identity();
};

struct OdometryIncrement6 {
  Pose6 delta = Pose6::Zero();  // robot frame, CPose3D parameters
  Matrix6d cov = Matrix6d::Zero();
};

struct LandmarkCounters {
  std::int64_t frames = 0;
  std::int64_t readings = 0;
  std::int64_t fused = 0;
  std::int64_t unknown_id = 0;
  std::int64_t gated = 0;
  std::int64_t ambiguous = 0;
  std::int64_t degenerate = 0;
  std::int64_t resamplings = 0;         // particle filter
  std::int64_t covariance_repairs = 0;  // EKF
  double nis_sum = 0.0;                 // y^T S^-1 y of the fused readings against the prediction
  double innovation_sum_sq = 0.0;       // of the range components [m^2]
};

// A reading the frame will fuse: its landmark and the noise to use.
struct AssociatedReading {
  std::int32_t landmark_id = -1;
  Eigen::Vector3d landmark_m = Eigen::Vector3d::Zero();
  Pose6 sensor_on_robot = Pose6::Zero();
  Eigen::Vector3d z = Eigen::Vector3d::Zero();
  Eigen::Vector3d sigma = Eigen::Vector3d::Ones();
};

// The association rule of the header against the predicted (mean, cov); counts in `counters`
// (readings, unknown_id, gated, ambiguous, degenerate, nis_sum, innovation_sum_sq).
std::vector<AssociatedReading> associate(const LandmarkFilterConfig& config, const BeaconMap& landmarks,
                                         const std::vector<BearingScan>& scans, const LandmarkBelief& predicted,
                                         LandmarkCounters& counters);

// The 1-sigma a filter uses for the readings of `scan`.
Eigen::Vector3d reading_sigma(const LandmarkFilterConfig& config, const BearingScan& scan);

// Q of the header for a step from `mean`.
Matrix6d odometry_noise(const LandmarkFilterConfig& config, const Pose6& mean, const OdometryIncrement6& u);

// Sets z, pitch, roll and their covariance rows and columns to 0 (planar).
void make_planar(LandmarkBelief& belief);

class LandmarkPoseFilter {
 public:
  virtual ~LandmarkPoseFilter() = default;
  virtual void step(const OdometryIncrement6& odometry, const std::vector<BearingScan>& scans) = 0;
  virtual LandmarkBelief belief() const = 0;
  virtual const LandmarkCounters& counters() const = 0;
};

// `seed` drives the particle filter only. Throws std::invalid_argument for a bad config.
std::unique_ptr<LandmarkPoseFilter> make_landmark_filter(FilterKind kind, const LandmarkFilterConfig& config,
                                                         const BeaconMap& landmarks, const LandmarkBelief& start,
                                                         std::uint64_t seed);
// The two kinds (landmark_ekf.cpp, landmark_particle_filter.cpp); config already validated.
std::unique_ptr<LandmarkPoseFilter> make_landmark_ekf(const LandmarkFilterConfig& config, const BeaconMap& landmarks,
                                                      const LandmarkBelief& start);
std::unique_ptr<LandmarkPoseFilter> make_landmark_particle_filter(const LandmarkFilterConfig& config,
                                                                  const BeaconMap& landmarks,
                                                                  const LandmarkBelief& start, std::uint64_t seed);

}  // namespace losmimo::localization
