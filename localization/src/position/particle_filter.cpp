#include "losmimo/localization/position/particle_filter.h"

#include <mrpt/bayes/CParticleFilter.h>
#include <mrpt/bayes/CParticleFilterData.h>
#include <mrpt/random/RandomGenerators.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <vector>

#include "losmimo/localization/position/beacon_model.h"
#include "losmimo/localization/optimal_proposal.h"
#include "losmimo/localization/particles.h"
#include "losmimo/localization/resampling.h"
#include "losmimo/localization/position/robustness.h"

namespace losmimo::localization {

namespace {

using mrpt::bayes::particle_storage_mode;
using ParticleData = mrpt::bayes::CParticleFilterData<Eigen::Vector3d, particle_storage_mode::VALUE>;
constexpr double kMinProposalRho_m = 1e-9;

// Weighted mean and covariance of the particle cloud (normalised linear weights), one pass
// with iterators (deque indexing is slow), accumulating about the first particle for accuracy.
void moments(const ParticleData::CParticleList& particles, Eigen::Vector3d& mean_m, Eigen::Matrix3d& cov_m2) {
  const std::vector<double> w = normalized_weights(log_weights(particles));
  const Eigen::Vector3d origin_m = particles.front().d;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  auto wi = w.begin();
  for (const auto& p : particles) {
    const Eigen::Vector3d e = p.d - origin_m;
    first += *wi * e;
    second.noalias() += *wi * e * e.transpose();
    ++wi;
  }
  mean_m = origin_m + first;
  cov_m2 = second - first * first.transpose();
}

// The beacon as whitened residuals r(q) = (z - h(q)) / sigma, angles wrapped, and A = dh/dq / sigma
// (optimal_proposal.h's measurement concept).
struct WhitenedBeacon {
  Eigen::Vector3d z;
  Eigen::Vector3d inv_sigma;

  double accumulate(const Eigen::Vector3d& q_m, Eigen::Matrix3d* AtA, Eigen::Vector3d* Atr) const {
    const Eigen::Vector3d r = beacon_innovation(z, beacon_predict(q_m)).cwiseProduct(inv_sigma);
    // The azimuth row has rho^2 in its denominator: no Jacobian on the array's z axis (the
    // gate's geometry check keeps the predicted mean >= kMinBeaconRho_m away from it).
    if (AtA != nullptr && std::hypot(q_m.x(), q_m.y()) >= kMinProposalRho_m) {
      const Eigen::Matrix3d A = inv_sigma.asDiagonal() * beacon_jacobian(q_m);
      AtA->noalias() += A.transpose() * A;
      Atr->noalias() += A.transpose() * r;
    }
    return r.squaredNorm();
  }

  void rows(const Eigen::Vector3d& q_m, std::vector<Eigen::Vector3d>& a) const {
    a.clear();
    // On the array's z axis (never fused: the geometry check rejects it) there is no row.
    if (std::hypot(q_m.x(), q_m.y()) < kMinProposalRho_m) return;
    const Eigen::Matrix3d A = inv_sigma.asDiagonal() * beacon_jacobian(q_m);
    for (int k = 0; k < 3; ++k) a.push_back(A.row(k).transpose());
  }

  double project(const Eigen::Vector3d& q_m, const std::vector<Eigen::Vector3d>& a, Eigen::Vector3d& Atr) const {
    const Eigen::Vector3d r = beacon_innovation(z, beacon_predict(q_m)).cwiseProduct(inv_sigma);
    Atr.setZero();
    for (std::size_t k = 0; k < a.size(); ++k) Atr += a[k] * r(static_cast<Eigen::Index>(k));
    return r.squaredNorm();
  }
};

}  // namespace

// The particle set MRPT's CParticleFilter runs on. The epoch's inputs are set before
// executeOn(); MRPT's action/observation pointers are unused (nullptr), which keeps
// mrpt::obs out of this library.
class ParticlePositionFilter::Mrpt final
    : public ParticleData,
      public mrpt::bayes::CParticleFilterDataImpl<Mrpt, ParticleData::CParticleList> {
 public:
  Mrpt(const FilterConfig& config, const Belief& initial, std::uint64_t seed)
      : config_(config), rng_(fold_seed(seed)), epochs_since_beacon_(initial.epochs_since_beacon) {
    configure_particle_filter(pf_, config);
    draw_from(initial.mean_m, initial.cov_m2);
    update_belief();
  }

  void step(const Eigen::Vector3d& measured_displacement_m, const std::optional<BeaconMeasurement>& beacon) {
    ++counters_.epochs;
    const ScreenedDisplacement d = screen_displacement(config_, measured_displacement_m, counters_);
    u_m_ = d.u_m;
    sigma_q_m_ = d.sigma_m;
    beacon_ = beacon;
    verdict_ = BeaconVerdict::kNone;

    pf_.executeOn(*this, nullptr, nullptr);
    last_ess_ = ESS();

    if (verdict_ == BeaconVerdict::kReset) {
      draw_from(reset_belief_.mean_m, reset_belief_.cov_m2);
    } else if (last_ess_ < config_.ess_threshold) {
      resample();
    }
    const bool used_beacon = verdict_ == BeaconVerdict::kFuse || verdict_ == BeaconVerdict::kReset;
    epochs_since_beacon_ = used_beacon ? 0 : epochs_since_beacon_ + 1;
    update_belief();
  }

  const Belief& belief() const { return belief_; }
  const FilterCounters& counters() const { return counters_; }
  int num_particles() const { return static_cast<int>(m_particles.size()); }
  double last_normalized_ess() const { return last_ess_; }

 protected:
  void prediction_and_update_pfStandardProposal(
      const mrpt::obs::CActionCollection* /*action*/, const mrpt::obs::CSensoryFrame* /*obs*/,
      const mrpt::bayes::CParticleFilter::TParticleFilterOptions& /*options*/) override {
    if (beacon_) {
      // Screen against the predicted moments: the cloud moved by d, plus sigma_d^2 I.
      Eigen::Vector3d mean_m;
      Eigen::Matrix3d cov_m2;
      moments(m_particles, mean_m, cov_m2);
      mean_m += u_m_;
      cov_m2 += sigma_q_m_ * sigma_q_m_ * Eigen::Matrix3d::Identity();
      predicted_mean_m_ = mean_m;
      verdict_ = screen_beacon(config_, beacon_, mean_m, cov_m2, consecutive_gated_, counters_);
    }
    if (verdict_ == BeaconVerdict::kFuse) {
      // Locally linearised optimal proposal with exact weights (optimal_proposal.h).
      const WhitenedBeacon measurement{to_vector(*beacon_),
                                       floored_beacon_cov(config_).diagonal().cwiseSqrt().cwiseInverse()};
      const Eigen::Matrix3d W = Eigen::Matrix3d::Identity() / (sigma_q_m_ * sigma_q_m_);
      const OptimalProposal<3, WhitenedBeacon> proposal(measurement, predicted_mean_m_, W);
      for (auto& p : m_particles) {
        Eigen::Vector3d eps;
        for (int a = 0; a < 3; ++a) eps(a) = rng_.drawGaussian1D_normalized();
        Eigen::Vector3d q_m;
        p.log_w += proposal.sample(Eigen::Vector3d(p.d + u_m_), W, eps, q_m);
        p.d = q_m;
      }
      return;
    }
    // No beacon to fuse: the motion model is the proposal.
    for (auto& p : m_particles) {
      for (int a = 0; a < 3; ++a) p.d(a) += u_m_(a) + sigma_q_m_ * rng_.drawGaussian1D_normalized();
    }
    if (verdict_ == BeaconVerdict::kReset) {
      reset_belief_ = floored_beacon_fix(config_, *beacon_);
    }
  }

 private:
  // Replaces the cloud by N equally weighted draws from N(mean, cov).
  void draw_from(const Eigen::Vector3d& mean_m, const Eigen::Matrix3d& cov_m2) {
    if (!cov_m2.allFinite() || !mean_m.allFinite()) ++counters_.non_finite_state;
    Eigen::Matrix3d P = cov_m2;
    make_spd<3>(P, config_.min_variance_m2, fallback_variance_m2(config_));
    const Eigen::Matrix3d L = P.llt().matrixL();
    m_particles.resize(static_cast<std::size_t>(config_.num_particles));
    for (auto& p : m_particles) {
      Eigen::Vector3d n;
      for (int a = 0; a < 3; ++a) n(a) = rng_.drawGaussian1D_normalized();
      p.d = mean_m + L * n;
      p.log_w = 0.0;
    }
  }

  void resample() {
    Eigen::Vector3d mean_m;
    Eigen::Matrix3d cov_m2;
    moments(m_particles, mean_m, cov_m2);
    resample_particles(*this, config_.resampling, rng_, counters_);
    const double h = config_.regularization_bandwidth;
    if (h <= 0.0) return;
    // Liu-West kernel jitter: shrink towards the mean by a = sqrt(1 - h^2) and add h L n, so
    // the cloud keeps its mean and covariance but duplicates become distinct particles.
    make_spd<3>(cov_m2, config_.min_variance_m2, fallback_variance_m2(config_));
    const Eigen::Matrix3d L = cov_m2.llt().matrixL();
    liu_west_jitter(m_particles, mean_m, L, h, rng_);
  }

  void update_belief() {
    moments(m_particles, belief_.mean_m, belief_.cov_m2);
    repair_covariance<3>(belief_.mean_m, belief_.cov_m2, config_, counters_);
    apply_health(config_, epochs_since_beacon_, belief_);
  }

  FilterConfig config_;
  mrpt::bayes::CParticleFilter pf_;
  mrpt::random::CRandomGenerator rng_;
  FilterCounters counters_;
  int epochs_since_beacon_ = 0;
  int consecutive_gated_ = 0;
  double last_ess_ = 1.0;
  Belief belief_;
  // Inputs of the current epoch, read by prediction_and_update_pfStandardProposal().
  Eigen::Vector3d u_m_ = Eigen::Vector3d::Zero();
  double sigma_q_m_ = 0.0;
  std::optional<BeaconMeasurement> beacon_;
  BeaconVerdict verdict_ = BeaconVerdict::kNone;
  Eigen::Vector3d predicted_mean_m_ = Eigen::Vector3d::Zero();
  Belief reset_belief_;
};

ParticlePositionFilter::ParticlePositionFilter(const FilterConfig& config, const Belief& initial, std::uint64_t seed) {
  validate(config);
  validate(initial);
  pf_ = std::make_unique<Mrpt>(config, initial, seed);
}

ParticlePositionFilter::~ParticlePositionFilter() = default;

void ParticlePositionFilter::step(const Eigen::Vector3d& measured_displacement_m,
                                  const std::optional<BeaconMeasurement>& beacon) {
  pf_->step(measured_displacement_m, beacon);
}

Belief ParticlePositionFilter::belief() const { return pf_->belief(); }
const FilterCounters& ParticlePositionFilter::counters() const { return pf_->counters(); }
int ParticlePositionFilter::num_particles() const { return pf_->num_particles(); }
double ParticlePositionFilter::last_normalized_ess() const { return pf_->last_normalized_ess(); }

}  // namespace losmimo::localization
