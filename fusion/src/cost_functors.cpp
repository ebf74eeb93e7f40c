// The autodiff instantiations of the refinement residuals live in this one TU (build cost).
#include "losmimo/fusion/cost_functors.h"

#include <Eigen/Cholesky>
#include <stdexcept>
#include <string>

namespace losmimo::fusion {

Eigen::MatrixXd sqrt_information(const Eigen::MatrixXd& cov, const char* who) {
  const Eigen::LLT<Eigen::MatrixXd> llt(cov);
  if (!cov.allFinite() || llt.info() != Eigen::Success) {
    throw std::invalid_argument(std::string(who) + ": the covariance is not symmetric positive definite");
  }
  // cov = L L^T  =>  cov^-1 = L^-T L^-1, so S = L^-1 whitens: |S e|^2 = e^T cov^-1 e.
  const Eigen::MatrixXd L = llt.matrixL();
  return L.triangularView<Eigen::Lower>().solve(Eigen::MatrixXd::Identity(cov.rows(), cov.cols()));
}

ceres::CostFunction* PositionPriorCost::Create(const Eigen::Vector3d& mean_m, const Eigen::Matrix3d& cov_m2) {
  return new ceres::AutoDiffCostFunction<PositionPriorCost, 3, 3>(
      new PositionPriorCost(mean_m, sqrt_information(cov_m2, "PositionPriorCost")));
}

ceres::CostFunction* BeaconCost::Create(double range_m, double azimuth_rad, double elevation_rad, double sigma_range_m,
                                        double sigma_angle_rad) {
  return new ceres::AutoDiffCostFunction<BeaconCost, 3, 3>(
      new BeaconCost(range_m, azimuth_rad, elevation_rad, sigma_range_m, sigma_angle_rad));
}

ceres::CostFunction* DisplacementCost::Create(const Eigen::Vector3d& displacement_m, double sigma_m) {
  return new ceres::AutoDiffCostFunction<DisplacementCost, 3, 3, 3>(new DisplacementCost(displacement_m, sigma_m));
}

ceres::CostFunction* CsiPhaseCost::Create(const Eigen::VectorXd& measured_phase_rad, const Eigen::Matrix3Xd& antennas_m,
                                          double wavenumber_rad_per_m, double sigma_phase_rad) {
  auto* functor = new CsiPhaseCost(measured_phase_rad, antennas_m, wavenumber_rad_per_m, sigma_phase_rad);
  const int num_residuals = functor->num_residuals();
  return new ceres::AutoDiffCostFunction<CsiPhaseCost, ceres::DYNAMIC, 3, 1>(functor, num_residuals);
}

}  // namespace losmimo::fusion
