#include "losmimo/placement/swarm.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "losmimo/placement/common/field_error.h"
#include "losmimo/placement/common/range.h"
#include "losmimo/placement/common/seed.h"

namespace losmimo::placement {

void validate(const ErrorModel& errors) {
  common::require_field_in(error_range::sigma_loc_m, errors.sigma_loc_m, "errors", "sigma_loc_m");
  common::require_field_in(error_range::sigma_act_m, errors.sigma_act_m, "errors", "sigma_act_m");
  common::require_field_in(error_range::sigma_loc_common_m, errors.sigma_loc_common_m, "errors", "sigma_loc_common_m");
}

std::string to_string(SigmaConvention convention) {
  return convention == SigmaConvention::kRms3d ? "rms_3d" : "per_axis";
}

SigmaConvention sigma_convention_from_string(const std::string& name) {
  if (name == "per_axis") return SigmaConvention::kPerAxis;
  if (name == "rms_3d") return SigmaConvention::kRms3d;
  throw std::invalid_argument("unknown sigma convention '" + name + "' (known: per_axis, rms_3d)");
}

std::string to_string(LocError kind) { return kind == LocError::kFixedPerUav ? "fixed_per_uav" : "fresh"; }

LocError loc_error_from_string(const std::string& name) {
  if (name == "fresh") return LocError::kFresh;
  if (name == "fixed_per_uav") return LocError::kFixedPerUav;
  throw std::invalid_argument("unknown localization error kind '" + name + "' (known: fresh, fixed_per_uav)");
}

double ErrorModel::axis_sigma(double sigma_m) const {
  return sigma_convention == SigmaConvention::kRms3d ? sigma_m / std::sqrt(3.0) : sigma_m;
}

Swarm::Swarm(const ChannelModel& model, const Eigen::Matrix3Xd& start_m, const ErrorModel& errors, std::uint64_t seed)
    : q_m_(start_m),
      channel_(model, start_m),
      errors_(errors),
      normal_key_(seed),
      placement_dist_m_(Eigen::VectorXd::Zero(start_m.cols())),
      probe_dist_m_(Eigen::VectorXd::Zero(start_m.cols())),
      commanded_placement_dist_m_(Eigen::VectorXd::Zero(start_m.cols())),
      commanded_probe_dist_m_(Eigen::VectorXd::Zero(start_m.cols())) {
  validate(errors);
  axis_sigma_loc_m_ = errors.axis_sigma_loc_m();
  axis_sigma_act_m_ = errors.axis_sigma_act_m();
  if (errors.loc_error == LocError::kFixedPerUav) {
    // Its own generator: the swarm's stream then draws only the actuation errors.
    std::mt19937_64 bias_rng(common::derive_seed(seed, {1}));
    std::normal_distribution<double> normal(0.0, 1.0);
    loc_bias_m_.resize(3, start_m.cols());
    for (Eigen::Index m = 0; m < start_m.cols(); ++m) {
      for (int i = 0; i < 3; ++i) loc_bias_m_(i, m) = normal(bias_rng) * axis_sigma_loc_m_;
    }
  }
  if (errors.sigma_loc_common_m > 0.0) {
    // Its own generator too: without a common part nothing else is drawn differently.
    std::mt19937_64 common_rng(common::derive_seed(seed, {2}));
    std::normal_distribution<double> normal(0.0, 1.0);
    for (int i = 0; i < 3; ++i) loc_common_m_(i) = normal(common_rng) * errors.axis_sigma_loc_common_m();
  }
}

void Swarm::refill_normals() {
  static_assert((kNormalBlocks * kernels::kNormalsPerBlock) % 3 == 0, "draws of three must not straddle a refill");
  channel_.model().kernels().normals(normal_key_, normal_next_block_, normal_buffer_.data(), kNormalBlocks);
  normal_next_block_ += kNormalBlocks;
  normal_used_ = 0;
}

Eigen::Vector3d Swarm::estimate_position(int m) {
  ++position_estimates_;
  if (estimator_) return estimator_(m, q_m_.col(m));
  if (loc_bias_m_.size() > 0) return q_m_.col(m) + loc_bias_m_.col(m) + loc_common_m_;
  return q_m_.col(m) + gaussian(axis_sigma_loc_m_) + loc_common_m_;
}

void Swarm::count_exact_probe(int m, const Eigen::Vector3d& r_m) {
  const double length = 2.0 * r_m.norm();
  probe_dist_m_(m) += length;
  commanded_probe_dist_m_(m) += length;
}

namespace {
std::string format_vector(const Eigen::Vector3d& v) {
  std::ostringstream text;
  text << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return text.str();
}
}  // namespace

Eigen::Vector3d Swarm::move(int m, const Eigen::Vector3d& r_m, MotionKind kind, bool update_channel) {
  const Eigen::Vector3d actual = r_m + gaussian(axis_sigma_act_m_);
  if (!r_m.allFinite() || !(q_m_.col(m) + actual).allFinite()) {
    if (!fault_) {
      const std::string what = !r_m.allFinite()
                                   ? "commanded move is non-finite (r = " + format_vector(r_m) + ")"
                                   : "move leaves a non-finite position (q = " + format_vector(q_m_.col(m)) +
                                         ", r = " + format_vector(r_m) + ")";
      fault_ = SwarmFault{m, "UAV " + std::to_string(m) + ": " + what};
    }
    return Eigen::Vector3d::Zero();
  }
  q_m_.col(m) += actual;
  if (update_channel) sync_channel(m);
  (kind == MotionKind::kProbe ? probe_dist_m_ : placement_dist_m_)(m) += actual.norm();
  (kind == MotionKind::kProbe ? commanded_probe_dist_m_ : commanded_placement_dist_m_)(m) += r_m.norm();
  return actual;
}

void Swarm::sync_channel(int m) {
  if (!conditions_.active()) {
    channel_.set_position(m, q_m_.col(m));
    return;
  }
  thread_local Eigen::VectorXcd row;
  measure_row_into(m, row);
  channel_.set_row(m, row);
}

void Swarm::sync_channels() {
  if (!conditions_.active()) {
    channel_.set_positions(q_m_);
    return;
  }
  for (int m = 0; m < num_uavs(); ++m) sync_channel(m);
}

void Swarm::set_channel_conditions(const ChannelConditions& conditions) {
  if (conditions.active() &&
      (conditions.num_uavs() != num_uavs() || conditions.num_antennas() != channel_.model().num_antennas())) {
    throw std::invalid_argument("Swarm: channel conditions for " + std::to_string(conditions.num_uavs()) + " x " +
                                std::to_string(conditions.num_antennas()) + ", the swarm is " +
                                std::to_string(num_uavs()) + " x " + std::to_string(channel_.model().num_antennas()));
  }
  conditions_ = conditions;
  if (!conditions_.active()) return;
  for (int m = 0; m < num_uavs(); ++m) sync_channel(m);
  channel_.refresh();
}

void Swarm::begin_iteration(int iteration) {
  if (!conditions_.active() || !conditions_.begin_iteration(iteration) || !conditions_.settings().fading()) return;
  for (int m = 0; m < num_uavs(); ++m) sync_channel(m);
  channel_.refresh();
}

void Swarm::measure_row_into(int m, Eigen::VectorXcd& x) {
  channel_.model().row(q_m_.col(m), x);
  if (conditions_.active()) conditions_.measure_row(m, x);
}

Eigen::MatrixXcd Swarm::true_channel() const {
  Eigen::MatrixXcd H = channel_.model().matrix(q_m_);
  if (conditions_.settings().fading()) {
    for (int m = 0; m < num_uavs(); ++m) {
      Eigen::VectorXcd row = H.row(m).transpose();
      conditions_.fade_row(m, row);
      H.row(m) = row.transpose();
    }
  }
  return H;
}

}  // namespace losmimo::placement
