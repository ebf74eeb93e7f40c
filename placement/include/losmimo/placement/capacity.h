#pragma once
// Capacity-seeking placement (Hanna, Krijestorac, Cabric, "UAV Swarm Position Optimization for
// High Capacity MIMO Backhaul", IEEE JSAC 2021): each UAV in turn climbs the MIMO capacity.
//
// Model, in the normalised units of channel.h (H is Nr x Nt, rows are UAVs, the far-field
// entries unit-modulus) and the power convention of metrics.h's sum rates: every BS antenna
// sends one unit of power (total Nt) and the noise variance is psi^2 = 1 / SNR
// (Scenario::noise_variance, SNR per BS-antenna-to-UAV link). With a = 1 / psi^2 and a transmit
// covariance Q (tr Q = Nt):
//   C(H) = log2 det(I_Nr + a H Q H^H)                                            [bit/s/Hz]
//        = sum_i log2(1 + a p_i lambda_i),   H H^H = E diag(lambda) E^H  (eigen-decomposition)
// - equal power (CapPower::kEqual): Q = I, p_i = 1. This is the brief's
//   log2 det(I + (SNR / Nt) H H^H) with the total power Nt instead of 1, i.e. the project's
//   per-antenna SNR; at orthogonality it equals metrics.h's ZF sum rate.
// - water-filling (kWaterfill): Q = V diag(p) V^H over the right singular vectors V of H,
//   p_i = max(0, mu - 1 / (a lambda_i)) on the min(Nr, Nt) largest modes, sum_i p_i = Nt.
// Bound (orthogonal_capacity_bps_hz): in the far field tr(H H^H) = Nr Nt whatever the
// positions, so by Jensen equal power gives at most r log2(1 + a Nr Nt / r), r = min(Nr, Nt):
//   C_max = min(Nr, Nt) log2(1 + SNR max(Nr, Nt)),
// reached exactly when the smaller Gram matrix is max(Nr, Nt) I (ICN 1). Water-filling gives
// there r log2(1 + SNR Nt Nr Nt / r^2) (= C_max when Nr >= Nt; more when Nr < Nt: the power
// goes to the Nr modes only). For Nr = Nt = 16 at 10 dB: 16 log2(161) = 117.3 bit/s/Hz.
//
// Gradient with respect to UAV m's position q_m. Only row m of H, h_m (h_mn, n = 1..Nt),
// depends on q_m. With A = I + a H Q H^H (Hermitian) and dH = e_m dh_m^T,
//   dC = (1 / ln 2) tr(A^-1 dA),  dA = a (dH Q H^H + H Q dH^H)
//      = (2 a / ln 2) Re tr(A^-1 dH Q H^H) = (2 a / ln 2) Re(dh_m^T w),
//   w  = Q H^H A^-1 e_m = H^H E diag(p_i / (1 + a p_i lambda_i)) E^H e_m   (length Nt),
// the last form because Q H^H = H^H E diag(p) E^H and A^-1 = E diag(1 / (1 + a p lambda)) E^H.
// The entry derivative is channel.h's: d h_mn / d q_m = h_mn s_n u_n, u_n = (q_m - p_n) / d_mn,
// s_n = -j 2 pi / lambda (far field) or -j 2 pi / lambda - 1 / d_mn (exact gain 1 / d_mn), so
//   grad_{q_m} C = (2 a / ln 2) sum_n u_n Re(h_mn s_n w_n).
// Water-filling: C(H) = max_Q log2 det(I + a H Q H^H) over tr Q = Nt, Q >= 0, and by the
// envelope theorem (Danskin) its gradient is the partial derivative at the optimal Q held
// fixed: the formula above with the water-filling powers p_i (and modes) of the current H.
//
// Distributed: UAV m knows its believed position q_hat_m (Swarm::estimate_position, as GD) and
// the measured channel (the swarm channel's rows: with Rician fading or CSI noise these are
// measurements). It models its own row at q_hat_m (ChannelModel::row) and keeps the others'
// measured rows (UavCapacity). Cost: one Nr x Nr Hermitian eigen-decomposition per evaluation
// (O(Nr^2 Nt + Nr^3)), so one iteration is O(Nr^4): meant for swarms of tens of UAVs.
//
// Planner iteration i: every UAV estimates its position; then each UAV m in turn moves by
//   r = b_i grad C(q_hat_m),  b_i = step * decay^(i-1)    [step in m^2 per bit/s/Hz],
// capped at max_move_m; with backtracking on, r is halved until C under the UAV's own model
// does not decrease (at most max_halvings times); if it still decreases the UAV stays.
// Stop: as every planner, the master's ICN target (run.h); capacity_bps_hz() reports the
// capacity of the measured channel after the last iteration.

#include <Eigen/Core>
#include <string>

#include "losmimo/placement/common/range.h"
#include "losmimo/placement/run.h"

namespace losmimo::placement {

enum class CapPower { kEqual, kWaterfill };
std::string to_string(CapPower power);                    // "equal", "waterfill"
CapPower cap_power_from_string(const std::string& name);  // std::invalid_argument for others

// Water-filling powers for mode gains g_i >= 0 (SNR per unit power): p_i = max(0, mu - 1 / g_i),
// sum p_i = total_power; zero gains get zero power.
Eigen::VectorXd waterfill_powers(const Eigen::VectorXd& gains, double total_power);

// C of H (normalised units) at noise variance psi^2 (bit/s/Hz), as above.
double capacity_bps_hz(const Eigen::MatrixXcd& H, double noise_variance, CapPower power);
// The bound above: C of Nr x Nt unit-modulus rows with the smaller Gram matrix max(Nr, Nt) I.
double orthogonal_capacity_bps_hz(int num_uavs, int num_bs_antennas, double noise_variance, CapPower power);

// UAV m's view of C while the others stay put: the channel H (the others' measured rows), its
// own row replaced by the model's at a candidate position. Keeps a copy of H.
class UavCapacity {
 public:
  UavCapacity(const ChannelModel& model, const Eigen::MatrixXcd& H, int m, double noise_variance, CapPower power);
  double capacity_at(const Eigen::Vector3d& q_m) const;
  // grad_{q_m} C [bit/s/Hz per m]; with `capacity` set, also C at q_m.
  Eigen::Vector3d gradient_at(const Eigen::Vector3d& q_m, double* capacity = nullptr) const;

 private:
  const ChannelModel* model_;
  mutable Eigen::MatrixXcd H_;
  int m_;
  double a_;  // 1 / psi^2
  CapPower power_;
};

struct CapOptions {
  double step = 1.0;  // m^2 per bit/s/Hz: the move per unit gradient
  double decay = 0.999;
  double max_move_m = 0.5;  // a per-iteration speed limit
  bool backtracking = true;
  int max_halvings = 6;
  CapPower power = CapPower::kEqual;
};
// The values each option accepts (validate() and the [cap] keys).
namespace cap_range {
inline constexpr common::Range step = common::Range::above_up_to(0.0, 1e6);
inline constexpr common::Range decay = common::Range::above_up_to(0.0, 1.0);
inline constexpr common::Range max_move_m = common::Range::above_up_to(0.0, 1e6);
inline constexpr common::Range max_halvings = common::Range::closed(0, 60);
}  // namespace cap_range
void validate(const CapOptions& options);

class CapacityPlanner : public Planner {
 public:
  CapacityPlanner(const Scenario& scenario, const CapOptions& options);
  std::string name() const override { return "cap"; }
  void start(Swarm& swarm) override;
  void iterate(Swarm& swarm, int iteration) override;
  std::optional<Eigen::Matrix3Xd> believed_positions() const override;

  // The move UAV m would command from believed position q_hat_m with base step b (for tests).
  Eigen::Vector3d plan_step(const Swarm& swarm, int m, const Eigen::Vector3d& q_hat_m, double b) const;
  // C of the measured channel (the swarm channel's rows) after start() / the last iterate().
  double capacity_bps_hz() const { return capacity_bps_hz_; }

 private:
  CapOptions options_;
  double noise_variance_;
  double capacity_bps_hz_ = 0.0;
  Eigen::Matrix3Xd believed_m_;  // empty before the first iteration
};

}  // namespace losmimo::placement
