// The particle filter of landmark_filter.h through mrpt::bayes::CParticleFilter: particles are
// 6-D poses; a frame with readings draws every particle from the linearised optimal proposal
// (optimal_proposal.h) of all its associated readings, a frame without from the motion model.
#include <mrpt/bayes/CParticleFilter.h>
#include <mrpt/bayes/CParticleFilterData.h>
#include <mrpt/random/RandomGenerators.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <exception>
#include <thread>
#include <vector>

#include "losmimo/localization/optimal_proposal.h"
#include "losmimo/localization/particles.h"
#include "losmimo/localization/pose/landmark_filter.h"
#include "losmimo/localization/range_az_el.h"
#include "losmimo/localization/resampling.h"

namespace losmimo::localization {

namespace {

using mrpt::bayes::particle_storage_mode;
using Particles6 = mrpt::bayes::CParticleFilterData<Pose6, particle_storage_mode::VALUE>;

constexpr int kLandmarkChordIterations = 8;

// The associated readings as whitened residuals r = (z - h(x)) / sigma (angles wrapped) and rows
// A = diag(1 / sigma) J_z_x: optimal_proposal.h's measurement concept.
class WhitenedBearings {
 public:
  explicit WhitenedBearings(const std::vector<AssociatedReading>& readings) : readings_(readings) {
    for (const AssociatedReading& u : readings_) sensors_.push_back(to_cpose3d(u.sensor_on_robot));
  }

  double accumulate(const Pose6& x, Matrix6d* AtA, Pose6* Atr) const {
    const mrpt::poses::CPose3D robot = to_cpose3d(x);
    double r2 = 0.0;
    for (std::size_t j = 0; j < readings_.size(); ++j) {
      const AssociatedReading& u = readings_[j];
      Matrix36d J;
      const Eigen::Vector3d h = landmark_predict(robot, sensors_[j], u.landmark_m, AtA ? &J : nullptr);
      const Eigen::Vector3d r = range_az_el_innovation(u.z, h).cwiseQuotient(u.sigma);
      r2 += r.squaredNorm();
      if (!AtA) continue;
      const Matrix36d A = u.sigma.cwiseInverse().asDiagonal() * J;
      AtA->noalias() += A.transpose() * A;
      *Atr += A.transpose() * r;
    }
    return r2;
  }

  void rows(const Pose6& x, std::vector<Pose6>& a) const {
    const mrpt::poses::CPose3D robot = to_cpose3d(x);
    a.clear();
    for (std::size_t j = 0; j < readings_.size(); ++j) {
      Matrix36d J;
      landmark_predict(robot, sensors_[j], readings_[j].landmark_m, &J);
      for (int k = 0; k < 3; ++k) a.push_back(J.row(k).transpose() / readings_[j].sigma(k));
    }
  }

  double project(const Pose6& x, const std::vector<Pose6>& a, Pose6& Atr) const {
    const mrpt::poses::CPose3D robot = to_cpose3d(x);
    Atr.setZero();
    double r2 = 0.0;
    std::size_t row = 0;
    for (std::size_t j = 0; j < readings_.size(); ++j) {
      const AssociatedReading& u = readings_[j];
      const Eigen::Vector3d r =
          range_az_el_innovation(u.z, landmark_predict(robot, sensors_[j], u.landmark_m)).cwiseQuotient(u.sigma);
      r2 += r.squaredNorm();
      for (int k = 0; k < 3; ++k, ++row) {
        if (!a.empty()) Atr += a[row] * r(k);
      }
    }
    return r2;
  }

 private:
  const std::vector<AssociatedReading>& readings_;
  std::vector<mrpt::poses::CPose3D> sensors_;
};

// Weighted mean and covariance of poses, deviations taken about the first pose (angles wrapped).
void pose6_moments(const std::vector<Pose6>& poses, const std::vector<double>& w, Pose6& mean, Matrix6d& cov) {
  Pose6 first = Pose6::Zero();
  for (std::size_t i = 0; i < poses.size(); ++i) first += w[i] * pose6_deviation(poses[i], poses.front());
  mean = compose_pose6(poses.front() + first, Pose6::Zero());
  Pose6 m1 = Pose6::Zero();
  Matrix6d m2 = Matrix6d::Zero();
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const Pose6 e = pose6_deviation(poses[i], mean);
    m1 += w[i] * e;
    m2.noalias() += w[i] * e * e.transpose();
  }
  cov = m2 - m1 * m1.transpose();
}

// f(k) for every k < n, the range split in two halves on two threads when the machine has two
// cores and there is enough work; f must touch only what belongs to its k. An exception in
// either half is rethrown here after both are done.
template <class F>
void for_each_index_split(std::size_t n, const F& f) {
  constexpr std::size_t kMinPerThread = 32;
  if (std::thread::hardware_concurrency() < 2 || n < 2 * kMinPerThread) {
    for (std::size_t k = 0; k < n; ++k) f(k);
    return;
  }
  const std::size_t half = n / 2;
  std::exception_ptr error;
  std::thread second([&] {
    try {
      for (std::size_t k = half; k < n; ++k) f(k);
    } catch (...) {
      error = std::current_exception();
    }
  });
  std::exception_ptr first_error;
  try {
    for (std::size_t k = 0; k < half; ++k) f(k);
  } catch (...) {
    first_error = std::current_exception();
  }
  second.join();
  if (first_error) std::rethrow_exception(first_error);
  if (error) std::rethrow_exception(error);
}

FilterConfig particle_options(const LandmarkFilterConfig& config) {
  FilterConfig f;
  f.num_particles = config.num_particles;
  f.resampling = config.resampling;
  f.ess_threshold = config.ess_threshold;
  return f;
}

class LandmarkParticleFilter final
    : public LandmarkPoseFilter,
      public Particles6,
      public mrpt::bayes::CParticleFilterDataImpl<LandmarkParticleFilter, Particles6::CParticleList> {
 public:
  LandmarkParticleFilter(const LandmarkFilterConfig& config, const BeaconMap& landmarks, const LandmarkBelief& start,
                         std::uint64_t seed)
      : config_(config), landmarks_(landmarks), rng_(fold_seed(seed)) {
    configure_particle_filter(pf_, particle_options(config));
    LandmarkBelief b = start;
    if (config_.planar) make_planar(b);
    // A start covariance with exact zeros (a known start) draws every particle at the mean.
    Eigen::SelfAdjointEigenSolver<Matrix6d> eig(0.5 * (b.cov + b.cov.transpose()));
    const Matrix6d root = eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
    m_particles.resize(static_cast<std::size_t>(config.num_particles));
    for (auto& p : m_particles) {
      p.d = project(b.mean + root * normal6());
      p.log_w = 0.0;
    }
    update_belief();
  }

  void step(const OdometryIncrement6& odometry, const std::vector<BearingScan>& scans) override {
    ++counters_.frames;
    u_ = odometry;
    scans_ = &scans;
    pf_.executeOn(*this, nullptr, nullptr);
    scans_ = nullptr;
    const std::vector<double> log_w = log_weights(m_particles);
    if (normalized_ess(log_w) < config_.ess_threshold) {
      performSubstitution(resampling_indices(config_.resampling, log_w, rng_));
      for (auto& p : m_particles) p.log_w = 0.0;
      ++counters_.resamplings;
    }
    update_belief();
  }

  LandmarkBelief belief() const override { return belief_; }
  const LandmarkCounters& counters() const override { return counters_; }

 protected:
  void prediction_and_update_pfStandardProposal(
      const mrpt::obs::CActionCollection* /*action*/, const mrpt::obs::CSensoryFrame* /*obs*/,
      const mrpt::bayes::CParticleFilter::TParticleFilterOptions& /*options*/) override {
    const std::size_t n = m_particles.size();
    const Matrix6d sigma_u = u_.cov + Matrix6d(config_.min_odometry_sigma.cwiseAbs2().asDiagonal());
    std::vector<Pose6> x_bar(n);
    std::vector<Matrix6d> J_u(n);
    std::size_t i = 0;
    for (const auto& p : m_particles) {
      x_bar[i] = compose_pose6(p.d, u_.delta, nullptr, &J_u[i]);
      ++i;
    }
    // Predicted moments: the spread of the predicted means plus the motion noise at the mean.
    const std::vector<double> w = normalized_weights(log_weights(m_particles));
    LandmarkBelief predicted;
    pose6_moments(x_bar, w, predicted.mean, predicted.cov);
    predicted.cov += odometry_noise(config_, predicted.mean, OdometryIncrement6{Pose6::Zero(), u_.cov});
    const std::vector<AssociatedReading> fuse =
        associate(config_, landmarks_, scans_ ? *scans_ : std::vector<BearingScan>{}, predicted, counters_);
    if (fuse.empty()) {  // the motion model: sample the increment, compose in the robot frame
      const Matrix6d L_u = sigma_u.llt().matrixL();
      for (auto& p : m_particles) p.d = project(compose_pose6(p.d, u_.delta + L_u * normal6()));
      return;
    }
    // The shared linearisation holds the particles' own process information (their mean W),
    // not the predicted covariance's: each particle's chord iterations solve W_i + A^T A, and
    // with the wider W_hat (particle spread included) they overshoot along the weakly measured
    // directions, leaving most particles to the full per-particle solve (62% of the draws on
    // MRPT's 6-D kf-slam demo; with W_mean and eight chord iterations none, about four
    // iterations per draw, and 0.2-0.4% on the 2-D and non-centred demos).
    const WhitenedBearings measurement(fuse);
    std::vector<Matrix6d> W(n);
    Matrix6d W_mean = Matrix6d::Zero();
    for (i = 0; i < n; ++i) {
      W[i] = (J_u[i] * sigma_u * J_u[i].transpose()).llt().solve(Matrix6d::Identity());
      W_mean += w[i] * W[i];
    }
    const OptimalProposal<6, WhitenedBearings> proposal(measurement, predicted.mean, W_mean, kLandmarkChordIterations);
    // The draws in particle order (the stream is the same for any split), then the particles'
    // proposals, independent of each other, on two threads.
    std::vector<Pose6> eps(n);
    for (Pose6& e : eps) e = normal6();
    std::vector<Pose6> x(n);
    std::vector<double> log_w_increment(n);
    for_each_index_split(n, [&](std::size_t k) { log_w_increment[k] = proposal.sample(x_bar[k], W[k], eps[k], x[k]); });
    i = 0;
    for (auto& p : m_particles) {
      p.log_w += log_w_increment[i];
      p.d = project(x[i]);
      ++i;
    }
  }

 private:
  Pose6 normal6() {
    Pose6 v;
    for (int k = 0; k < 6; ++k) v(k) = rng_.drawGaussian1D_normalized();
    return v;
  }

  // Angles normalised as CPose3D; z, pitch, roll at 0 when planar.
  // Inside |pitch| < pi/2 the yaw-pitch-roll of a rotation is unique, so wrapping yaw and roll
  // gives the angles CPose3D would (to rounding) without building and decomposing its matrix.
  Pose6 project(const Pose6& x) const {
    constexpr double kHalfPi = 1.57079632679489661923;
    Pose6 out = x;
    if (std::abs(x(kP6Pitch)) < kHalfPi - 1e-6) {
      out(kP6Yaw) = wrap_angle_rad(x(kP6Yaw));
      out(kP6Roll) = wrap_angle_rad(x(kP6Roll));
    } else {
      out = compose_pose6(x, Pose6::Zero());
    }
    if (config_.planar) out(kP6Z) = out(kP6Pitch) = out(kP6Roll) = 0.0;
    return out;
  }

  void update_belief() {
    std::vector<Pose6> poses;
    poses.reserve(m_particles.size());
    for (const auto& p : m_particles) poses.push_back(p.d);
    pose6_moments(poses, normalized_weights(log_weights(m_particles)), belief_.mean, belief_.cov);
    belief_.cov = 0.5 * (belief_.cov + belief_.cov.transpose()).eval();
  }

  LandmarkFilterConfig config_;
  BeaconMap landmarks_;
  mrpt::bayes::CParticleFilter pf_;
  mrpt::random::CRandomGenerator rng_;
  LandmarkCounters counters_;
  LandmarkBelief belief_;
  OdometryIncrement6 u_;
  const std::vector<BearingScan>* scans_ = nullptr;
};

}  // namespace

std::unique_ptr<LandmarkPoseFilter> make_landmark_particle_filter(const LandmarkFilterConfig& config,
                                                                  const BeaconMap& landmarks,
                                                                  const LandmarkBelief& start, std::uint64_t seed) {
  return std::make_unique<LandmarkParticleFilter>(config, landmarks, start, seed);
}

}  // namespace losmimo::localization
