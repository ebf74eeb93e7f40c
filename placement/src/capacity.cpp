#include "losmimo/placement/capacity.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "losmimo/placement/channel.h"
#include "belief_sweep.h"

namespace losmimo::placement {

std::string to_string(CapPower power) { return power == CapPower::kWaterfill ? "waterfill" : "equal"; }

CapPower cap_power_from_string(const std::string& name) {
  if (name == "equal") return CapPower::kEqual;
  if (name == "waterfill") return CapPower::kWaterfill;
  throw std::invalid_argument("unknown power allocation '" + name + "' (known: equal, waterfill)");
}

Eigen::VectorXd waterfill_powers(const Eigen::VectorXd& gains, double total_power) {
  const Eigen::Index n = gains.size();
  Eigen::VectorXd p = Eigen::VectorXd::Zero(n);
  std::vector<Eigen::Index> order;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (gains(i) > 0.0) order.push_back(i);
  }
  std::sort(order.begin(), order.end(), [&](Eigen::Index l, Eigen::Index r) { return gains(l) > gains(r); });
  // The k strongest modes are on when mu = (P + sum_{i<k} 1/g_i) / k exceeds 1 / g_k.
  double inverse_sum = 0.0;
  double mu = 0.0;
  std::size_t on = 0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const double inv = 1.0 / gains(order[k]);
    const double mu_k = (total_power + inverse_sum + inv) / static_cast<double>(k + 1);
    if (mu_k <= inv) break;
    inverse_sum += inv;
    mu = mu_k;
    on = k + 1;
  }
  for (std::size_t k = 0; k < on; ++k) p(order[k]) = mu - 1.0 / gains(order[k]);
  return p;
}

namespace {

// H H^H = E diag(lambda) E^H and the powers p of each mode (lambda ascending, clamped at 0).
struct Modes {
  Eigen::VectorXd lambda;
  Eigen::MatrixXcd E;
  Eigen::VectorXd p;
};

Modes modes_of(const Eigen::MatrixXcd& H, double a, CapPower power, bool vectors) {
  Modes out;
  const Eigen::MatrixXcd K = H * H.adjoint();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXcd> eig(K, vectors ? Eigen::ComputeEigenvectors : Eigen::EigenvaluesOnly);
  out.lambda = eig.eigenvalues().cwiseMax(0.0);
  if (vectors) out.E = eig.eigenvectors();
  const Eigen::Index nr = H.rows();
  if (power == CapPower::kEqual) {
    out.p = Eigen::VectorXd::Ones(nr);
  } else {
    // The min(Nr, Nt) largest modes (the rest are H's null space), total power Nt.
    const Eigen::Index r = std::min(H.rows(), H.cols());
    Eigen::VectorXd gains = Eigen::VectorXd::Zero(nr);
    gains.tail(r) = a * out.lambda.tail(r);
    out.p = waterfill_powers(gains, static_cast<double>(H.cols()));
  }
  return out;
}

double capacity_of(const Modes& m, double a) {
  double c = 0.0;
  for (Eigen::Index i = 0; i < m.lambda.size(); ++i) c += std::log1p(a * m.p(i) * m.lambda(i));
  return c / std::log(2.0);
}

}  // namespace

double capacity_bps_hz(const Eigen::MatrixXcd& H, double noise_variance, CapPower power) {
  const double a = 1.0 / noise_variance;
  return capacity_of(modes_of(H, a, power, false), a);
}

double orthogonal_capacity_bps_hz(int num_uavs, int num_bs_antennas, double noise_variance, CapPower power) {
  const double nr = num_uavs, nt = num_bs_antennas;
  const double r = std::min(nr, nt);
  const double a = 1.0 / noise_variance;
  const double lambda = nr * nt / r;                              // each of the r modes
  const double p = power == CapPower::kWaterfill ? nt / r : 1.0;  // per mode
  return r * std::log2(1.0 + a * p * lambda);
}

UavCapacity::UavCapacity(const ChannelModel& model, const Eigen::MatrixXcd& H, int m, double noise_variance,
                         CapPower power)
    : model_(&model), H_(H), m_(m), a_(1.0 / noise_variance), power_(power) {
  if (m < 0 || m >= H.rows()) throw std::out_of_range("UavCapacity: no UAV " + std::to_string(m));
}

double UavCapacity::capacity_at(const Eigen::Vector3d& q_m) const {
  H_.row(m_) = model_->row(q_m).transpose();
  return capacity_of(modes_of(H_, a_, power_, false), a_);
}

Eigen::Vector3d UavCapacity::gradient_at(const Eigen::Vector3d& q_m, double* capacity) const {
  const Eigen::VectorXcd h = model_->row(q_m);
  H_.row(m_) = h.transpose();
  const Modes modes = modes_of(H_, a_, power_, true);
  if (capacity) *capacity = capacity_of(modes, a_);
  // w = H^H E diag(p / (1 + a p lambda)) E^H e_m
  const Eigen::ArrayXd weight = modes.p.array() / (1.0 + a_ * modes.p.array() * modes.lambda.array());
  const Eigen::VectorXcd c = (weight * modes.E.row(m_).adjoint().array()).matrix();
  const Eigen::VectorXcd w = H_.adjoint() * (modes.E * c);
  Eigen::VectorXcd s;
  Eigen::Matrix3Xd U;
  model_->row_derivative_terms(q_m, s, U);
  const Eigen::VectorXd re = (h.array() * s.array() * w.array()).real();
  return (2.0 * a_ / std::log(2.0)) * (U * re);
}

void validate(const CapOptions& o) {
  namespace r = cap_range;
  common::require_field_in(r::step, o.step, "cap", "step");
  common::require_field_in(r::decay, o.decay, "cap", "decay");
  common::require_field_in(r::max_move_m, o.max_move_m, "cap", "max_move_m");
  common::require_field_in(r::max_halvings, o.max_halvings, "cap", "max_halvings");
}

CapacityPlanner::CapacityPlanner(const Scenario& scenario, const CapOptions& options)
    : options_(options), noise_variance_(scenario.noise_variance()) {
  validate(options_);
}

void CapacityPlanner::start(Swarm& swarm) {
  believed_m_.resize(3, 0);
  capacity_bps_hz_ = placement::capacity_bps_hz(swarm.channel().H(), noise_variance_, options_.power);
}

std::optional<Eigen::Matrix3Xd> CapacityPlanner::believed_positions() const {
  if (believed_m_.cols() == 0) return std::nullopt;
  return believed_m_;
}

Eigen::Vector3d CapacityPlanner::plan_step(const Swarm& swarm, int m, const Eigen::Vector3d& q_hat_m, double b) const {
  const UavCapacity view(swarm.channel().model(), swarm.channel().H(), m, noise_variance_, options_.power);
  double c0 = 0.0;
  Eigen::Vector3d r = b * view.gradient_at(q_hat_m, &c0);
  if (!r.allFinite()) return Eigen::Vector3d::Zero();
  const double norm = r.norm();
  if (norm > options_.max_move_m) r *= options_.max_move_m / norm;
  if (options_.backtracking) {
    int h = 0;
    while (view.capacity_at(q_hat_m + r) < c0) {
      if (h++ == options_.max_halvings) return Eigen::Vector3d::Zero();
      r *= 0.5;
    }
  }
  return r;
}

void CapacityPlanner::iterate(Swarm& swarm, int iteration) {
  const double b = detail::decayed_step(options_.step, options_.decay, iteration);
  detail::estimate_then_move_each(
      swarm, believed_m_, [&](int m, const Eigen::Vector3d& q_hat_m) { return plan_step(swarm, m, q_hat_m, b); });
  capacity_bps_hz_ = placement::capacity_bps_hz(swarm.channel().H(), noise_variance_, options_.power);
}

}  // namespace losmimo::placement
