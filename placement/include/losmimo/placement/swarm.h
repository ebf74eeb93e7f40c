#pragma once
// The swarm during a placement run: true UAV positions, their channel, the paper's error
// models, and the distance each UAV has flown.
//
// Errors (paper section 2), drawn from the swarm's own stream of standard normal numbers:
// - localization: an estimate of UAV m's position is q_m + N(0, s_loc^2 I), drawn fresh at
//   every estimate;
// - actuation: a commanded motion r from q_m ends at q_m + r + N(0, s_act^2 I).
// The per-axis deviations s are the sigmas as given (SigmaConvention::kPerAxis) or sigma / sqrt(3)
// (kRms3d: sigma is the RMS length of the 3-D error). The paper says only "random Gaussian
// variables with standard deviations sigma_loc and sigma_act"; per axis is the default.
// With LocError::kFixedPerUav the localization error of UAV m is one draw n_m per swarm (a bias
// that stays for the whole run), from a generator of its own seeded from the swarm's seed.
// A common-mode part (sigma_loc_common_m, default 0) adds one offset c ~ N(0, s_common^2 I),
// drawn once per swarm from another generator of its own and shared by every UAV for the whole
// run, to every estimate: a BS array mounted off its bearing or a BS position surveyed wrong
// moves every UAV's fix the same way (placement/swarm_shape.h: the channel barely sees it).
// The stream is counter-based (kernels.h, normals, keyed by the swarm's seed): its i-th number
// depends on (seed, i) only, the same on every instruction set, and it comes 16 per vector
// block. A zero sigma draws nothing.
// Distances: the true straight-line lengths flown, and the commanded lengths |r|, placement
// moves and BF probe motions kept apart.
//
// Channel conditions (channel_conditions.h, inactive unless set): with Rician fading or CSI
// estimation noise, every row the swarm's channel caches is a measurement (the broadcast rows,
// the master's Gram matrix), BF's probes measure through measure_row_into, and the true channel
// (true_channel) is for evaluation only.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <random>
#include <string>

#include "losmimo/placement/channel_conditions.h"
#include "losmimo/placement/swarm_channel.h"

namespace losmimo::placement {

enum class SigmaConvention { kPerAxis, kRms3d };
// "per_axis", "rms_3d"; from_string throws std::invalid_argument listing the names.
std::string to_string(SigmaConvention convention);
SigmaConvention sigma_convention_from_string(const std::string& name);

enum class LocError { kFresh, kFixedPerUav };
// "fresh", "fixed_per_uav".
std::string to_string(LocError kind);
LocError loc_error_from_string(const std::string& name);

struct ErrorModel {
  double sigma_loc_m = 0.0;
  double sigma_act_m = 0.0;
  SigmaConvention sigma_convention = SigmaConvention::kPerAxis;
  LocError loc_error = LocError::kFresh;
  double sigma_loc_common_m = 0.0;  // the common-mode part, shared by every UAV (see above)

  // The standard deviation per axis of each error [m].
  double axis_sigma_loc_m() const { return axis_sigma(sigma_loc_m); }
  double axis_sigma_act_m() const { return axis_sigma(sigma_act_m); }
  double axis_sigma_loc_common_m() const { return axis_sigma(sigma_loc_common_m); }
  // Whether a position estimate is the truth (both localization parts 0).
  bool exact_localization() const { return sigma_loc_m == 0.0 && sigma_loc_common_m == 0.0; }
  // Both localization parts set to 0 (another source, or none, replaces the model).
  void clear_localization() {
    sigma_loc_m = 0.0;
    sigma_loc_common_m = 0.0;
  }

 private:
  double axis_sigma(double sigma_m) const;
};
// The values each sigma accepts (validate() and the [errors] keys). The bound: beyond ~1e154 m a
// drawn position overflows the channel's distances (1e300 ran with NaN channels).
namespace error_range {
inline constexpr common::Range sigma_loc_m = common::Range::closed(0.0, 1e3);
inline constexpr common::Range sigma_act_m = common::Range::closed(0.0, 1e3);
inline constexpr common::Range sigma_loc_common_m = common::Range::closed(0.0, 1e3);
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
  Swarm(const ChannelModel& model, const Eigen::Matrix3Xd& start_m, const ErrorModel& errors, std::uint64_t seed);

  int num_uavs() const { return static_cast<int>(q_m_.cols()); }
  const Eigen::Matrix3Xd& true_positions_m() const { return q_m_; }
  const SwarmChannel& channel() const { return channel_; }
  const ErrorModel& errors() const { return errors_; }

  // Where UAV m believes it is (see the error model above).
  Eigen::Vector3d estimate_position(int m);
  // What the run has taken from its seed so far: blocks of the normal stream drawn (actuation
  // and fresh localization errors) and calls of estimate_position. A run with none of either
  // comes out the same for any seed and any localization error.
  std::uint64_t normal_blocks_drawn() const { return normal_next_block_; }
  long long position_estimates() const { return position_estimates_; }
  // Commands UAV m to move by r_m; returns the true displacement. With update_channel false
  // the channel keeps UAV m's old row until sync_channel(m): BF's probe flights measure the
  // row at the probe point through UavObjective, and the others' Gram matrix stays fixed.
  // A non-finite r_m, or a move that would leave a non-finite position, is refused: the UAV
  // stays, the move returns zero and the first such move is kept in numerical_fault().
  Eigen::Vector3d move(int m, const Eigen::Vector3d& r_m, MotionKind kind, bool update_channel = true);
  const std::optional<SwarmFault>& numerical_fault() const { return fault_; }
  // UAV m's LoS channel row at its true position (noise-free; the model's).
  Eigen::VectorXcd measure_row(int m) const { return channel_.model().row(q_m_.col(m)); }
  // Brings UAV m's cached row up to date: its LoS row, or with active conditions a measurement.
  void sync_channel(int m);
  // sync_channel for every UAV, in UAV order: without conditions all rows and the Gram matrix
  // at once (SwarmChannel::set_positions), with conditions one measurement per UAV.
  void sync_channels();

  // Rician fading and CSI noise; the swarm keeps a copy. Active conditions (sized Nr x Nt)
  // re-measure every row at once: the master's first broadcast.
  void set_channel_conditions(const ChannelConditions& conditions);
  const ChannelConditions& channel_conditions() const { return conditions_; }
  // Before iteration i (run_placement calls it): when a new coherence block begins, the scatter
  // is redrawn and every UAV measures and broadcasts its row again. Nothing without fading.
  void begin_iteration(int iteration);
  // What UAV m measures at its true position now (a fresh draw of the estimation noise): its LoS
  // row without conditions, the same bits as ChannelModel::row.
  void measure_row_into(int m, Eigen::VectorXcd& x);
  // The channel at the true positions without estimation noise: the LoS channel, faded by the
  // current block's scatter when fading is on.
  Eigen::MatrixXcd true_channel() const;
  // ChannelConditions::noise_floor_objective (0 without conditions).
  double noise_floor_objective() const { return conditions_.noise_floor_objective(); }
  // Whether a stalled planner may escape at measured objective f: always without conditions,
  // else only above twice the noise floor (below it a lower measured f is mostly noise, and an
  // escape jump of up to half a lateral period would follow it).
  bool escape_allowed(double objective) const {
    return !conditions_.active() || objective > 2.0 * conditions_.noise_floor_objective();
  }

  const Eigen::VectorXd& placement_distance_m() const { return placement_dist_m_; }
  const Eigen::VectorXd& probe_distance_m() const { return probe_dist_m_; }
  // The same lengths as commanded (sum of |r|), before the actuation error.
  const Eigen::VectorXd& commanded_placement_distance_m() const { return commanded_placement_dist_m_; }
  const Eigen::VectorXd& commanded_probe_distance_m() const { return commanded_probe_dist_m_; }
  // Counts a probe flight out by r and back that has no actuation error (BF's
  // ProbeActuation::kKeptMoveOnly): 2 |r| true and commanded, the UAV ends where it was.
  void count_exact_probe(int m, const Eigen::Vector3d& r_m);

  // A different localization source (e.g. a filter's belief) replaces the Gaussian model.
  using PositionEstimator = std::function<Eigen::Vector3d(int m, const Eigen::Vector3d& true_q_m)>;
  void set_position_estimator(PositionEstimator estimator) { estimator_ = std::move(estimator); }

 private:
  // sigma times the next three numbers of the stream (zero, drawing nothing, if sigma is 0).
  Eigen::Vector3d gaussian(double sigma) {
    if (sigma == 0.0) return Eigen::Vector3d::Zero();
    if (normal_used_ == static_cast<int>(normal_buffer_.size())) refill_normals();
    const double* n = normal_buffer_.data() + normal_used_;
    normal_used_ += 3;
    return Eigen::Vector3d(n[0], n[1], n[2]) * sigma;
  }
  void refill_normals();

  Eigen::Matrix3Xd q_m_;
  SwarmChannel channel_;
  ErrorModel errors_;
  // The counter-based stream: the next kNormalBlocks blocks are buffered, a multiple of three
  // numbers, so that every draw of three lies within one refill.
  static constexpr int kNormalBlocks = 12;
  std::uint64_t normal_key_;
  std::uint64_t normal_next_block_ = 0;
  long long position_estimates_ = 0;
  int normal_used_ = kNormalBlocks * kernels::kNormalsPerBlock;
  std::array<double, kNormalBlocks * kernels::kNormalsPerBlock> normal_buffer_{};
  Eigen::VectorXd placement_dist_m_;
  Eigen::VectorXd probe_dist_m_;
  Eigen::VectorXd commanded_placement_dist_m_;
  Eigen::VectorXd commanded_probe_dist_m_;
  double axis_sigma_loc_m_ = 0.0;
  double axis_sigma_act_m_ = 0.0;
  Eigen::Matrix3Xd loc_bias_m_;  // LocError::kFixedPerUav: UAV m's fixed error (3 x Nr), else empty
  Eigen::Vector3d loc_common_m_ = Eigen::Vector3d::Zero();  // the common-mode offset (0 unless set)
  PositionEstimator estimator_;
  std::optional<SwarmFault> fault_;
  ChannelConditions conditions_;
};

}  // namespace losmimo::placement
