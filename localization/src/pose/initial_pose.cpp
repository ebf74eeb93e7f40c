#include "losmimo/localization/pose/initial_pose.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "losmimo/localization/position/beacon_model.h"

namespace losmimo::localization {

namespace {

constexpr double kTwoPi = 6.283185307179586;

// The prior's yaw marginal: mean and variance.
void yaw_marginal(const PosePrior& prior, double& mean_rad, double& var_rad2) {
  const PoseBelief m =
      std::holds_alternative<PoseBox>(prior) ? moments(std::get<PoseBox>(prior)) : std::get<PoseBelief>(prior);
  mean_rad = m.mean(kPoseYaw);
  var_rad2 = m.cov(kPoseYaw, kPoseYaw);
}

// g = -dRz/dyaw(yaw) s (position change per radian of heading at a fixed sensor point).
Eigen::Vector3d heading_lever(double yaw_rad, const Eigen::Vector3d& s) {
  const double c = std::cos(yaw_rad);
  const double sn = std::sin(yaw_rad);
  return {sn * s.x() + c * s.y(), -c * s.x() + sn * s.y(), 0.0};
}

}  // namespace

void validate(const PosePrior& prior) {
  if (const PoseBox* box = std::get_if<PoseBox>(&prior)) {
    static const char* kAxis[4] = {"x", "y", "z", "yaw"};
    for (int i = 0; i < kPoseSize; ++i) {
      if (!std::isfinite(box->min(i)) || !std::isfinite(box->max(i)) || box->min(i) > box->max(i)) {
        std::ostringstream msg;
        msg << "pose_box.min_" << kAxis[i] << " = " << box->min(i) << ", max_" << kAxis[i] << " = " << box->max(i)
            << ": must be finite with min <= max";
        throw std::invalid_argument(msg.str());
      }
    }
    if (box->max(kPoseYaw) - box->min(kPoseYaw) > kTwoPi + 1e-12) {
      std::ostringstream msg;
      msg << "pose_box yaw width = " << box->max(kPoseYaw) - box->min(kPoseYaw) << ": must be <= 2 pi";
      throw std::invalid_argument(msg.str());
    }
    return;
  }
  const PoseBelief& g = std::get<PoseBelief>(prior);
  if (const std::optional<std::string> problem = health_problem(g)) {
    throw std::invalid_argument("pose prior " + *problem + ": must be finite");
  }
  const Eigen::LLT<Eigen::Matrix4d> llt(g.cov);
  if (llt.info() != Eigen::Success) {
    std::ostringstream msg;
    msg << "pose prior cov determinant = " << g.cov.determinant() << ": must be positive definite";
    throw std::invalid_argument(msg.str());
  }
}

PoseBelief moments(const PoseBox& box) {
  PoseBelief b;
  b.mean = 0.5 * (box.min + box.max);
  b.mean(kPoseYaw) = wrap_angle_rad(b.mean(kPoseYaw));
  const Eigen::Vector4d width = box.max - box.min;
  b.cov = (width.cwiseAbs2() / 12.0).asDiagonal();
  return b;
}

PoseBelief moments(const InitialPose& initial) {
  if (!initial.fix) {
    if (const PoseBox* box = std::get_if<PoseBox>(&initial.prior)) return moments(*box);
    return std::get<PoseBelief>(initial.prior);
  }
  double yaw_rad = 0.0;
  double var_yaw_rad2 = 0.0;
  yaw_marginal(initial.prior, yaw_rad, var_yaw_rad2);
  const Eigen::Vector3d& s = initial.fix->sensor_on_robot_m;
  const Eigen::Vector3d g = heading_lever(yaw_rad, s);
  PoseBelief b;
  b.mean.head<3>() = initial.fix->fix.sensor_m - sensor_position_m(Eigen::Vector4d(0.0, 0.0, 0.0, yaw_rad), s);
  b.mean(kPoseYaw) = yaw_rad;
  b.cov.setZero();
  b.cov.topLeftCorner<3, 3>() = initial.fix->fix.cov_m2 + var_yaw_rad2 * g * g.transpose();
  b.cov.block<3, 1>(0, kPoseYaw) = var_yaw_rad2 * g;
  b.cov.block<1, 3>(kPoseYaw, 0) = var_yaw_rad2 * g.transpose();
  b.cov(kPoseYaw, kPoseYaw) = var_yaw_rad2;
  return b;
}

InitialPose initial_pose(const PosePrior& prior) {
  validate(prior);
  InitialPose out;
  out.prior = prior;
  return out;
}

InitialPose initial_pose(const std::vector<BeaconRangeScan>& scans, const BeaconMap& beacons,
                         const PoseFilterConfig& config, const PosePrior& prior) {
  InitialPose out = initial_pose(prior);
  if (scans.empty()) return out;
  std::vector<RangeReading> readings;
  std::optional<Eigen::Vector3d> offset_m;
  bool one_offset = true;
  for (const BeaconRangeScan& scan : scans) {
    const double sigma_m = range_sigma_m(config, scan);
    for (const BeaconRange& r : scan.ranges) {
      ++out.counters.ranges_received;
      const RangeVerdict verdict = screen_range(r, scan, beacons, sigma_m, config.filter.max_beacon_range_m);
      if (verdict != RangeVerdict::kUsable) {
        count_rejection(verdict, out.counters);
        continue;
      }
      if (!offset_m) offset_m = r.sensor_on_robot_m;
      one_offset = one_offset && r.sensor_on_robot_m == *offset_m;
      readings.push_back({*beacons.find(r.beacon_id), r.range_m, sigma_m});
    }
  }
  const auto no_fix = [&](const std::string& why) {
    out.note = why;
    out.usable_ranges_not_fused = static_cast<int>(readings.size());
    return out;
  };
  if (static_cast<int>(readings.size()) < config.min_ranges_for_fix) {
    return no_fix(std::to_string(readings.size()) +
                  " usable range(s) < min_ranges_for_fix = " + std::to_string(config.min_ranges_for_fix));
  }
  if (!one_offset) return no_fix("the readings have different sensor offsets");

  // The prior of the sensor point (header).
  const PoseBelief m = moments(out);  // no fix yet: the prior's moments
  const Eigen::Vector3d s = *offset_m;
  const double lever2 = s.head<2>().squaredNorm();
  const Eigen::Vector3d c0_m = sensor_position_m(m.mean, s);
  const Eigen::Matrix3d P0_m2 =
      m.cov.topLeftCorner<3, 3>() + lever2 * Eigen::Vector3d(1.0, 1.0, 0.0).asDiagonal().toDenseMatrix();
  const RangeFixResult result = range_fix(readings, c0_m, P0_m2);
  if (!result.fix) return no_fix(result.problem);
  out.fix = SensorFix{*result.fix, s};
  out.counters.ranges_fused += static_cast<std::int64_t>(readings.size());
  return out;
}

Eigen::Vector4d sample_initial_pose(const InitialPose& initial, mrpt::random::CRandomGenerator& rng) {
  const auto normal = [&rng] { return rng.drawGaussian1D_normalized(); };
  const auto uniform = [&rng](double lo, double hi) { return lo == hi ? lo : rng.drawUniform(lo, hi); };
  const PoseBox* box = std::get_if<PoseBox>(&initial.prior);
  if (!initial.fix) {
    if (box) {
      Eigen::Vector4d x;
      for (int i = 0; i < kPoseSize; ++i) x(i) = uniform(box->min(i), box->max(i));
      x(kPoseYaw) = wrap_angle_rad(x(kPoseYaw));
      return x;
    }
    const PoseBelief& g = std::get<PoseBelief>(initial.prior);
    const Eigen::Matrix4d L = g.cov.llt().matrixL();
    Eigen::Vector4d n;
    for (int i = 0; i < kPoseSize; ++i) n(i) = normal();
    Eigen::Vector4d x = g.mean + L * n;
    x(kPoseYaw) = wrap_angle_rad(x(kPoseYaw));
    return x;
  }
  double yaw_rad = 0.0;
  if (box) {
    yaw_rad = uniform(box->min(kPoseYaw), box->max(kPoseYaw));
  } else {
    const PoseBelief& g = std::get<PoseBelief>(initial.prior);
    yaw_rad = g.mean(kPoseYaw) + std::sqrt(g.cov(kPoseYaw, kPoseYaw)) * normal();
  }
  const Eigen::Matrix3d L = initial.fix->fix.cov_m2.llt().matrixL();
  Eigen::Vector3d n;
  for (int i = 0; i < 3; ++i) n(i) = normal();
  const Eigen::Vector3d c_m = initial.fix->fix.sensor_m + L * n;
  const Eigen::Vector3d offset_m =
      sensor_position_m(Eigen::Vector4d(0.0, 0.0, 0.0, yaw_rad), initial.fix->sensor_on_robot_m);
  return {c_m.x() - offset_m.x(), c_m.y() - offset_m.y(), c_m.z() - offset_m.z(), wrap_angle_rad(yaw_rad)};
}

}  // namespace losmimo::localization
