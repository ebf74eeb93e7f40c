#include "losmimo/placement/swarm.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace losmimo::placement {

void validate(const ErrorModel& errors) {
  const auto check = [](const char* field, double value) {
    if (!(value >= 0.0 && value <= kMaxErrorSigma_m)) {
      std::ostringstream msg;
      msg << "errors." << field << " = " << value << ": must be in [0, 1e3] m";
      throw std::invalid_argument(msg.str());
    }
  };
  check("sigma_loc_m", errors.sigma_loc_m);
  check("sigma_act_m", errors.sigma_act_m);
}

Swarm::Swarm(const ChannelModel& model, const Eigen::Matrix3Xd& start_m, const ErrorModel& errors,
             std::uint64_t seed)
    : q_m_(start_m),
      channel_(model, start_m),
      errors_(errors),
      rng_(seed),
      placement_dist_m_(Eigen::VectorXd::Zero(start_m.cols())),
      probe_dist_m_(Eigen::VectorXd::Zero(start_m.cols())) {
  validate(errors);
}

Eigen::Vector3d Swarm::gaussian(double sigma) {
  if (sigma == 0.0) return Eigen::Vector3d::Zero();
  return Eigen::Vector3d(normal_(rng_), normal_(rng_), normal_(rng_)) * sigma;
}

Eigen::Vector3d Swarm::estimate_position(int m) {
  if (estimator_) return estimator_(m, q_m_.col(m));
  return q_m_.col(m) + gaussian(errors_.sigma_loc_m);
}

Eigen::Vector3d Swarm::move(int m, const Eigen::Vector3d& r_m, MotionKind kind, bool update_channel) {
  const Eigen::Vector3d actual = r_m + gaussian(errors_.sigma_act_m);
  q_m_.col(m) += actual;
  if (update_channel) channel_.set_position(m, q_m_.col(m));
  (kind == MotionKind::kProbe ? probe_dist_m_ : placement_dist_m_)(m) += actual.norm();
  return actual;
}

}  // namespace losmimo::placement
