#include "losmimo/fusion/rawlog/mrpt_logs/bearing_log.h"

#include <algorithm>

#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/poses/CPosePDF.h>

#include "log_loader.h"
#include "losmimo/localization/pose/odometry_model.h"

namespace losmimo::mrpt_logs {

namespace {

using localization::OdometryIncrement6;
using localization::Pose6;

// A 2-D increment (x, y, phi) with its 3x3 covariance as a 6-D one.
OdometryIncrement6 planar_increment(double x, double y, double phi, const Eigen::Matrix3d& cov) {
  OdometryIncrement6 u;
  u.delta << x, y, 0.0, phi, 0.0, 0.0;
  const int idx[3] = {localization::kP6X, localization::kP6Y, localization::kP6Yaw};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) u.cov(idx[r], idx[c]) = cov(r, c);
  return u;
}

class Loader : public detail::LogLoader<Loader, BearingLog, BearingFrame, mrpt::obs::CObservationBearingRange> {
 public:
  using LogLoader::LogLoader;

  void add_observation_to(const mrpt::obs::CObservation& o, BearingFrame& frame) {
    const std::string name = o.GetRuntimeClass()->className;
    const auto* b = dynamic_cast<const mrpt::obs::CObservationBearingRange*>(&o);
    if (!b) {
      ++log_.skipped[name];
      return;
    }
    localization::BearingScan scan;
    const mrpt::poses::CPose3D& s = b->sensorLocationOnRobot;
    scan.sensor_on_robot << s.x(), s.y(), s.z(), s.yaw(), s.pitch(), s.roll();
    scan.sigma = Eigen::Vector3d(b->sensor_std_range, b->sensor_std_yaw, b->sensor_std_pitch);
    scan.max_range_m = b->maxSensorDistance;
    for (const auto& m : b->sensedData) {
      scan.readings.push_back({m.landmarkID, localization::to_range_az_el(m.range, m.yaw, m.pitch)});
      if (m.landmarkID < 0) ++log_.readings_without_id;
      if (m.pitch != 0.0f) ++log_.nonzero_pitch_readings;
    }
    const auto n = static_cast<std::int64_t>(b->sensedData.size());
    log_.readings += n;
    log_.max_readings_per_observation = std::max(log_.max_readings_per_observation, n);
    if (b->validCovariances) ++log_.valid_covariance_observations;
    ++log_.bearing_observations;
    ++log_.used[name];
    frame.scans.push_back(std::move(scan));
  }

  void add_action(const mrpt::obs::CAction& a) {
    const std::string name = a.GetRuntimeClass()->className;
    if (const auto* m3 = dynamic_cast<const mrpt::obs::CActionRobotMovement3D*>(&a)) {
      const auto& p = m3->poseChange.mean;
      OdometryIncrement6 u;
      u.delta << p.x(), p.y(), p.z(), p.yaw(), p.pitch(), p.roll();
      u.cov = m3->poseChange.cov.asEigen();
      add_increment(u);
      ++log_.actions_3d;
      ++log_.used[name];
    } else if (const auto* m2 = dynamic_cast<const mrpt::obs::CActionRobotMovement2D*>(&a); m2 && m2->poseChange) {
      mrpt::math::CMatrixDouble33 cov;
      mrpt::poses::CPose2D mean;
      m2->poseChange->getCovarianceAndMean(cov, mean);
      add_increment(planar_increment(mean.x(), mean.y(), mean.phi(), cov.asEigen()));
      ++log_.used[name];
    } else {
      ++log_.skipped[name];
    }
  }

  // A 2-D increment between two odometry poses, with the 2-D motion model's covariance, as 6-D.
  OdometryIncrement6 odometry_increment(const Eigen::Vector4d& u) const {
    const localization::OdometryIncrement o =
        localization::odometry_2d(u(0), u(1), u(3), localization::GaussianMotionModel2D{});
    Eigen::Matrix3d cov;
    const int idx[3] = {localization::kPoseX, localization::kPoseY, localization::kPoseYaw};
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) cov(r, c) = o.cov(idx[r], idx[c]);
    return planar_increment(u(0), u(1), u(3), cov);
  }

  static OdometryIncrement6 chain(const OdometryIncrement6& u1, const OdometryIncrement6& u2) {
    localization::Matrix6d J_x, J_u;
    OdometryIncrement6 out;
    out.delta = localization::compose_pose6(u1.delta, u2.delta, &J_x, &J_u);
    out.cov = J_x * u1.cov * J_x.transpose() + J_u * u2.cov * J_u.transpose();
    return out;
  }
};

}  // namespace

BearingLog load_bearing_log(rawlog_io::RawlogReader& reader) { return detail::load_log<Loader, BearingLog>(reader); }

}  // namespace losmimo::mrpt_logs
