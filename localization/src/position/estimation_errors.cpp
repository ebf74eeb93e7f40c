#include "losmimo/localization/position/estimation_errors.h"

#include <cmath>
#include <limits>

namespace losmimo::localization {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

double nees(const Belief& belief, const Eigen::Vector3d& truth_m) {
  return nees<3>(belief.mean_m - truth_m, belief.cov_m2);
}

void ErrorAccumulator::add(const Eigen::Vector3d& estimate_m, const Eigen::Vector3d& truth_m) {
  const Eigen::Vector3d e = estimate_m - truth_m;
  sq_m2_ += e.squaredNorm();
  lateral_sq_m2_ += e.tail<2>().squaredNorm();
  ++samples_;
}

void ErrorAccumulator::add(const Belief& belief, const Eigen::Vector3d& truth_m) {
  add(belief.mean_m, truth_m);
  nees_ += nees(belief, truth_m);
  ++nees_samples_;
}

ErrorAccumulator& ErrorAccumulator::operator+=(const ErrorAccumulator& other) {
  sq_m2_ += other.sq_m2_;
  lateral_sq_m2_ += other.lateral_sq_m2_;
  nees_ += other.nees_;
  samples_ += other.samples_;
  nees_samples_ += other.nees_samples_;
  return *this;
}

double ErrorAccumulator::rmse_m() const {
  return samples_ > 0 ? std::sqrt(sq_m2_ / static_cast<double>(samples_)) : kNaN;
}

double ErrorAccumulator::lateral_rmse_m() const {
  return samples_ > 0 ? std::sqrt(lateral_sq_m2_ / static_cast<double>(samples_)) : kNaN;
}

double ErrorAccumulator::average_nees() const {
  return nees_samples_ > 0 ? nees_ / static_cast<double>(nees_samples_) : kNaN;
}

}  // namespace losmimo::localization
