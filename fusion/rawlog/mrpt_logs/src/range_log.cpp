#include "losmimo/mrpt_logs/range_log.h"

#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservationBeaconRanges.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPosePDF.h>
#include <mrpt/system/datetime.h>

#include "losmimo/rawlog_io/labels.h"

namespace losmimo::mrpt_logs {

namespace {

using localization::OdometryIncrement;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

double seconds_of(const mrpt::Clock::time_point& t) { return t == INVALID_TIMESTAMP ? kNan : mrpt::Clock::toDouble(t); }

// u1 (+) u2 with the covariance of the header.
OdometryIncrement chain(const OdometryIncrement& u1, const OdometryIncrement& u2) {
  OdometryIncrement out;
  out.delta = localization::compose(u1.delta, u2.delta);
  const Eigen::Matrix4d Jx = localization::compose_jacobian_pose(u1.delta, u2.delta);
  const Eigen::Matrix4d Ju = localization::compose_jacobian_increment(u1.delta);
  out.cov = Jx * u1.cov * Jx.transpose() + Ju * u2.cov * Ju.transpose();
  return out;
}

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

class Loader {
 public:
  explicit Loader(RangeLog& log) : log_(log) {}

  void add(const mrpt::serialization::CSerializable& obj, const std::string& class_name) {
    if (const auto* sf = dynamic_cast<const mrpt::obs::CSensoryFrame*>(&obj)) {
      RangeFrame frame;
      frame.step = sensory_frames_++;
      frame.timestamp_s = kNan;
      for (const auto& o : *sf) {
        if (!o) continue;
        if (std::isnan(frame.timestamp_s)) frame.timestamp_s = seconds_of(o->timestamp);
        add_observation_to(*o, frame);
      }
      take_pending(frame);
      log_.frames.push_back(std::move(frame));
      return;
    }
    if (const auto* acts = dynamic_cast<const mrpt::obs::CActionCollection*>(&obj)) {
      for (std::size_t i = 0; i < acts->size(); ++i) add_action(acts->get(i));
      return;
    }
    const std::int64_t index = top_level_++;
    if (const auto* b = dynamic_cast<const mrpt::obs::CObservationBeaconRanges*>(&obj)) {
      RangeFrame frame;
      frame.step = index;
      frame.timestamp_s = seconds_of(b->timestamp);
      add_observation_to(*b, frame);
      take_pending(frame);
      log_.frames.push_back(std::move(frame));
      return;
    }
    if (const auto* odo = dynamic_cast<const mrpt::obs::CObservationOdometry*>(&obj)) {
      const Eigen::Vector4d p(odo->odometry.x(), odo->odometry.y(), 0.0, odo->odometry.phi());
      if (last_odometry_) {
        const Eigen::Vector4d u = localization::increment_between(*last_odometry_, p);
        add_increment(localization::odometry_2d(u(0), u(1), u(3), localization::GaussianMotionModel2D{}));
      }
      last_odometry_ = p;
      ++log_.used[class_name];
      return;
    }
    ++log_.skipped[class_name];
  }

  void finish() {
    if (pending_) ++log_.trailing_actions;
  }

 private:
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

  void add_increment(const OdometryIncrement& u) { pending_ = pending_ ? chain(*pending_, u) : u; }

  void take_pending(RangeFrame& frame) {
    if (pending_) {
      frame.has_odometry = true;
      frame.odometry = *pending_;
    }
    pending_.reset();
  }

  RangeLog& log_;
  std::int64_t sensory_frames_ = 0;
  std::int64_t top_level_ = 0;
  std::optional<OdometryIncrement> pending_;
  std::optional<Eigen::Vector4d> last_odometry_;
};

}  // namespace

RangeLog load_range_log(rawlog_io::RawlogReader& reader) {
  RangeLog log;
  Loader loader(log);
  while (auto object = reader.next()) {
    if (object->object) loader.add(*object->object, object->class_name);
  }
  loader.finish();
  log.read_status = reader.status();
  return log;
}

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
