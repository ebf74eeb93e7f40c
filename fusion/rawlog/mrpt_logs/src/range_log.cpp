#include "losmimo/fusion/rawlog/mrpt_logs/range_log.h"

#include <sstream>

#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservationBeaconRanges.h>
#include <mrpt/poses/CPosePDF.h>

#include "log_loader.h"
#include "losmimo/fusion/rawlog/io/labels.h"

namespace losmimo::mrpt_logs {

namespace {

using localization::OdometryIncrement;

localization::BeaconRangeScan scan_of(const mrpt::obs::CObservationBeaconRanges& obs) {
  localization::BeaconRangeScan scan;
  scan.std_error_m = obs.stdError;
  scan.min_sensor_distance_m = obs.minSensorDistance;
  scan.max_sensor_distance_m = obs.maxSensorDistance;
  for (const auto& m : obs.sensedData) {
    localization::BeaconRange r;
    r.beacon_id = m.beaconID;
    r.range_m = m.sensedDistance;
    r.sensor_on_robot_m =
        Eigen::Vector3d(m.sensorLocationOnRobot.x(), m.sensorLocationOnRobot.y(), m.sensorLocationOnRobot.z());
    scan.ranges.push_back(r);
  }
  return scan;
}

class Loader : public detail::LogLoader<Loader, RangeLog, RangeFrame, mrpt::obs::CObservationBeaconRanges> {
 public:
  using LogLoader::LogLoader;

  void add_observation_to(const mrpt::obs::CObservation& o, RangeFrame& frame) {
    const std::string name = o.GetRuntimeClass()->className;
    if (const auto* b = dynamic_cast<const mrpt::obs::CObservationBeaconRanges*>(&o)) {
      frame.scans.push_back(scan_of(*b));
      if (const auto label = rawlog_io::split_uav_label(b->sensorLabel)) log_.beacon_uavs.insert(label->uav);
      ++log_.beacon_observations;
      log_.ranges += static_cast<std::int64_t>(b->sensedData.size());
      ++log_.used[name];
    } else {
      ++log_.skipped[name];
    }
  }

  void add_action(const mrpt::obs::CAction& a) {
    const std::string name = a.GetRuntimeClass()->className;
    if (const auto* m3 = dynamic_cast<const mrpt::obs::CActionRobotMovement3D*>(&a)) {
      const auto& p = m3->poseChange.mean;
      add_increment(
          localization::odometry_3d(Eigen::Vector4d(p.x(), p.y(), p.z(), p.yaw()), m3->poseChange.cov.asEigen()));
      ++log_.used[name];
    } else if (const auto* m2 = dynamic_cast<const mrpt::obs::CActionRobotMovement2D*>(&a); m2 && m2->poseChange) {
      mrpt::math::CMatrixDouble33 cov;
      mrpt::poses::CPose2D mean;
      m2->poseChange->getCovarianceAndMean(cov, mean);
      OdometryIncrement u;
      u.delta = Eigen::Vector4d(mean.x(), mean.y(), 0.0, mean.phi());
      const int idx[3] = {localization::kPoseX, localization::kPoseY, localization::kPoseYaw};
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) u.cov(idx[r], idx[c]) = cov(r, c);
      add_increment(u);
      ++log_.used[name];
    } else {
      ++log_.skipped[name];
    }
  }

  // A 2-D increment between two odometry poses, with the 2-D motion model's covariance.
  OdometryIncrement odometry_increment(const Eigen::Vector4d& u) const {
    return localization::odometry_2d(u(0), u(1), u(3), localization::GaussianMotionModel2D{});
  }

  // u1 (+) u2 with the covariance of the header.
  static OdometryIncrement chain(const OdometryIncrement& u1, const OdometryIncrement& u2) {
    OdometryIncrement out;
    out.delta = localization::compose(u1.delta, u2.delta);
    const Eigen::Matrix4d Jx = localization::compose_jacobian_pose(u1.delta, u2.delta);
    const Eigen::Matrix4d Ju = localization::compose_jacobian_increment(u1.delta);
    out.cov = Jx * u1.cov * Jx.transpose() + Ju * u2.cov * Ju.transpose();
    return out;
  }
};

}  // namespace

RangeLog load_range_log(rawlog_io::RawlogReader& reader) { return detail::load_log<Loader, RangeLog>(reader); }

std::string describe_counts(const std::map<std::string, std::int64_t>& counts) {
  if (counts.empty()) return "none";
  std::ostringstream s;
  bool first = true;
  for (const auto& [name, n] : counts) {
    s << (first ? "" : ", ") << name << " x " << n;
    first = false;
  }
  return s.str();
}

}  // namespace losmimo::mrpt_logs
