#include "losmimo/fusion/bearing_smoother.h"

#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <memory>
#include <stdexcept>

#include "losmimo/localization/range_az_el.h"
#include "solver_options.h"

namespace losmimo::fusion {

namespace {

using localization::Matrix36d;
using localization::Matrix6d;
using localization::Pose6;

using Map6 = Eigen::Map<const Pose6>;
using RowMajor6 = Eigen::Matrix<double, 6, 6, Eigen::RowMajor>;
using RowMajor36 = Eigen::Matrix<double, 3, 6, Eigen::RowMajor>;

// The inverse of the lower Cholesky factor of a covariance (floored so that it exists).
Matrix6d whitener(const Matrix6d& cov) {
  const Matrix6d floored = 0.5 * (cov + cov.transpose()) + 1e-12 * Matrix6d::Identity();
  const Matrix6d L = floored.llt().matrixL();
  return L.triangularView<Eigen::Lower>().solve(Matrix6d::Identity());
}

// r = Wp dev(x, m).
class PriorCost final : public ceres::SizedCostFunction<6, 6> {
 public:
  PriorCost(const Pose6& mean, const Matrix6d& whiten) : mean_(mean), whiten_(whiten) {}
  bool Evaluate(double const* const* p, double* r, double** J) const override {
    Eigen::Map<Pose6>{r} = whiten_ * localization::pose6_deviation(Map6(p[0]), mean_);
    if (J && J[0]) Eigen::Map<RowMajor6>{J[0]} = whiten_;
    return true;
  }

 private:
  const Pose6 mean_;
  const Matrix6d whiten_;
};

// r = Wk dev(a (+) u, b).
class OdometryCost final : public ceres::SizedCostFunction<6, 6, 6> {
 public:
  OdometryCost(const Pose6& u, const Matrix6d& whiten) : u_(u), whiten_(whiten) {}
  bool Evaluate(double const* const* p, double* r, double** J) const override {
    Matrix6d J_a;
    const Pose6 predicted = localization::compose_pose6(Map6(p[0]), u_, &J_a, nullptr);
    Eigen::Map<Pose6>{r} = whiten_ * localization::pose6_deviation(predicted, Map6(p[1]));
    if (J && J[0]) Eigen::Map<RowMajor6>{J[0]} = whiten_ * J_a;
    if (J && J[1]) Eigen::Map<RowMajor6>{J[1]} = -whiten_;
    return true;
  }

 private:
  const Pose6 u_;
  const Matrix6d whiten_;
};

// r = (z - h(x)) / sigma, angles wrapped.
class ReadingCost final : public ceres::SizedCostFunction<3, 6> {
 public:
  explicit ReadingCost(const localization::AssociatedReading& reading) : reading_(reading) {}
  bool Evaluate(double const* const* p, double* r, double** J) const override {
    Matrix36d H;
    const Eigen::Vector3d h =
        localization::landmark_predict(Map6(p[0]), reading_.sensor_on_robot, reading_.landmark_m, J ? &H : nullptr);
    Eigen::Map<Eigen::Vector3d>{r} = localization::range_az_el_innovation(reading_.z, h).cwiseQuotient(reading_.sigma);
    if (J && J[0]) Eigen::Map<RowMajor36>{J[0]} = -(reading_.sigma.cwiseInverse().asDiagonal() * H);
    return true;
  }

 private:
  const localization::AssociatedReading reading_;
};

}  // namespace

BearingSmootherResult smooth_bearing_track(const localization::LandmarkFilterConfig& config,
                                           const localization::LandmarkBelief& start,
                                           const std::vector<BearingSmootherFrame>& frames, int max_iterations) {
  if (frames.empty()) throw std::invalid_argument("smooth_bearing_track: no frame");
  const std::size_t n = frames.size();
  BearingSmootherResult out;
  out.track.reserve(n);
  for (const BearingSmootherFrame& f : frames) out.track.push_back(f.filter_belief.mean);
  ceres::Problem problem;
  // The start: a floor of 1 mm / 1 mrad keeps a known start (zero covariance) finite.
  const Matrix6d P0 = start.cov + 1e-6 * Matrix6d::Identity();
  problem.AddResidualBlock(new PriorCost(start.mean, whitener(P0)), nullptr, out.track[0].data());
  for (std::size_t k = 1; k < n; ++k) {
    const localization::OdometryIncrement6& u = frames[k].odometry;
    const Matrix6d Q = localization::odometry_noise(config, frames[k - 1].filter_belief.mean, u);
    problem.AddResidualBlock(new OdometryCost(u.delta, whitener(Q)), nullptr, out.track[k - 1].data(),
                             out.track[k].data());
  }
  for (std::size_t k = 0; k < n; ++k) {
    for (const localization::AssociatedReading& r : frames[k].readings) {
      problem.AddResidualBlock(new ReadingCost(r), nullptr, out.track[k].data());
      ++out.readings_used;
    }
  }
  if (config.planar) {
    for (std::size_t k = 0; k < n; ++k) {
      problem.SetManifold(out.track[k].data(), new ceres::SubsetManifold(6, {localization::kP6Z, localization::kP6Pitch,
                                                                             localization::kP6Roll}));
    }
  }
  ceres::Solver::Options options = quiet_solver_options(max_iterations);
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  out.iterations = static_cast<int>(summary.iterations.size());
  out.converged = summary.termination_type == ceres::CONVERGENCE;
  out.initial_cost = summary.initial_cost;
  out.final_cost = summary.final_cost;
  for (Pose6& x : out.track) x = localization::compose_pose6(x, Pose6::Zero());
  return out;
}

}  // namespace losmimo::fusion
