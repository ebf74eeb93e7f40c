#include "losmimo/localization/position/ekf.h"

#include <mrpt/bayes/CKalmanFilterCapable.h>

#include <Eigen/Cholesky>
#include <cmath>

#include "losmimo/localization/filter_health.h"
#include "losmimo/localization/kalman.h"
#include "losmimo/localization/position/beacon_model.h"
#include "losmimo/localization/position/robustness.h"

namespace losmimo::localization {

namespace {
constexpr size_t kStateSize = 3;   // q = (x, y, z)
constexpr size_t kObsSize = 3;     // z = (r, az, el)
constexpr size_t kFeatSize = 0;    // no map: a plain (non-SLAM) filter
constexpr size_t kActionSize = 3;  // d = measured displacement
// A Jacobian row is not evaluated closer than this to the z axis (rho^2 in the denominator);
// such beacons are rejected by screen_beacon anyway.
constexpr double kMinJacobianRho_m = 1e-9;
}  // namespace

class EkfPositionFilter::Mrpt final
    : public mrpt::bayes::CKalmanFilterCapable<kStateSize, kObsSize, kFeatSize, kActionSize> {
 public:
  Mrpt(const FilterConfig& config, const Belief& initial)
      : config_(config), epochs_since_beacon_(initial.epochs_since_beacon) {
    configure_ekf(KF_options);
    m_xkk.resize(kStateSize);
    m_pkk.setSize(kStateSize, kStateSize);
    set_state(initial.mean_m, initial.cov_m2);
  }

  void step(const Eigen::Vector3d& measured_displacement_m, const std::optional<BeaconMeasurement>& beacon) {
    ++counters_.epochs;
    const ScreenedDisplacement d = screen_displacement(config_, measured_displacement_m, counters_);
    u_m_ = d.u_m;
    sigma_q_m_ = d.sigma_m;
    beacon_ = beacon;
    verdict_ = BeaconVerdict::kNone;
    runOneKalmanIteration();
    const bool used_beacon = verdict_ == BeaconVerdict::kFuse || verdict_ == BeaconVerdict::kReset;
    epochs_since_beacon_ = used_beacon ? 0 : epochs_since_beacon_ + 1;
  }

  Belief belief() const {
    Belief b;
    b.mean_m = mean_m();
    b.cov_m2 = cov_m2();
    apply_health(config_, epochs_since_beacon_, b);
    return b;
  }

  const FilterCounters& counters() const { return counters_; }

 protected:
  void OnGetAction(KFArray_ACT& out_u) const override {
    for (size_t i = 0; i < kActionSize; ++i) out_u[i] = u_m_(static_cast<Eigen::Index>(i));
  }

  void OnTransitionModel(const KFArray_ACT& in_u, KFArray_VEH& inout_x, bool& out_skipPrediction) const override {
    for (size_t i = 0; i < kStateSize; ++i) inout_x[i] += in_u[i];
    out_skipPrediction = false;
  }

  void OnTransitionJacobian(KFMatrix_VxV& out_F) const override { out_F.setIdentity(); }

  void OnTransitionNoise(KFMatrix_VxV& out_Q) const override {
    out_Q.setZero();
    for (size_t i = 0; i < kStateSize; ++i) out_Q(i, i) = sigma_q_m_ * sigma_q_m_;
  }

  void OnGetObservationNoise(KFMatrix_OxO& out_R) const override { out_R = KFMatrix_OxO(floored_beacon_cov(config_)); }

  void OnObservationModel(const std::vector<size_t>& /*idx_landmarks_to_predict*/,
                          vector_KFArray_OBS& out_predictions) const override {
    // FEAT_SIZE = 0: MRPT asks for N_map = 0 landmarks but expects exactly one prediction.
    const Eigen::Vector3d z_pred = beacon_predict(mean_m());
    out_predictions.resize(1);
    for (size_t i = 0; i < kObsSize; ++i) out_predictions[0][i] = z_pred(static_cast<Eigen::Index>(i));
  }

  void OnObservationJacobians(size_t /*idx_landmark_to_predict*/, KFMatrix_OxV& Hx,
                              KFMatrix_OxF& /*Hy*/) const override {
    const Eigen::Vector3d q_m = mean_m();
    if (std::hypot(q_m.x(), q_m.y()) < kMinJacobianRho_m) {
      Hx.setZero();
      return;
    }
    Hx = KFMatrix_OxV(beacon_jacobian(q_m));
  }

  void OnSubstractObservationVectors(KFArray_OBS& A, const KFArray_OBS& B) const override {
    const Eigen::Vector3d y = beacon_innovation(Eigen::Vector3d(A[0], A[1], A[2]), Eigen::Vector3d(B[0], B[1], B[2]));
    for (size_t i = 0; i < kObsSize; ++i) A[i] = y(static_cast<Eigen::Index>(i));
  }

  void OnGetObservationsAndDataAssociation(vector_KFArray_OBS& out_z, std::vector<int>& out_data_association,
                                           const vector_KFArray_OBS& /*in_all_predictions*/, const KFMatrix& /*in_S*/,
                                           const std::vector<size_t>& /*in_lm_indices_in_S*/,
                                           const KFMatrix_OxO& /*in_R*/) override {
    out_z.clear();
    out_data_association.clear();  // must stay empty when FEAT_SIZE = 0
    // m_xkk / m_pkk hold the prediction here: screen against it, and keep what the Joseph
    // form needs in OnPostIteration.
    P_pred_m2_ = cov_m2();
    verdict_ = screen_beacon(config_, beacon_, mean_m(), P_pred_m2_, consecutive_gated_, counters_);
    if (verdict_ != BeaconVerdict::kFuse) return;
    const Eigen::Vector3d z = to_vector(*beacon_);
    KFArray_OBS z_obs;
    for (size_t i = 0; i < kObsSize; ++i) z_obs[i] = z(static_cast<Eigen::Index>(i));
    out_z.push_back(z_obs);
    H_ = beacon_jacobian(mean_m());
  }

  void OnPostIteration() override {
    if (verdict_ == BeaconVerdict::kFuse) {
      const Eigen::Matrix3d R = floored_beacon_cov(config_);
      const Eigen::Matrix3d S = H_ * P_pred_m2_ * H_.transpose() + R;
      // K = P H^T S^-1, via S K^T = H P (S and P symmetric).
      const Eigen::Matrix3d K = S.llt().solve(H_ * P_pred_m2_).transpose();
      const Eigen::Matrix3d A = Eigen::Matrix3d::Identity() - K * H_;
      m_pkk.asEigen() = A * P_pred_m2_ * A.transpose() + K * R * K.transpose();
    } else if (verdict_ == BeaconVerdict::kReset) {
      const Belief fix = floored_beacon_fix(config_, *beacon_);
      set_state(fix.mean_m, fix.cov_m2);
    }
    Eigen::Matrix3d P = cov_m2();
    repair_covariance<3>(mean_m(), P, config_, counters_);
    m_pkk.asEigen() = P;
  }

 private:
  Eigen::Vector3d mean_m() const { return {m_xkk[0], m_xkk[1], m_xkk[2]}; }
  Eigen::Matrix3d cov_m2() const { return m_pkk.asEigen(); }
  void set_state(const Eigen::Vector3d& mean_m, const Eigen::Matrix3d& cov_m2) {
    for (size_t i = 0; i < kStateSize; ++i) m_xkk[i] = mean_m(static_cast<Eigen::Index>(i));
    m_pkk.asEigen() = cov_m2;
  }

  FilterConfig config_;
  FilterCounters counters_;
  int epochs_since_beacon_ = 0;
  int consecutive_gated_ = 0;
  // Inputs of the current epoch, read by the MRPT callbacks.
  Eigen::Vector3d u_m_ = Eigen::Vector3d::Zero();
  double sigma_q_m_ = 0.0;
  std::optional<BeaconMeasurement> beacon_;
  // Set during the current epoch.
  BeaconVerdict verdict_ = BeaconVerdict::kNone;
  Eigen::Matrix3d P_pred_m2_ = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d H_ = Eigen::Matrix3d::Identity();
};

EkfPositionFilter::EkfPositionFilter(const FilterConfig& config, const Belief& initial) {
  validate(config);
  validate(initial);
  kf_ = std::make_unique<Mrpt>(config, initial);
}

EkfPositionFilter::~EkfPositionFilter() = default;

void EkfPositionFilter::step(const Eigen::Vector3d& measured_displacement_m,
                             const std::optional<BeaconMeasurement>& beacon) {
  kf_->step(measured_displacement_m, beacon);
}

Belief EkfPositionFilter::belief() const { return kf_->belief(); }

const FilterCounters& EkfPositionFilter::counters() const { return kf_->counters(); }

}  // namespace losmimo::localization
