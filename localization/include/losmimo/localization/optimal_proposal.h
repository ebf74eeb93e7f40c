#pragma once
// The particle filters' proposal when a measurement is fused: the locally linearised optimal
// proposal (Doucet, Godsill and Andrieu, "On sequential Monte Carlo sampling methods for Bayesian
// filtering", Stat. Comput. 2000, sec. II-D), with exact importance weights.
//
// Why: with the motion model as the proposal (the "standard" proposal), each particle is moved
// blind and then weighted by the likelihood. When the measurement is much sharper than the
// motion noise (the BS beacon at its smallest noise: a 1 mm lateral 1-sigma at 1 km against
// centimetres of dead-reckoning noise per epoch), only a handful of the N particles land inside
// the likelihood, the weights collapse onto them, and the moment-matched covariance is a
// few-particle artefact orders of magnitude below the true error (NEES ~1e6). Sampling each
// particle from its own posterior given the measurement puts every particle where the
// likelihood is; the weights then vary only with how well each particle's prediction explains
// the measurement (the predictive likelihood, as wide as H Q H^T + R), so the cloud stays
// diverse at any measurement noise. Regularisation (more jitter) would inflate the covariance
// instead, and tempering would fuse less information than the measurement has.
//
// For one particle: predicted mean xbar, process noise x ~ N(xbar, Q) with W = Q^-1 (SPD), and
// the measurement as whitened residuals r(x) = R^-1/2 (z - h(x)) (angles wrapped) with whitened
// Jacobian A(x) = R^-1/2 dh/dx, so that log p(z | x) = -1/2 |r(x)|^2 + const:
//   Lambda(m) = W + A(m)^T A(m),  m <- xbar + Lambda^-1 A(m)^T (r(m) + A(m) (m - xbar))
// iterated from m = xbar (Gauss-Newton on the particle's MAP; it stops when the step is below
// 1e-9 of the state's scale or after kMaxProposalIterations), then
//   x = m + L^-T eps,  Lambda = L L^T (at the last linearisation point),  eps ~ N(0, I)
//   log w += log p(z | x) + log N(x; xbar, Q) - log N(x; m, Lambda^-1)
//          = -1/2 |r(x)|^2 - 1/2 (x - xbar)^T W (x - xbar) + 1/2 |eps|^2 - sum_i log L_ii  (+ const)
// The constant (the same for every particle when det W is) is dropped: weights are normalised.
// Nothing is approximated in the weights: the linearisation only shapes the proposal, so the
// filter stays correct (if less efficient) where h is strongly non-linear.
//
// Speed (OptimalProposal): a Jacobian and a factorisation per particle and iteration cost more
// than MRPT's whole standard-proposal step. So the epoch linearises once, at the predicted mean
// xhat with its W_hat: Lambda_hat = W_hat + A(xhat)^T A(xhat) = L_hat L_hat^T, and each particle
// runs chord iterations (simplified Newton with that fixed matrix) on its own residuals,
//   m <- m + Lambda_hat^-1 (A_hat^T r(m) - W (m - xbar)),
// from m = xbar until the step is below kChordTolerance sigmas (at most max_chord_iterations,
// kMaxChordIterations unless the constructor is given another),
// then x = m + L_hat^-T eps with the weight above (sum log L_hat_ii in place of sum log L_ii).
// A particle whose chord iterations do not settle (far from xhat where h bends) gets the full
// per-particle Gauss-Newton instead. Either way the weight is exact for the proposal used.
//
// Measurement concept M (N = state size, Vec/Mat its vector/matrix):
//   double accumulate(const Vec& x, Mat* AtA, Vec* Atr): |r(x)|^2; when AtA/Atr are not null,
//     adds A(x)^T A(x) and A(x)^T r(x);
//   void rows(const Vec& x, std::vector<Vec>& a): the rows of A(x);
//   double project(const Vec& x, const std::vector<Vec>& a, Vec& Atr): |r(x)|^2, and
//     Atr = sum_j a_j r_j(x) (rows given, e.g. A(xhat)'s).

#include <cmath>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace losmimo::localization {

inline constexpr int kMaxProposalIterations = 5;
inline constexpr int kMaxChordIterations = 4;
inline constexpr double kChordTolerance = 1e-3;  // sigmas of the proposal

// Draws x for one particle as above; returns the log-weight increment. eps: N(0, I) draws.
template <int N, class Measurement>
double sample_optimal_proposal(const Eigen::Matrix<double, N, 1>& x_bar, const Eigen::Matrix<double, N, N>& W,
                               const Measurement& measurement, const Eigen::Matrix<double, N, 1>& eps,
                               Eigen::Matrix<double, N, 1>& x_out) {
  using Vec = Eigen::Matrix<double, N, 1>;
  using Mat = Eigen::Matrix<double, N, N>;
  Vec m = x_bar;
  Eigen::LLT<Mat> llt;
  for (int it = 0; it < kMaxProposalIterations; ++it) {
    Mat info = W;
    Vec rhs = Vec::Zero();
    measurement.accumulate(m, &info, &rhs);  // info = W + A^T A, rhs = A^T r(m)
    // A^T (r + A (m - xbar)) = rhs + (info - W)(m - xbar)
    rhs.noalias() += (info - W) * (m - x_bar);
    llt.compute(info);
    const Vec next = x_bar + llt.solve(rhs);
    const double step = (next - m).norm();
    m = next;
    if (step <= 1e-9 * (1.0 + m.norm())) break;
  }
  // Lambda of the last linearisation point (any SPD Lambda gives a valid proposal; the weight
  // below uses the same one).
  const Mat L = llt.matrixL();
  x_out = m + L.transpose().template triangularView<Eigen::Upper>().solve(eps);
  const Vec dx = x_out - x_bar;
  double log_det_L = 0.0;
  for (int i = 0; i < N; ++i) log_det_L += std::log(L(i, i));
  const double r2 = measurement.accumulate(x_out, nullptr, nullptr);
  return -0.5 * r2 - 0.5 * dx.dot(W * dx) + 0.5 * eps.squaredNorm() - log_det_L;
}

// The shared-linearisation proposal of one epoch (header).
template <int N, class Measurement>
class OptimalProposal {
 public:
  using Vec = Eigen::Matrix<double, N, 1>;
  using Mat = Eigen::Matrix<double, N, N>;

  OptimalProposal(const Measurement& measurement, const Vec& x_hat, const Mat& W_hat,
                  int max_chord_iterations = kMaxChordIterations)
      : measurement_(measurement), max_chord_iterations_(max_chord_iterations) {
    measurement_.rows(x_hat, rows_);
    Mat info = W_hat;
    for (const Vec& a : rows_) info.noalias() += a * a.transpose();
    const Eigen::LLT<Mat> llt(info);
    // Explicit inverses (N <= 4): one matrix-vector product per particle instead of two
    // triangular solves, which dominated the step.
    info_inv_ = llt.solve(Mat::Identity());
    L_T_inv_ = Mat(llt.matrixL().transpose()).template triangularView<Eigen::Upper>().solve(Mat::Identity());
    log_det_L_ = 0.0;
    for (int i = 0; i < N; ++i) log_det_L_ += std::log(llt.matrixL()(i, i));
  }

  // Draws x for one particle (xbar, W); returns the log-weight increment. eps: N(0, I) draws.
  double sample(const Vec& x_bar, const Mat& W, const Vec& eps, Vec& x_out) const {
    Vec m = x_bar;
    bool settled = false;
    for (int it = 0; it < max_chord_iterations_ && !settled; ++it) {
      Vec grad;
      measurement_.project(m, rows_, grad);
      grad.noalias() -= W * (m - x_bar);
      const Vec step = info_inv_ * grad;
      m += step;
      settled = step.dot(grad) <= kChordTolerance * kChordTolerance;  // |step|^2 in Lambda_hat's metric
    }
    if (!settled) return sample_optimal_proposal<N>(x_bar, W, measurement_, eps, x_out);
    x_out = m + L_T_inv_ * eps;
    const Vec dx = x_out - x_bar;
    Vec unused;
    const double r2 = measurement_.project(x_out, {}, unused);
    return -0.5 * r2 - 0.5 * dx.dot(W * dx) + 0.5 * eps.squaredNorm() - log_det_L_;
  }

 private:
  const Measurement& measurement_;
  int max_chord_iterations_;
  std::vector<Vec> rows_;
  Mat info_inv_;  // Lambda_hat^-1
  Mat L_T_inv_;   // L_hat^-T
  double log_det_L_ = 0.0;
};

}  // namespace losmimo::localization
