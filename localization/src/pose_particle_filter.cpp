#include "losmimo/localization/pose_particle_filter.h"

#include <mrpt/bayes/CParticleFilter.h>
#include <mrpt/bayes/CParticleFilterData.h>
#include <mrpt/random/RandomGenerators.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <vector>

#include "losmimo/localization/beacon_model.h"
#include "losmimo/localization/initial_pose.h"
#include "losmimo/localization/optimal_proposal.h"
#include "losmimo/localization/particle_filter.h"
#include "losmimo/localization/range_screening.h"
#include "losmimo/localization/resampling.h"

namespace losmimo::localization {

namespace {

using mrpt::bayes::particle_storage_mode;
using PoseParticles = mrpt::bayes::CParticleFilterData<Eigen::Vector4d, particle_storage_mode::VALUE>;

// x - about, with the heading difference wrapped to (-pi, pi].
Eigen::Vector4d deviation(const Eigen::Vector4d& x, const Eigen::Vector4d& about) {
  Eigen::Vector4d d = x - about;
  d(kPoseYaw) = wrap_angle_rad(d(kPoseYaw));
  return d;
}

// Weighted mean (circular heading) and covariance of poses, accumulated about the first pose.
void pose_moments(const std::vector<Eigen::Vector4d>& poses, const std::vector<double>& w, Eigen::Vector4d& mean,
                  Eigen::Matrix4d& cov) {
  double sin_sum = 0.0;
  double cos_sum = 0.0;
  Eigen::Vector3d first_p = Eigen::Vector3d::Zero();
  const Eigen::Vector3d origin_m = poses.front().head<3>();
  for (std::size_t i = 0; i < poses.size(); ++i) {
    first_p += w[i] * (poses[i].head<3>() - origin_m);
    sin_sum += w[i] * std::sin(poses[i](kPoseYaw));
    cos_sum += w[i] * std::cos(poses[i](kPoseYaw));
  }
  mean.head<3>() = origin_m + first_p;
  mean(kPoseYaw) = std::atan2(sin_sum, cos_sum);
  Eigen::Vector4d first = Eigen::Vector4d::Zero();
  Eigen::Matrix4d second = Eigen::Matrix4d::Zero();
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const Eigen::Vector4d e = deviation(poses[i], mean);
    first += w[i] * e;
    second.noalias() += w[i] * e * e.transpose();
  }
  cov = second - first * first.transpose();
}

// The fused readings as whitened residuals (optimal_proposal.h's measurement concept).
struct WhitenedRanges {
  const std::vector<UsableRange>* readings;

  double accumulate(const Eigen::Vector4d& x, Eigen::Matrix4d* AtA, Eigen::Vector4d* Atr) const {
    const double c = std::cos(x(kPoseYaw));
    const double s = std::sin(x(kPoseYaw));
    double r2 = 0.0;
    for (const UsableRange& u : *readings) {
      const Eigen::Vector3d& o = u.sensor_on_robot_m;
      const Eigen::Vector3d d(x(kPoseX) + c * o.x() - s * o.y() - u.beacon_m.x(),
                              x(kPoseY) + s * o.x() + c * o.y() - u.beacon_m.y(), x(kPoseZ) + o.z() - u.beacon_m.z());
      const double h = d.norm();
      const double r = (u.range_m - h) / u.sigma_m;
      r2 += r * r;
      if (AtA == nullptr || !(h >= kMinRangeGeometry_m)) continue;
      const Eigen::Vector3d e = d / h;
      const Eigen::Vector4d a =
          Eigen::Vector4d(e.x(), e.y(), e.z(), e.x() * (-s * o.x() - c * o.y()) + e.y() * (c * o.x() - s * o.y())) /
          u.sigma_m;
      AtA->noalias() += a * a.transpose();
      *Atr += a * r;
    }
    return r2;
  }
};

}  // namespace

class ParticlePoseFilter::Mrpt final : public PoseParticles,
                                       public mrpt::bayes::CParticleFilterDataImpl<Mrpt, PoseParticles::CParticleList> {
 public:
  Mrpt(const PoseFilterConfig& config, const BeaconMap& beacons, const InitialPose& initial, std::uint64_t seed)
      : config_(config), beacons_(beacons), rng_(fold_seed(seed)) {
    pf_.m_options.PF_algorithm = mrpt::bayes::CParticleFilter::pfStandardProposal;
    pf_.m_options.sampleSize = static_cast<unsigned int>(config.filter.num_particles);
    pf_.m_options.adaptiveSampleSize = false;
    pf_.m_options.BETA = 0.0;  // MRPT's own (global-generator) resampling never runs
    m_particles.resize(static_cast<std::size_t>(config.filter.num_particles));
    for (auto& p : m_particles) {
      p.d = sample_initial_pose(initial, rng_);
      p.log_w = 0.0;
    }
    epochs_since_beacon_ = initial.fix ? 0 : config.filter.degraded_after_epochs;
    update_belief();
  }

  void step(const OdometryIncrement& odometry, const std::vector<BeaconRangeScan>& scans) {
    ++counters_.epochs;
    u_ = screen_odometry(config_, odometry, counters_);
    scans_ = &scans;
    verdict_ = RangeEpochVerdict::kNone;
    pf_.executeOn(*this, nullptr, nullptr);
    scans_ = nullptr;
    last_ess_ = ESS();
    if (verdict_ != RangeEpochVerdict::kReset && last_ess_ < config_.filter.ess_threshold) resample();
    const bool used = verdict_ == RangeEpochVerdict::kFuse || verdict_ == RangeEpochVerdict::kReset;
    epochs_since_beacon_ = used ? 0 : epochs_since_beacon_ + 1;
    update_belief();
  }

  const PoseBelief& belief() const { return belief_; }
  const FilterCounters& counters() const { return counters_; }
  int num_particles() const { return static_cast<int>(m_particles.size()); }
  double last_normalized_ess() const { return last_ess_; }

 protected:
  void prediction_and_update_pfStandardProposal(
      const mrpt::obs::CActionCollection* /*action*/, const mrpt::obs::CSensoryFrame* /*obs*/,
      const mrpt::bayes::CParticleFilter::TParticleFilterOptions& /*options*/) override {
    const std::size_t n = m_particles.size();
    // Predicted means xbar_i and the predicted moments (header).
    std::vector<Eigen::Vector4d> x_bar(n);
    std::vector<double> log_w(n);
    std::size_t i = 0;
    for (const auto& p : m_particles) {
      x_bar[i] = compose(p.d, u_.delta);
      log_w[i] = p.log_w;
      ++i;
    }
    const std::vector<double> w = normalized_weights(log_w);
    Eigen::Vector4d mean;
    Eigen::Matrix4d cov;
    pose_moments(x_bar, w, mean, cov);
    Eigen::Matrix4d mean_Q = Eigen::Matrix4d::Zero();
    i = 0;
    for (const auto& p : m_particles) {
      const Eigen::Matrix4d G = compose_jacobian_increment(p.d);
      mean_Q.noalias() += w[i++] * (G * u_.cov * G.transpose());
    }
    cov += mean_Q;
    const RangeUpdatePlan plan = plan_range_update(config_, beacons_, scans_ ? *scans_ : std::vector<BeaconRangeScan>{},
                                                   mean, cov, consecutive_gated_, counters_);
    verdict_ = plan.verdict;

    if (plan.verdict != RangeEpochVerdict::kFuse) {
      // Motion model: sample the increment, compose in the robot frame.
      const Eigen::Matrix4d L_u = u_.cov.llt().matrixL();
      for (auto& p : m_particles) p.d = compose(p.d, u_.delta + L_u * normal4());
      if (plan.verdict == RangeEpochVerdict::kReset) redraw_positions(*plan.reset_fix, plan.reset_sensor_on_robot_m);
      return;
    }
    // Optimal proposal per particle.
    const Eigen::Matrix4d W_u = u_.cov.llt().solve(Eigen::Matrix4d::Identity());
    const WhitenedRanges measurement{&plan.fuse};
    i = 0;
    for (auto& p : m_particles) {
      const Eigen::Matrix4d G = compose_jacobian_increment(p.d);
      const Eigen::Matrix4d W = G * W_u * G.transpose();
      Eigen::Vector4d x;
      p.log_w += sample_optimal_proposal<4>(x_bar[i], W, measurement, normal4(), x);
      x(kPoseYaw) = wrap_angle_rad(x(kPoseYaw));
      p.d = x;
      ++i;
    }
  }

 private:
  Eigen::Vector4d normal4() {
    Eigen::Vector4d n;
    for (int k = 0; k < kPoseSize; ++k) n(k) = rng_.drawGaussian1D_normalized();
    return n;
  }

  void redraw_positions(const RangeFix& fix, const Eigen::Vector3d& sensor_on_robot_m) {
    const Eigen::Matrix3d L = fix.cov_m2.llt().matrixL();
    for (auto& p : m_particles) {
      Eigen::Vector3d n;
      for (int k = 0; k < 3; ++k) n(k) = rng_.drawGaussian1D_normalized();
      const Eigen::Vector3d c_m = fix.sensor_m + L * n;
      const Eigen::Vector4d heading_only(0.0, 0.0, 0.0, p.d(kPoseYaw));
      p.d.head<3>() = c_m - sensor_position_m(heading_only, sensor_on_robot_m);
      p.log_w = 0.0;
    }
  }

  void current_moments(Eigen::Vector4d& mean, Eigen::Matrix4d& cov) const {
    std::vector<Eigen::Vector4d> poses;
    std::vector<double> log_w;
    poses.reserve(m_particles.size());
    log_w.reserve(m_particles.size());
    for (const auto& p : m_particles) {
      poses.push_back(p.d);
      log_w.push_back(p.log_w);
    }
    pose_moments(poses, normalized_weights(log_w), mean, cov);
  }

  void resample() {
    Eigen::Vector4d mean;
    Eigen::Matrix4d cov;
    current_moments(mean, cov);
    std::vector<double> log_w;
    log_w.reserve(m_particles.size());
    for (const auto& p : m_particles) log_w.push_back(p.log_w);
    performSubstitution(resampling_indices(config_.filter.resampling, log_w, rng_));
    for (auto& p : m_particles) p.log_w = 0.0;
    ++counters_.resamplings;
    const double h = config_.filter.regularization_bandwidth;
    if (h <= 0.0) return;
    // Liu-West jitter (particle_filter.h), deviations about the (circular) mean.
    make_spd(cov, config_.filter.min_variance_m2, fallback_variance());
    const Eigen::Matrix4d L = cov.llt().matrixL();
    const double a = std::sqrt(1.0 - h * h);
    for (auto& p : m_particles) {
      Eigen::Vector4d x = mean + a * deviation(p.d, mean) + h * (L * normal4());
      x(kPoseYaw) = wrap_angle_rad(x(kPoseYaw));
      p.d = x;
    }
  }

  double fallback_variance() const {
    return config_.filter.missing_displacement_sigma_m * config_.filter.missing_displacement_sigma_m;
  }

  void update_belief() {
    current_moments(belief_.mean, belief_.cov);
    if (!belief_.cov.allFinite() || !belief_.mean.allFinite()) ++counters_.non_finite_state;
    if (make_spd(belief_.cov, config_.filter.min_variance_m2, fallback_variance())) ++counters_.covariance_repairs;
    apply_health(config_, epochs_since_beacon_, belief_);
  }

  PoseFilterConfig config_;
  BeaconMap beacons_;
  mrpt::bayes::CParticleFilter pf_;
  mrpt::random::CRandomGenerator rng_;
  FilterCounters counters_;
  int epochs_since_beacon_ = 0;
  int consecutive_gated_ = 0;
  double last_ess_ = 1.0;
  PoseBelief belief_;
  // Inputs of the current epoch, read by prediction_and_update_pfStandardProposal().
  OdometryIncrement u_;
  const std::vector<BeaconRangeScan>* scans_ = nullptr;
  RangeEpochVerdict verdict_ = RangeEpochVerdict::kNone;
};

ParticlePoseFilter::ParticlePoseFilter(const PoseFilterConfig& config, const BeaconMap& beacons,
                                       const InitialPose& initial, std::uint64_t seed) {
  validate(config);
  validate(initial.prior);
  pf_ = std::make_unique<Mrpt>(config, beacons, initial, seed);
}

ParticlePoseFilter::~ParticlePoseFilter() = default;

void ParticlePoseFilter::step(const OdometryIncrement& odometry, const std::vector<BeaconRangeScan>& scans) {
  pf_->step(odometry, scans);
}

PoseBelief ParticlePoseFilter::belief() const { return pf_->belief(); }
const FilterCounters& ParticlePoseFilter::counters() const { return pf_->counters(); }
int ParticlePoseFilter::num_particles() const { return pf_->num_particles(); }
double ParticlePoseFilter::last_normalized_ess() const { return pf_->last_normalized_ess(); }

}  // namespace losmimo::localization
