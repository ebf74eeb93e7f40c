// The autodiff instantiations of the pose smoother's residuals live in this one TU (build cost).
#include "losmimo/fusion/pose_cost_functors.h"

namespace losmimo::fusion {

ceres::CostFunction* PosePriorCost::Create(const Eigen::Vector4d& mean, const Eigen::Matrix4d& cov) {
  return new ceres::AutoDiffCostFunction<PosePriorCost, 4, 4>(
      new PosePriorCost(mean, sqrt_information(cov, "PosePriorCost")));
}

ceres::CostFunction* OdometryCost::Create(const Eigen::Vector4d& increment, const Eigen::Matrix4d& cov) {
  return new ceres::AutoDiffCostFunction<OdometryCost, 4, 4, 4>(
      new OdometryCost(increment, sqrt_information(cov, "OdometryCost")));
}

ceres::CostFunction* RangeCost::Create(double range_m, const Eigen::Vector3d& sensor_on_robot_m,
                                       const Eigen::Vector3d& beacon_m, double sigma_m) {
  return new ceres::AutoDiffCostFunction<RangeCost, 1, 4>(new RangeCost(range_m, sensor_on_robot_m, beacon_m, sigma_m));
}

}  // namespace losmimo::fusion
