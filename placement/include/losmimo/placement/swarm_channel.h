#pragma once
// The swarm's channel with a cached Gram matrix, so that one UAV's move costs O(Nt^2).
//
// Moving UAV m changes only row m of H (written x, length Nt). With A = G - conj(x_old) x_old^T
// the Gram matrix of the other UAVs ("leave-one-out"), the objective with row x is
//   f(x) = F_A + 2 sum_{l != k} Re(conj(x_l) conj(A_lk) x_k) + (sum_l |x_l|^2)^2 - sum_l |x_l|^4
// with F_A = sum_{l != k} |A_lk|^2: one Hermitian form, O(Nt^2), per probe. Its gradient with
// respect to the UAV's position q (B = A + conj(x) x^T, the Gram matrix with the new row) is
//   grad f = 4 sum_l u_l Re(conj(s_l) Q_l),   Q_l = conj(x_l) sum_{k != l} conj(B_lk) x_k
// with s_l, u_l from ChannelModel::row_derivative_terms: also O(Nt^2). In the far field
// (s_l = -j 2 pi / lambda) this is the paper's formula, summed over ordered pairs.
// The arithmetic is in kernels.h (vectorised, the same bits on every instruction set).
//
// Fewer UAVs than antennas (Nr < Nt, metrics.h): the streams are the UAVs, and the swarm keeps
// the UAVs' Gram matrix K = H H^H (Nr x Nr) instead, with f = sum_{j != l} |K_jl|^2 and
// UAV m's view in O(Nr Nt) per probe (swarm_channel_uavs.cpp, plain scalar code).

#include <Eigen/Core>
#include <complex>
#include <cstdint>
#include <vector>

#include "losmimo/placement/channel.h"

namespace losmimo::placement {

class SwarmChannel {
 public:
  SwarmChannel(const ChannelModel& model, const Eigen::Matrix3Xd& q_m);

  // Which Gram matrix is kept: the BS antennas' when Nr >= Nt (the paper's), else the UAVs'.
  enum class GramSide { kBsAntennas, kUavs };
  GramSide gram_side() const { return side_; }

  int num_uavs() const { return static_cast<int>(H_.rows()); }
  const Eigen::MatrixXcd& H() const { return H_; }
  // G = H^H H (Nt x Nt), exactly Hermitian. Built from the kernels' planes on first use after
  // a change (O(Nt^2)); the planners use gram_planes(). On the UAV side: K = H H^H (Nr x Nr).
  const Eigen::MatrixXcd& gram() const;
  const ChannelModel& model() const { return *model_; }
  // f = sum_{l != k} |G_lk|^2 (of K on the UAV side).
  double objective() const;

  // Replaces UAV m's row by its channel at q_m (O(Nt^2) update of the Gram matrix).
  void set_position(int m, const Eigen::Vector3d& q_m);
  void set_row(int m, const Eigen::VectorXcd& x);
  // Every UAV's row at once, at the columns of q_m (3 x Nr), and G rebuilt from the rows
  // (kernels gram_of_rows: O(Nr Nt^2), no rank updates): for moves of the whole swarm that
  // nothing measures in between (the URA baseline). std::invalid_argument on a wrong size.
  void set_positions(const Eigen::Matrix3Xd& q_m);
  // Recomputes the Gram matrix from H (clears accumulated rounding).
  void refresh();

  // The kernels' view (kernels.h): G in split planes (BS-antenna side only: std::logic_error on
  // the UAV side), and UAV m's row in split planes (ld long).
  kernels::GramPlanes gram_planes() const;
  const double* row_re(int m) const { return row_re_.data() + static_cast<std::ptrdiff_t>(m) * ld_; }
  const double* row_im(int m) const { return row_im_.data() + static_cast<std::ptrdiff_t>(m) * ld_; }
  // True if every entry of G is finite.
  bool gram_is_finite() const;
  // Changes with every set_position(s), set_row and refresh: a UavObjective checks it is current.
  std::uint64_t version() const { return version_; }

 private:
  void replace_row(int m, const double* re, const double* im);
  // The UAV side (swarm_channel_uavs.cpp).
  void rebuild_uav_gram();
  void update_uav_gram(int m);
  double uav_gram_objective() const;

  const ChannelModel* model_;
  GramSide side_;
  int ld_;
  Eigen::MatrixXcd H_;
  std::vector<double> row_re_, row_im_;    // H's rows, ld apart (pads 0)
  std::vector<double> gram_re_, gram_im_;  // G, ld x Nt, column-major (pad rows 0)
  mutable Eigen::MatrixXcd gram_;          // gram()'s copy
  mutable bool gram_stale_ = true;
  int updates_since_refresh_ = 0;
  std::uint64_t version_ = 0;
  // objective() of version objective_version_: a planner's stall test and the run's record of
  // the same iteration ask for it in turn.
  mutable std::uint64_t objective_version_ = ~std::uint64_t{0};
  mutable double objective_ = 0.0;
  // gram_is_finite() likewise (the run's health check and the ICN check ask in turn).
  mutable std::uint64_t finite_version_ = ~std::uint64_t{0};
  mutable bool gram_finite_ = true;
  Eigen::MatrixXcd uav_gram_;  // K on the UAV side (exactly Hermitian)
};

// What UAV m sees while the others stay put: the leave-one-out Gram matrix A, and f and
// grad f as functions of its own row or position (on the UAV side: the others' rows, see above). Built in O(1): it
// reads the swarm's channel, which must not change while the view is used (std::logic_error if it has: build a new view
// after any move).
class UavObjective {
 public:
  // What the values include: the whole f (kTotal), or f - F_A (kWithoutOthers): F_A, the
  // others' own energy, is a constant of UAV m's view, so the difference ranks UAV m's
  // positions alike (to rounding) and saves an O(Nt^2) pass (GD's step and line search).
  // objectives_at always gives the whole f (std::logic_error on a kWithoutOthers view).
  enum class Energy { kTotal, kWithoutOthers };
  UavObjective(const SwarmChannel& swarm, int m, Energy energy = Energy::kTotal);

  double objective_of_row(const Eigen::VectorXcd& x) const;
  double objective_at(const Eigen::Vector3d& q_m) const;
  // With `objective` set, also f at q_m (= objective_at(q_m), bit for bit) from the same row.
  Eigen::Vector3d gradient_at(const Eigen::Vector3d& q_m, double* objective = nullptr) const;

  // f at the columns of q_m, after UAV m's current row if with_current_row (its "stay" value,
  // f[0]), kernels::kLanes candidates per pass (kernels::objectives_lanes: one small complex
  // matrix product); f has with_current_row + q_m.cols() entries. Values agree with
  // objective_at to rounding, not to the bit: compare candidates of one call (or of calls of
  // this function) with each other.
  void objectives_at(const Eigen::Ref<const Eigen::Matrix3Xd>& q_m, bool with_current_row, double* f) const;

  int uav() const { return m_; }

 private:
  void check_current() const;
  double leave_one_out_energy() const;  // F_A (F_others on the UAV side), computed on first use
  bool uav_side() const { return swarm_->gram_side() == SwarmChannel::GramSide::kUavs; }
  // The UAV side (swarm_channel_uavs.cpp): F_others, f of a row in split planes (and the c_j),
  // f at a position, and the gradient (returns f).
  double uav_side_others_energy() const;
  double uav_side_objective(const double* xr, const double* xi, std::vector<std::complex<double>>* c) const;
  double uav_side_objective_at(const Eigen::Vector3d& q_m) const;
  double uav_side_gradient(const Eigen::Vector3d& q_m, double* grad) const;

  const SwarmChannel* swarm_;
  int m_;
  std::uint64_t version_;
  Energy energy_;
  mutable double F_A_ = 0.0;
  mutable bool have_F_A_ = false;
};

}  // namespace losmimo::placement
