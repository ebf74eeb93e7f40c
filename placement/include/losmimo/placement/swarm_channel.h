#pragma once
// The swarm's channel with a cached Gram matrix, so that one UAV's move costs O(Nt^2).
//
// Moving UAV m changes only row m of H (written x, length Nt). With A = G - conj(x_old) x_old^T
// the Gram matrix of the other UAVs ("leave-one-out"), the objective with row x is
//   f(x) = F_A + 2 Re(x^H conj(A) x) - 2 sum_l A_ll |x_l|^2 + (sum_l |x_l|^2)^2 - sum_l |x_l|^4
// with F_A = sum_{l != k} |A_lk|^2: one Hermitian form, O(Nt^2), per probe. Its gradient with
// respect to the UAV's position q (B = A + conj(x) x^T, the Gram matrix with the new row) is
//   grad f = 4 sum_l u_l Re(conj(s_l) Q_l),   Q_l = conj(x_l) sum_{k != l} conj(B_lk) x_k
// with s_l, u_l from ChannelModel::row_derivative_terms: also O(Nt^2). In the far field
// (s_l = -j 2 pi / lambda) this is the paper's formula, summed over ordered pairs.

#include <Eigen/Core>

#include "losmimo/placement/channel.h"

namespace losmimo::placement {

class SwarmChannel {
 public:
  SwarmChannel(const ChannelModel& model, const Eigen::Matrix3Xd& q_m);

  int num_uavs() const { return static_cast<int>(H_.rows()); }
  const Eigen::MatrixXcd& H() const { return H_; }
  const Eigen::MatrixXcd& gram() const { return G_; }
  const ChannelModel& model() const { return *model_; }
  double objective() const;

  // Replaces UAV m's row by its channel at q_m (O(Nt^2) update of the Gram matrix).
  void set_position(int m, const Eigen::Vector3d& q_m);
  void set_row(int m, const Eigen::VectorXcd& x);
  // Recomputes the Gram matrix from H (clears accumulated rounding).
  void refresh();

 private:
  const ChannelModel* model_;
  Eigen::MatrixXcd H_;
  Eigen::MatrixXcd G_;
  int updates_since_refresh_ = 0;
};

// What UAV m sees while the others stay put: the leave-one-out Gram matrix A, and f and
// grad f as functions of its own row or position. Built in O(Nt^2).
class UavObjective {
 public:
  UavObjective(const SwarmChannel& swarm, int m);

  double objective_of_row(const Eigen::VectorXcd& x) const;
  double objective_at(const Eigen::Vector3d& q_m) const;
  // With `objective` set, also f at q_m (= objective_at(q_m), bit for bit) from the same row.
  Eigen::Vector3d gradient_at(const Eigen::Vector3d& q_m, double* objective = nullptr) const;

 private:
  // conj(A) x in real arithmetic: (Re + j Im)(conj(A)) x, split into real matrices so that
  // the kernel vectorises (Eigen's complex matrix-vector product does not, at Nt = 16).
  void apply_conj_A(const Eigen::VectorXcd& x, Eigen::VectorXcd& Ax) const;
  // f from the row, its powers p = |x|^2 and conj(A) x.
  double objective_given(const Eigen::VectorXcd& x, const Eigen::ArrayXd& p, const Eigen::VectorXcd& Ax) const;

  const ChannelModel* model_;
  Eigen::MatrixXd A_conj_re_;  // Re(conj(A)) = Re(A)
  Eigen::MatrixXd A_conj_im_;  // Im(conj(A)) = -Im(A)
  Eigen::VectorXd A_diag_;
  double F_A_;
};

}  // namespace losmimo::placement
