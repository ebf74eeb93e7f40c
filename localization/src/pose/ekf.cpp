#include "losmimo/localization/pose/ekf.h"

#include <mrpt/bayes/CKalmanFilterCapable.h>

#include <algorithm>
#include <cmath>

#include "losmimo/localization/filter_health.h"
#include "losmimo/localization/kalman.h"
#include "losmimo/localization/position/beacon_model.h"
#include "losmimo/localization/pose/initial_pose.h"
#include "losmimo/localization/pose/robustness.h"

namespace losmimo::localization {

namespace {
constexpr size_t kStateSize = 4;   // x = (x, y, z, yaw)
constexpr size_t kFeatSize = 0;    // no map in the state
constexpr size_t kActionSize = 4;  // u = (dx, dy, dz, dyaw)
constexpr size_t kObsSize = kRangesPerUpdate;
constexpr double kIekfTolerance = 1e-10;  // relative step that ends the iterations

// x - lin with the heading difference wrapped.
Eigen::Vector4d pose_delta(const Eigen::Vector4d& x, const Eigen::Vector4d& lin) {
  Eigen::Vector4d d = x - lin;
  d(kPoseYaw) = wrap_angle_rad(d(kPoseYaw));
  return d;
}
}  // namespace

class EkfPoseFilter::Mrpt final
    : public mrpt::bayes::CKalmanFilterCapable<kStateSize, kObsSize, kFeatSize, kActionSize> {
 public:
  Mrpt(const PoseFilterConfig& config, const BeaconMap& beacons, const InitialPose& initial)
      : config_(config), beacons_(beacons) {
    configure_ekf(KF_options);
    m_xkk.resize(kStateSize);
    m_pkk.setSize(kStateSize, kStateSize);
    const PoseBelief start = moments(initial);
    set_state(start.mean, start.cov);
    epochs_since_beacon_ = initial.fix ? 0 : config.filter.degraded_after_epochs;
  }

  void step(const OdometryIncrement& odometry, const std::vector<BeaconRangeScan>& scans) {
    ++counters_.epochs;
    u_ = screen_odometry(config_, odometry, counters_);
    // 1. Prediction only.
    predict_ = true;
    batch_.clear();
    runOneKalmanIteration();
    predict_ = false;
    // 2. Screen against the prediction, then the iterated update, kRangesPerUpdate at a time.
    const RangeUpdatePlan plan =
        plan_range_update(config_, beacons_, scans, mean(), cov(), consecutive_gated_, counters_);
    innovations_ = plan.innovations;
    for (std::size_t first = 0; first < plan.fuse.size(); first += kRangesPerUpdate) {
      const std::size_t last = std::min(plan.fuse.size(), first + kRangesPerUpdate);
      batch_.assign(plan.fuse.begin() + static_cast<std::ptrdiff_t>(first),
                    plan.fuse.begin() + static_cast<std::ptrdiff_t>(last));
      iterated_update();
    }
    batch_.clear();
    if (plan.verdict == RangeEpochVerdict::kReset) reset_position(*plan.reset_fix, plan.reset_sensor_on_robot_m);
    const bool used = plan.verdict == RangeEpochVerdict::kFuse || plan.verdict == RangeEpochVerdict::kReset;
    epochs_since_beacon_ = used ? 0 : epochs_since_beacon_ + 1;
  }

  PoseBelief belief() const {
    PoseBelief b;
    b.mean = mean();
    b.cov = cov();
    apply_health(config_, epochs_since_beacon_, b);
    return b;
  }

  const FilterCounters& counters() const { return counters_; }
  const RangeInnovations& innovations() const { return innovations_; }

 protected:
  void OnGetAction(KFArray_ACT& out_u) const override {
    for (size_t i = 0; i < kActionSize; ++i) out_u[i] = u_.delta(static_cast<Eigen::Index>(i));
  }

  void OnTransitionModel(const KFArray_ACT& in_u, KFArray_VEH& inout_x, bool& out_skipPrediction) const override {
    out_skipPrediction = !predict_;
    if (!predict_) return;
    const Eigen::Vector4d next = compose(Eigen::Vector4d(inout_x[0], inout_x[1], inout_x[2], inout_x[3]),
                                         Eigen::Vector4d(in_u[0], in_u[1], in_u[2], in_u[3]));
    for (size_t i = 0; i < kStateSize; ++i) inout_x[i] = next(static_cast<Eigen::Index>(i));
  }

  // Called with m_xkk still the previous estimate (MRPT evaluates F and Q before storing x').
  void OnTransitionJacobian(KFMatrix_VxV& out_F) const override {
    out_F = KFMatrix_VxV(compose_jacobian_pose(mean(), u_.delta));
  }

  void OnTransitionNoise(KFMatrix_VxV& out_Q) const override {
    const Eigen::Matrix4d G = compose_jacobian_increment(mean());
    out_Q = KFMatrix_VxV(G * u_.cov * G.transpose());
  }

  void OnGetObservationNoise(KFMatrix_OxO& out_R) const override {
    out_R.setIdentity();  // unused slots: any positive variance (their H rows are zero)
    for (std::size_t j = 0; j < batch_.size(); ++j) out_R(j, j) = batch_[j].sigma_m * batch_[j].sigma_m;
  }

  // The linearisation at lin_ expressed at the current estimate x0 (the header's iterate).
  void OnObservationModel(const std::vector<size_t>& /*idx_landmarks_to_predict*/,
                          vector_KFArray_OBS& out_predictions) const override {
    out_predictions.resize(1);  // FEAT_SIZE = 0: one prediction for the whole observation
    KFArray_OBS& h = out_predictions[0];
    h.setZero();
    const Eigen::Vector4d step = pose_delta(mean(), lin_);
    for (std::size_t j = 0; j < batch_.size(); ++j) {
      const UsableRange& r = batch_[j];
      h[j] = range_predict(lin_, r.sensor_on_robot_m, r.beacon_m) +
             range_jacobian(lin_, r.sensor_on_robot_m, r.beacon_m).dot(step);
    }
  }

  void OnObservationJacobians(size_t /*idx_landmark_to_predict*/, KFMatrix_OxV& Hx,
                              KFMatrix_OxF& /*Hy*/) const override {
    Hx.setZero();
    for (std::size_t j = 0; j < batch_.size(); ++j) {
      const Eigen::RowVector4d H = range_jacobian(lin_, batch_[j].sensor_on_robot_m, batch_[j].beacon_m);
      for (size_t i = 0; i < kStateSize; ++i) Hx(j, i) = H(static_cast<Eigen::Index>(i));
    }
  }

  void OnGetObservationsAndDataAssociation(vector_KFArray_OBS& out_z, std::vector<int>& out_data_association,
                                           const vector_KFArray_OBS& in_all_predictions, const KFMatrix& /*in_S*/,
                                           const std::vector<size_t>& /*in_lm_indices_in_S*/,
                                           const KFMatrix_OxO& /*in_R*/) override {
    out_z.clear();
    out_data_association.clear();  // must stay empty when FEAT_SIZE = 0
    if (batch_.empty()) return;
    KFArray_OBS z = in_all_predictions[0];  // unused slots: innovation 0
    for (std::size_t j = 0; j < batch_.size(); ++j) z[j] = batch_[j].range_m;
    out_z.push_back(z);
  }

  void OnPostIteration() override {
    if (!batch_.empty()) {
      // Joseph form from the covariance before the update, with the H and R of this iteration
      // (fixed size; unused rows: H = 0, R = 1, which change nothing).
      Eigen::Matrix<double, kObsSize, kStateSize> H = Eigen::Matrix<double, kObsSize, kStateSize>::Zero();
      Eigen::Matrix<double, kObsSize, 1> R = Eigen::Matrix<double, kObsSize, 1>::Ones();
      for (std::size_t j = 0; j < batch_.size(); ++j) {
        H.row(static_cast<Eigen::Index>(j)) = range_jacobian(lin_, batch_[j].sensor_on_robot_m, batch_[j].beacon_m);
        R(static_cast<Eigen::Index>(j)) = batch_[j].sigma_m * batch_[j].sigma_m;
      }
      const Eigen::Matrix<double, kObsSize, kObsSize> S =
          H * P0_ * H.transpose() + Eigen::Matrix<double, kObsSize, kObsSize>(R.asDiagonal());
      const Eigen::Matrix<double, kStateSize, kObsSize> K = S.llt().solve(H * P0_).transpose();  // P H^T S^-1
      const Eigen::Matrix4d A = Eigen::Matrix4d::Identity() - K * H;
      m_pkk.asEigen() = A * P0_ * A.transpose() + K * R.asDiagonal() * K.transpose();
    }
    m_xkk[kPoseYaw] = wrap_angle_rad(m_xkk[kPoseYaw]);
    repair();
  }

 private:
  Eigen::Vector4d mean() const { return {m_xkk[0], m_xkk[1], m_xkk[2], m_xkk[3]}; }
  Eigen::Matrix4d cov() const { return m_pkk.asEigen(); }
  void set_state(const Eigen::Vector4d& mean, const Eigen::Matrix4d& cov) {
    for (size_t i = 0; i < kStateSize; ++i) m_xkk[i] = mean(static_cast<Eigen::Index>(i));
    m_pkk.asEigen() = cov;
  }

  // Gauss-Newton on the prior (x0, P0) and the batch: each MRPT iteration updates (x0, P0)
  // with the model linearised at lin_; lin_ moves to the result until it stops moving.
  void iterated_update() {
    const Eigen::Vector4d x0 = mean();
    P0_ = cov();
    lin_ = x0;
    for (int it = 0; it < kMaxIekfIterations; ++it) {
      set_state(x0, P0_);
      runOneKalmanIteration();
      const Eigen::Vector4d next = mean();
      const double step = pose_delta(next, lin_).norm();
      lin_ = next;
      if (step <= kIekfTolerance * (1.0 + next.norm())) break;
    }
  }

  void repair() {
    Eigen::Matrix4d P = cov();
    repair_covariance<4>(mean(), P, config_.filter, counters_);
    m_pkk.asEigen() = P;
  }

  // The reset of pose/filter.h: position from the fix, heading kept (its mean and variance).
  void reset_position(const RangeFix& fix, const Eigen::Vector3d& sensor_on_robot_m) {
    InitialPose start;
    PoseBelief heading;
    heading.mean = mean();
    heading.cov = cov();
    start.prior = heading;
    start.fix = SensorFix{fix, sensor_on_robot_m};
    const PoseBelief b = moments(start);
    set_state(b.mean, b.cov);
    repair();
  }

  PoseFilterConfig config_;
  BeaconMap beacons_;
  FilterCounters counters_;
  RangeInnovations innovations_;
  int epochs_since_beacon_ = 0;
  int consecutive_gated_ = 0;
  // Inputs of the current iteration, read by the MRPT callbacks.
  OdometryIncrement u_;
  bool predict_ = true;
  std::vector<UsableRange> batch_;
  Eigen::Vector4d lin_ = Eigen::Vector4d::Zero();
  Eigen::Matrix4d P0_ = Eigen::Matrix4d::Identity();
};

EkfPoseFilter::EkfPoseFilter(const PoseFilterConfig& config, const BeaconMap& beacons, const InitialPose& initial) {
  validate(config);
  validate(initial.prior);
  kf_ = std::make_unique<Mrpt>(config, beacons, initial);
}

EkfPoseFilter::~EkfPoseFilter() = default;

void EkfPoseFilter::step(const OdometryIncrement& odometry, const std::vector<BeaconRangeScan>& scans) {
  kf_->step(odometry, scans);
}

PoseBelief EkfPoseFilter::belief() const { return kf_->belief(); }

const FilterCounters& EkfPoseFilter::counters() const { return kf_->counters(); }

const RangeInnovations& EkfPoseFilter::last_innovations() const { return kf_->innovations(); }

}  // namespace losmimo::localization
