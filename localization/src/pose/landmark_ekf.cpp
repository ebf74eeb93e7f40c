// The EKF of landmark_filter.h through mrpt::bayes::CKalmanFilterCapable<6, 3, 0, 6>: state the
// 6-D pose, one bearing-range reading per update iteration (sequential updates), action the
// odometry increment.
#include <mrpt/bayes/CKalmanFilterCapable.h>

#include "losmimo/localization/filter_health.h"
#include "losmimo/localization/kalman.h"
#include "losmimo/localization/pose/landmark_filter.h"
#include "losmimo/localization/range_az_el.h"

namespace losmimo::localization {

namespace {

constexpr size_t kStateSize = 6;
constexpr size_t kObsSize = 3;  // (range, azimuth, elevation)
constexpr size_t kFeatSize = 0;
constexpr size_t kActionSize = 6;
constexpr double kMinVariance = 1e-18;  // floor of the covariance's eigenvalues

class LandmarkEkf final : public LandmarkPoseFilter,
                          public mrpt::bayes::CKalmanFilterCapable<kStateSize, kObsSize, kFeatSize, kActionSize> {
 public:
  LandmarkEkf(const LandmarkFilterConfig& config, const BeaconMap& landmarks, const LandmarkBelief& start)
      : config_(config), landmarks_(landmarks) {
    configure_ekf(KF_options);
    m_xkk.resize(kStateSize);
    m_pkk.setSize(kStateSize, kStateSize);
    LandmarkBelief b = start;
    if (config_.planar) make_planar(b);
    set_state(b);
  }

  void step(const OdometryIncrement6& odometry, const std::vector<BearingScan>& scans) override {
    ++counters_.frames;
    u_ = odometry;
    predict_ = true;
    reading_ = nullptr;
    runOneKalmanIteration();
    predict_ = false;
    finish();
    const std::vector<AssociatedReading> fuse = associate(config_, landmarks_, scans, belief(), counters_);
    for (const AssociatedReading& r : fuse) {
      reading_ = &r;
      runOneKalmanIteration();
      finish();
    }
    reading_ = nullptr;
  }

  LandmarkBelief belief() const override {
    LandmarkBelief b;
    for (size_t i = 0; i < kStateSize; ++i) b.mean(static_cast<Eigen::Index>(i)) = m_xkk[i];
    b.cov = m_pkk.asEigen();
    return b;
  }

  const LandmarkCounters& counters() const override { return counters_; }

 protected:
  void OnGetAction(KFArray_ACT& out_u) const override {
    for (size_t i = 0; i < kActionSize; ++i) out_u[i] = u_.delta(static_cast<Eigen::Index>(i));
  }

  void OnTransitionModel(const KFArray_ACT& in_u, KFArray_VEH& inout_x, bool& out_skipPrediction) const override {
    out_skipPrediction = !predict_;
    if (!predict_) return;
    Pose6 x, u;
    for (size_t i = 0; i < kStateSize; ++i) {
      x(static_cast<Eigen::Index>(i)) = inout_x[i];
      u(static_cast<Eigen::Index>(i)) = in_u[i];
    }
    const Pose6 next = compose_pose6(x, u);
    for (size_t i = 0; i < kStateSize; ++i) inout_x[i] = next(static_cast<Eigen::Index>(i));
  }

  // Called with m_xkk still the previous estimate (MRPT evaluates F and Q before storing x').
  void OnTransitionJacobian(KFMatrix_VxV& out_F) const override {
    Matrix6d F;
    compose_pose6(belief().mean, u_.delta, &F, nullptr);
    out_F = KFMatrix_VxV(F);
  }

  void OnTransitionNoise(KFMatrix_VxV& out_Q) const override {
    out_Q = KFMatrix_VxV(odometry_noise(config_, belief().mean, u_));
  }

  void OnGetObservationNoise(KFMatrix_OxO& out_R) const override {
    out_R.setZero();
    const Eigen::Vector3d s = reading_ ? reading_->sigma : Eigen::Vector3d::Ones();
    for (size_t i = 0; i < kObsSize; ++i)
      out_R(i, i) = s(static_cast<Eigen::Index>(i)) * s(static_cast<Eigen::Index>(i));
  }

  void OnObservationModel(const std::vector<size_t>& /*idx_landmarks_to_predict*/,
                          vector_KFArray_OBS& out_predictions) const override {
    out_predictions.resize(1);  // FEAT_SIZE = 0: one prediction for the whole observation
    out_predictions[0].setZero();
    if (!reading_) return;
    const Eigen::Vector3d h = landmark_predict(belief().mean, reading_->sensor_on_robot, reading_->landmark_m);
    for (size_t i = 0; i < kObsSize; ++i) out_predictions[0][i] = h(static_cast<Eigen::Index>(i));
  }

  void OnObservationJacobians(size_t /*idx_landmark_to_predict*/, KFMatrix_OxV& Hx,
                              KFMatrix_OxF& /*Hy*/) const override {
    Hx.setZero();
    if (!reading_) return;
    Matrix36d H;
    landmark_predict(belief().mean, reading_->sensor_on_robot, reading_->landmark_m, &H);
    Hx = KFMatrix_OxV(H);
  }

  void OnSubstractObservationVectors(KFArray_OBS& A, const KFArray_OBS& B) const override {
    const Eigen::Vector3d d =
        range_az_el_innovation(Eigen::Vector3d(A[0], A[1], A[2]), Eigen::Vector3d(B[0], B[1], B[2]));
    for (size_t i = 0; i < kObsSize; ++i) A[i] = d(static_cast<Eigen::Index>(i));
  }

  void OnGetObservationsAndDataAssociation(vector_KFArray_OBS& out_z, std::vector<int>& out_data_association,
                                           const vector_KFArray_OBS& /*in_all_predictions*/, const KFMatrix& /*in_S*/,
                                           const std::vector<size_t>& /*in_lm_indices_in_S*/,
                                           const KFMatrix_OxO& /*in_R*/) override {
    out_z.clear();
    out_data_association.clear();  // must stay empty when FEAT_SIZE = 0
    if (!reading_) return;
    KFArray_OBS z;
    for (size_t i = 0; i < kObsSize; ++i) z[i] = reading_->z(static_cast<Eigen::Index>(i));
    out_z.push_back(z);
  }

 private:
  void set_state(const LandmarkBelief& b) {
    for (size_t i = 0; i < kStateSize; ++i) m_xkk[i] = b.mean(static_cast<Eigen::Index>(i));
    m_pkk.asEigen() = b.cov;
  }

  // After every iteration: angles normalised as CPose3D, the planar constraint, a symmetric
  // covariance with eigenvalues >= kMinVariance.
  void finish() {
    LandmarkBelief b = belief();
    b.mean = compose_pose6(b.mean, Pose6::Zero());
    if (config_.planar) {
      b.cov = 0.5 * (b.cov + b.cov.transpose()).eval();
      make_planar(b);  // exact zeros in z, pitch, roll: no eigenvalue floor there
    } else if (make_spd<6>(b.cov, kMinVariance, 1.0)) {
      ++counters_.covariance_repairs;
    }
    set_state(b);
  }

  LandmarkFilterConfig config_;
  BeaconMap landmarks_;
  LandmarkCounters counters_;
  OdometryIncrement6 u_;
  bool predict_ = true;
  const AssociatedReading* reading_ = nullptr;
};

}  // namespace

std::unique_ptr<LandmarkPoseFilter> make_landmark_ekf(const LandmarkFilterConfig& config, const BeaconMap& landmarks,
                                                      const LandmarkBelief& start) {
  return std::make_unique<LandmarkEkf>(config, landmarks, start);
}

}  // namespace losmimo::localization
