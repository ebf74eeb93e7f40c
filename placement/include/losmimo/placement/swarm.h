#pragma once
// The swarm during a placement run: true UAV positions, their channel, the paper's error
// models, and the distance each UAV has flown.
//
// Errors (paper section 2), drawn from the swarm's own generator:
// - localization: an estimate of UAV m's position is q_m + N(0, sigma_loc_m^2 I), drawn
//   fresh at every estimate;
// - actuation: a commanded motion r from q_m ends at q_m + r + N(0, sigma_act_m^2 I).
// Distances are the true straight-line lengths flown, placement moves and BF probe motions
// kept apart.

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <optional>
#include <random>
#include <string>

#include "losmimo/placement/swarm_channel.h"

namespace losmimo::placement {

struct ErrorModel {
  double sigma_loc_m = 0.0;
  double sigma_act_m = 0.0;
};
// The values each sigma accepts (validate() and the [errors] keys). The bound: beyond ~1e154 m a
// drawn position overflows the channel's distances (1e300 ran with NaN channels).
namespace error_range {
inline constexpr common::Range sigma_loc_m = common::Range::closed(0.0, 1e3);
inline constexpr common::Range sigma_act_m = common::Range::closed(0.0, 1e3);
}  // namespace error_range
// Throws common::FieldError naming the field if a sigma is out of its range.
void validate(const ErrorModel& errors);

enum class MotionKind { kPlacement, kProbe };

// A non-finite move the Swarm refused (Swarm::numerical_fault).
struct SwarmFault {
  int uav = -1;
  std::string reason;  // "UAV 3: commanded move is non-finite (r = (nan, 0, 0))"
};

class Swarm {
 public:
  Swarm(const ChannelModel& model, const Eigen::Matrix3Xd& start_m, const ErrorModel& errors,
        std::uint64_t seed);

  int num_uavs() const { return static_cast<int>(q_m_.cols()); }
  const Eigen::Matrix3Xd& true_positions_m() const { return q_m_; }
  const SwarmChannel& channel() const { return channel_; }
  const ErrorModel& errors() const { return errors_; }

  // Where UAV m believes it is (see the error model above).
  Eigen::Vector3d estimate_position(int m);
  // Commands UAV m to move by r_m; returns the true displacement. With update_channel false
  // the channel keeps UAV m's old row until sync_channel(m): BF's probe flights measure the
  // row at the probe point through UavObjective, and the others' Gram matrix stays fixed.
  // A non-finite r_m, or a move that would leave a non-finite position, is refused: the UAV
  // stays, the move returns zero and the first such move is kept in numerical_fault().
  Eigen::Vector3d move(int m, const Eigen::Vector3d& r_m, MotionKind kind, bool update_channel = true);
  const std::optional<SwarmFault>& numerical_fault() const { return fault_; }
  // UAV m's channel row at its true position (what it measures now, noise-free).
  Eigen::VectorXcd measure_row(int m) const { return channel_.model().row(q_m_.col(m)); }
  void sync_channel(int m) { channel_.set_position(m, q_m_.col(m)); }

  const Eigen::VectorXd& placement_distance_m() const { return placement_dist_m_; }
  const Eigen::VectorXd& probe_distance_m() const { return probe_dist_m_; }

  // A different localization source (e.g. a filter's belief) replaces the Gaussian model.
  using PositionEstimator = std::function<Eigen::Vector3d(int m, const Eigen::Vector3d& true_q_m)>;
  void set_position_estimator(PositionEstimator estimator) { estimator_ = std::move(estimator); }

  std::mt19937_64& rng() { return rng_; }

 private:
  Eigen::Vector3d gaussian(double sigma);

  Eigen::Matrix3Xd q_m_;
  SwarmChannel channel_;
  ErrorModel errors_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  Eigen::VectorXd placement_dist_m_;
  Eigen::VectorXd probe_dist_m_;
  PositionEstimator estimator_;
  std::optional<SwarmFault> fault_;
};

}  // namespace losmimo::placement
