#include "losmimo/localization/pose/particle_filter.h"

#include <mrpt/bayes/CParticleFilter.h>
#include <mrpt/bayes/CParticleFilterData.h>
#include <mrpt/random/RandomGenerators.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <vector>

#include "losmimo/localization/position/beacon_model.h"
#include "losmimo/localization/pose/initial_pose.h"
#include "losmimo/localization/optimal_proposal.h"
#include "losmimo/localization/particles.h"
#include "losmimo/localization/pose/robustness.h"
#include "losmimo/localization/resampling.h"

namespace losmimo::localization {

namespace {

using mrpt::bayes::particle_storage_mode;
using PoseParticles = mrpt::bayes::CParticleFilterData<Eigen::Vector4d, particle_storage_mode::VALUE>;

// x - about, with the heading difference wrapped to (-pi, pi].
Eigen::Vector4d deviation(const Eigen::Vector4d& x, const Eigen::Vector4d& about) {
  Eigen::Vector4d d = x - about;
  d(kPoseYaw) = wrap_near_rad(d(kPoseYaw));
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

// G M G^T for G = J_x'_u at heading (c, s) = (cos, sin): the x-y block rotated, R M_xy R^T, the
// x-y rows of the cross blocks rotated, R M_x,rest, and the rest unchanged.
Eigen::Matrix4d rotate_xy(const Eigen::Matrix4d& M, double c, double s) {
  Eigen::Matrix2d R;
  R << c, -s, s, c;
  Eigen::Matrix4d out = M;
  out.topLeftCorner<2, 2>() = R * M.topLeftCorner<2, 2>() * R.transpose();
  out.topRightCorner<2, 2>() = R * M.topRightCorner<2, 2>();
  out.bottomLeftCorner<2, 2>() = out.topRightCorner<2, 2>().transpose();
  return out;
}

// E[G M G^T] over headings with weighted moments trig = (E c, E s, E c^2, E s^2, E cs): with
// R = c I + s J (J the quarter turn), R A R^T = c^2 A + cs (J A + A J^T) + s^2 J A J^T and
// R B = c B + s J B, both linear in the moments.
Eigen::Matrix4d rotated_mean(const Eigen::Matrix4d& M, const Eigen::Matrix<double, 5, 1>& trig) {
  Eigen::Matrix2d J;
  J << 0.0, -1.0, 1.0, 0.0;
  const Eigen::Matrix2d A = M.topLeftCorner<2, 2>();
  const Eigen::Matrix2d B = M.topRightCorner<2, 2>();
  Eigen::Matrix4d out = M;
  out.topLeftCorner<2, 2>() = trig(2) * A + trig(4) * (J * A + A * J.transpose()) + trig(3) * (J * A * J.transpose());
  out.topRightCorner<2, 2>() = trig(0) * B + trig(1) * (J * B);
  out.bottomLeftCorner<2, 2>() = out.topRightCorner<2, 2>().transpose();
  return out;
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

  void rows(const Eigen::Vector4d& x, std::vector<Eigen::Vector4d>& a) const {
    a.clear();
    for (const UsableRange& u : *readings) {
      a.push_back(range_jacobian(x, u.sensor_on_robot_m, u.beacon_m).transpose() / u.sigma_m);
    }
  }

  double project(const Eigen::Vector4d& x, const std::vector<Eigen::Vector4d>& a, Eigen::Vector4d& Atr) const {
    const double c = std::cos(x(kPoseYaw));
    const double s = std::sin(x(kPoseYaw));
    Atr.setZero();
    double r2 = 0.0;
    for (std::size_t j = 0; j < readings->size(); ++j) {
      const UsableRange& u = (*readings)[j];
      const Eigen::Vector3d& o = u.sensor_on_robot_m;
      const Eigen::Vector3d d(x(kPoseX) + c * o.x() - s * o.y() - u.beacon_m.x(),
                              x(kPoseY) + s * o.x() + c * o.y() - u.beacon_m.y(), x(kPoseZ) + o.z() - u.beacon_m.z());
      const double r = (u.range_m - d.norm()) / u.sigma_m;
      r2 += r * r;
      if (!a.empty()) Atr += a[j] * r;
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
    configure_particle_filter(pf_, config.filter);
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
  const RangeInnovations& innovations() const { return innovations_; }
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
    std::vector<Eigen::Vector2d> cos_sin(n);  // of each particle's heading before the step
    std::size_t i = 0;
    for (const auto& p : m_particles) {
      x_bar[i] = compose(p.d, u_.delta);
      log_w[i] = p.log_w;
      cos_sin[i] = Eigen::Vector2d(std::cos(p.d(kPoseYaw)), std::sin(p.d(kPoseYaw)));
      ++i;
    }
    const std::vector<double> w = normalized_weights(log_w);
    Eigen::Vector4d mean;
    Eigen::Matrix4d cov;
    pose_moments(x_bar, w, mean, cov);
    // E_w[G_i Sigma_u G_i^T] from the weighted moments of cos and sin (rotated_mean()).
    Eigen::Matrix<double, 5, 1> trig = Eigen::Matrix<double, 5, 1>::Zero();  // E c, E s, E c^2, E s^2, E cs
    for (std::size_t k = 0; k < n; ++k) {
      const double c = cos_sin[k](0);
      const double sn = cos_sin[k](1);
      trig += w[k] * Eigen::Matrix<double, 5, 1>(c, sn, c * c, sn * sn, c * sn);
    }
    cov += rotated_mean(u_.cov, trig);
    const RangeUpdatePlan plan = plan_range_update(config_, beacons_, scans_ ? *scans_ : std::vector<BeaconRangeScan>{},
                                                   mean, cov, consecutive_gated_, counters_);
    verdict_ = plan.verdict;
    innovations_ = plan.innovations;

    if (plan.verdict != RangeEpochVerdict::kFuse) {
      // Motion model: sample the increment, compose in the robot frame.
      const Eigen::Matrix4d L_u = u_.cov.llt().matrixL();
      for (auto& p : m_particles) p.d = compose(p.d, u_.delta + L_u * normal4());
      if (plan.verdict == RangeEpochVerdict::kReset) redraw_positions(*plan.reset_fix, plan.reset_sensor_on_robot_m);
      return;
    }
    // Optimal proposal per particle, linearised once at the predicted mean (optimal_proposal.h).
    const Eigen::Matrix4d W_u = u_.cov.llt().solve(Eigen::Matrix4d::Identity());
    const WhitenedRanges measurement{&plan.fuse};
    const Eigen::Matrix4d G_hat =
        compose_jacobian_increment(Eigen::Vector4d(0.0, 0.0, 0.0, mean(kPoseYaw) - u_.delta(kPoseYaw)));
    const OptimalProposal<4, WhitenedRanges> proposal(measurement, mean, G_hat * W_u * G_hat.transpose());
    i = 0;
    for (auto& p : m_particles) {
      const Eigen::Matrix4d W = rotate_xy(W_u, cos_sin[i](0), cos_sin[i](1));  // G_i W_u G_i^T
      Eigen::Vector4d x;
      p.log_w += proposal.sample(x_bar[i], W, normal4(), x);
      x(kPoseYaw) = wrap_near_rad(x(kPoseYaw));
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
    poses.reserve(m_particles.size());
    for (const auto& p : m_particles) poses.push_back(p.d);
    pose_moments(poses, normalized_weights(log_weights(m_particles)), mean, cov);
  }

  void resample() {
    Eigen::Vector4d mean;
    Eigen::Matrix4d cov;
    current_moments(mean, cov);
    resample_particles(*this, config_.filter.resampling, rng_, counters_);
    const double h = config_.filter.regularization_bandwidth;
    if (h <= 0.0) return;
    // Liu-West jitter (position/particle_filter.h), deviations about the (circular) mean.
    make_spd<4>(cov, config_.filter.min_variance_m2, fallback_variance_m2(config_.filter));
    const Eigen::Matrix4d L = cov.llt().matrixL();
    const double a = std::sqrt(1.0 - h * h);
    for (auto& p : m_particles) {
      Eigen::Vector4d x = mean + a * deviation(p.d, mean) + h * (L * normal4());
      x(kPoseYaw) = wrap_near_rad(x(kPoseYaw));
      p.d = x;
    }
  }

  void update_belief() {
    current_moments(belief_.mean, belief_.cov);
    repair_covariance<4>(belief_.mean, belief_.cov, config_.filter, counters_);
    apply_health(config_, epochs_since_beacon_, belief_);
  }

  PoseFilterConfig config_;
  BeaconMap beacons_;
  mrpt::bayes::CParticleFilter pf_;
  mrpt::random::CRandomGenerator rng_;
  FilterCounters counters_;
  RangeInnovations innovations_;
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
const RangeInnovations& ParticlePoseFilter::last_innovations() const { return pf_->innovations(); }
int ParticlePoseFilter::num_particles() const { return pf_->num_particles(); }
double ParticlePoseFilter::last_normalized_ess() const { return pf_->last_normalized_ess(); }

}  // namespace losmimo::localization
