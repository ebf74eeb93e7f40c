// The gradient checker itself: a hand-written CSI Jacobian passes when right and is caught
// when wrong (kept in its own TU: a CostFunction subclass next to the other tests' virtual
// calls trips GCC's speculative devirtualisation warnings).
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <random>

#include "fusion/gradient_probe.h"
#include "losmimo/fusion/cost_functors.h"
#include "losmimo/fusion/csi.h"

namespace losmimo::fusion {
namespace {

using test_support::probe;

// The CSI residual with a hand-written Jacobian: dr_k/dq = kappa (u_k - u_q)^T / sigma,
// dr_k/dpsi = -1 / sigma (u_k = (q - p_k)/d_k, u_q = q/|q|). bug = true flips the sign of the
// position Jacobian, the kind of mistake the checker exists to catch.
class AnalyticCsiCost final : public ceres::CostFunction {
 public:
  AnalyticCsiCost(const Eigen::VectorXd& phase, const placement::ChannelModel& model, double sigma, bool bug)
      : functor_(phase, model.antennas_m(), model.wavenumber_rad_per_m(), sigma),
        antennas_m_(model.antennas_m()),
        kappa_(model.wavenumber_rad_per_m()),
        sigma_(sigma),
        bug_(bug) {
    set_num_residuals(static_cast<int>(phase.size()));
    mutable_parameter_block_sizes()->assign({3, 1});
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    functor_(parameters[0], parameters[1], residuals);
    if (jacobians == nullptr) return true;
    const Eigen::Map<const Eigen::Vector3d> q(parameters[0]);
    const Eigen::Vector3d u_q = q.normalized();
    for (Eigen::Index k = 0; k < antennas_m_.cols(); ++k) {
      const Eigen::Vector3d u_k = (q - antennas_m_.col(k)).normalized();
      const Eigen::Vector3d J = (bug_ ? -1.0 : 1.0) * kappa_ * (u_k - u_q) / sigma_;
      if (jacobians[0] != nullptr) {
        for (int i = 0; i < 3; ++i) jacobians[0][3 * k + i] = J(i);
      }
      if (jacobians[1] != nullptr) jacobians[1][k] = -1.0 / sigma_;
    }
    return true;
  }

 private:
  CsiPhaseCost functor_;
  Eigen::Matrix3Xd antennas_m_;
  double kappa_;
  double sigma_;
  bool bug_;
};

TEST(GradientCheck, HandWrittenCsiJacobian_PassesWhenRightAndIsCaughtWhenWrong) {
  constexpr double kNoiseVariance = 0.1;
  const placement::ChannelModel model(placement::Scenario{});
  std::mt19937_64 rng(26);
  const Eigen::Vector3d q_true(1012.0, -7.0, 19.0);
  const CsiMeasurement c = simulate_csi(model, q_true, kNoiseVariance, rng);
  Eigen::VectorXd phase(c.y.size());
  for (Eigen::Index k = 0; k < c.y.size(); ++k) phase(k) = std::arg(c.y(k));
  const double sigma = csi_phase_sigma_rad(kNoiseVariance);
  Eigen::Vector3d q = q_true + Eigen::Vector3d(0.3, 0.2, -0.2);
  double psi = csi_reference_phase_rad(model, c, q);
  const AnalyticCsiCost right(phase, model, sigma, false);
  const AnalyticCsiCost wrong(phase, model, sigma, true);
  std::string log;
  EXPECT_TRUE(probe(right, {q.data(), &psi}, &log)) << log;
  EXPECT_FALSE(probe(wrong, {q.data(), &psi}));
}

}  // namespace
}  // namespace losmimo::fusion
