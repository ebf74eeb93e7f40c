// The robustness rules one by one (robustness.h) and input validation (filter.h,
// position/simulator.h).

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "losmimo/localization/position/beacon_model.h"
#include "losmimo/localization/position/filter.h"
#include "losmimo/localization/position/robustness.h"
#include "losmimo/localization/position/simulator.h"

namespace losmimo::localization {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Expects `fn` to throw std::invalid_argument whose message names `field`.
template <typename Fn>
void expect_invalid(Fn fn, const std::string& field) {
  try {
    fn();
    ADD_FAILURE() << "no exception for " << field;
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr(field));
  }
}

TEST(MakeSpd, SpdMatrix_IsLeftUntouched) {
  Eigen::Matrix3d P;
  P << 2.0, 0.5, 0.1, 0.5, 1.0, 0.2, 0.1, 0.2, 0.5;
  const Eigen::Matrix3d before = P;
  EXPECT_FALSE(make_spd(P, 1e-10, 1.0));
  EXPECT_EQ(P, before);
}

TEST(MakeSpd, IndefiniteAndAsymmetric_BecomesSymmetricWithFlooredEigenvalues) {
  Eigen::Matrix3d P;
  P << 1.0, 2.0, 0.0, 2.1, 1.0, 0.0, 0.0, 0.0, -1.0;  // eigenvalues ~3.05, -1.05, -1
  constexpr double kFloor = 1e-6;
  EXPECT_TRUE(make_spd(P, kFloor, 1.0));
  EXPECT_EQ(P, P.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(P);
  EXPECT_GE(eig.eigenvalues().minCoeff(), kFloor * (1.0 - 1e-9));
}

TEST(MakeSpd, NonFinite_BecomesFallback) {
  Eigen::Matrix3d P = Eigen::Matrix3d::Identity();
  P(0, 1) = kNaN;
  EXPECT_TRUE(make_spd(P, 1e-10, 4.0));
  EXPECT_EQ(P, 4.0 * Eigen::Matrix3d::Identity());
}

TEST(Mahalanobis2, MatchesExplicitInverse) {
  Eigen::Matrix3d S;
  S << 3.0, 0.4, 0.2, 0.4, 2.0, 0.1, 0.2, 0.1, 1.0;
  const Eigen::Vector3d y(0.3, -1.2, 0.7);
  EXPECT_NEAR(mahalanobis2(y, S), y.dot(S.inverse() * y), 1e-12);
  EXPECT_EQ(mahalanobis2(y, -S), kInf);  // not SPD: never passes a gate
}

TEST(DisplacementSigma, FloorPlusFraction_WithNoiseFloor) {
  FilterConfig config;
  EXPECT_DOUBLE_EQ(displacement_sigma_m(config, 2.0), 0.01 + 0.02 * 2.0);
  config.noise.dr_sigma_floor_m = 0.0;
  config.noise.dr_sigma_fraction = 0.0;
  EXPECT_DOUBLE_EQ(displacement_sigma_m(config, 2.0), config.min_sigma_displacement_m);
}

class ScreenBeacon : public ::testing::Test {
 protected:
  FilterConfig config;
  FilterCounters counters;
  int consecutive = 0;
  Eigen::Vector3d mean_m{1000.0, 0.0, 0.0};
  Eigen::Matrix3d cov_m2 = 0.01 * Eigen::Matrix3d::Identity();

  BeaconVerdict screen(const Eigen::Vector3d& true_q_m) {
    return screen_beacon(config, to_measurement(beacon_predict(true_q_m)), mean_m, cov_m2, consecutive, counters);
  }
};

TEST_F(ScreenBeacon, NoBeacon_CountsNothing) {
  EXPECT_EQ(screen_beacon(config, std::nullopt, mean_m, cov_m2, consecutive, counters), BeaconVerdict::kNone);
  EXPECT_EQ(counters.beacons_received, 0);
}

TEST_F(ScreenBeacon, NonFiniteOrNonPositiveRange_RejectedAndCounted) {
  for (const double bad : {kNaN, kInf, -kInf}) {
    BeaconMeasurement z = to_measurement(beacon_predict(mean_m));
    z.elevation_rad = bad;
    EXPECT_EQ(screen_beacon(config, z, mean_m, cov_m2, consecutive, counters), BeaconVerdict::kNonFinite);
  }
  BeaconMeasurement z = to_measurement(beacon_predict(mean_m));
  z.range_m = -1.0;
  EXPECT_EQ(screen_beacon(config, z, mean_m, cov_m2, consecutive, counters), BeaconVerdict::kNonFinite);
  EXPECT_EQ(counters.rejected_non_finite_beacon, 4);
  EXPECT_EQ(counters.beacons_received, 4);
  EXPECT_EQ(counters.beacons_fused, 0);
}

TEST_F(ScreenBeacon, PredictionAboveArray_RejectedForGeometry) {
  mean_m = Eigen::Vector3d(0.1, 0.1, 500.0);
  EXPECT_EQ(screen(mean_m), BeaconVerdict::kGeometry);
  EXPECT_EQ(counters.rejected_geometry, 1);
}

TEST_F(ScreenBeacon, GateThreshold_SeparatesNearFromFar) {
  // S ~ (0.01 + 0.01) I per axis in metres at 1 km, so a 0.3 m offset is d2 ~ 4.5 and a
  // 1 m offset is d2 ~ 50 > 16.27.
  EXPECT_EQ(screen(mean_m + Eigen::Vector3d(0.0, 0.3, 0.0)), BeaconVerdict::kFuse);
  EXPECT_EQ(screen(mean_m + Eigen::Vector3d(0.0, 1.0, 0.0)), BeaconVerdict::kGated);
  EXPECT_EQ(counters.rejected_gate, 1);
  EXPECT_EQ(counters.beacons_fused, 1);
  config.gate_enabled = false;
  EXPECT_EQ(screen(mean_m + Eigen::Vector3d(0.0, 1.0, 0.0)), BeaconVerdict::kFuse);
}

TEST_F(ScreenBeacon, ConsecutiveRejections_TriggerResetThenStartOver) {
  config.reset_after_rejections = 3;
  const Eigen::Vector3d far_m = mean_m + Eigen::Vector3d(0.0, 10.0, 0.0);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(screen(far_m), BeaconVerdict::kGated);
  EXPECT_EQ(screen(far_m), BeaconVerdict::kReset);
  EXPECT_EQ(counters.resets, 1);
  EXPECT_EQ(consecutive, 0);
  EXPECT_EQ(screen(far_m), BeaconVerdict::kGated);  // counting starts over
  config.reset_after_rejections = 0;                // never reset
  for (int i = 0; i < 10; ++i) EXPECT_EQ(screen(far_m), BeaconVerdict::kGated);
}

TEST_F(ScreenBeacon, RangeAboveTheLimit_RejectedAsOutOfRange_NeverTowardsAReset) {
  // GIVEN: two gate rejections in a row already, and a reset due at the third.
  config.reset_after_rejections = 3;
  const Eigen::Vector3d far_m = mean_m + Eigen::Vector3d(0.0, 10.0, 0.0);
  for (int i = 0; i < 2; ++i) ASSERT_EQ(screen(far_m), BeaconVerdict::kGated);
  const double limit_m = config.max_beacon_range_m;
  for (const double range_m : {1e300, std::nextafter(limit_m, kInf), 2.0 * limit_m}) {
    BeaconMeasurement z = to_measurement(beacon_predict(mean_m));
    z.range_m = range_m;
    // WHEN / THEN: rejected before the gate, however many arrive.
    for (int i = 0; i < 5; ++i) {
      EXPECT_EQ(screen_beacon(config, z, mean_m, cov_m2, consecutive, counters), BeaconVerdict::kOutOfRange)
          << "range_m = " << range_m;
    }
  }
  EXPECT_EQ(counters.rejected_out_of_range_beacon, 15);
  EXPECT_EQ(counters.rejected_gate, 2);
  EXPECT_EQ(counters.resets, 0);
  EXPECT_EQ(counters.beacons_fused, 0);
  EXPECT_EQ(consecutive, 2);  // neither counted nor cleared
  EXPECT_EQ(counters.rejected_total(), 17);
  // The streak of gate rejections goes on where it was.
  EXPECT_EQ(screen(far_m), BeaconVerdict::kGated);
  EXPECT_EQ(screen(far_m), BeaconVerdict::kReset);
}

TEST_F(ScreenBeacon, RangeAtOrJustBelowTheLimit_IsLeftToTheGate) {
  const double limit_m = config.max_beacon_range_m;
  // Far from the belief at 1 km: gated, and counted towards a reset, as any other beacon.
  BeaconMeasurement z = to_measurement(beacon_predict(mean_m));
  z.range_m = std::nextafter(limit_m, 0.0);
  EXPECT_EQ(screen_beacon(config, z, mean_m, cov_m2, consecutive, counters), BeaconVerdict::kGated);
  EXPECT_EQ(consecutive, 1);
  // Where the belief agrees: fused, up to the limit itself.
  for (const double range_m : {std::nextafter(limit_m, 0.0), limit_m}) {
    mean_m = Eigen::Vector3d(range_m, 0.0, 0.0);
    z = to_measurement(beacon_predict(mean_m));
    EXPECT_EQ(screen_beacon(config, z, mean_m, cov_m2, consecutive, counters), BeaconVerdict::kFuse)
        << "range_m = " << range_m;
  }
  EXPECT_EQ(counters.rejected_out_of_range_beacon, 0);
  EXPECT_EQ(counters.rejected_gate, 1);
  EXPECT_EQ(counters.beacons_fused, 2);
}

TEST_F(ScreenBeacon, ElevationOutsideHalfPiAfterWrapping_RejectedAsOutOfRange) {
  constexpr double kHalfPi_rad = 1.57079632679489661923;
  constexpr double kTwoPi_rad = 6.28318530717958647692;
  const BeaconMeasurement nominal = to_measurement(beacon_predict(mean_m));
  for (const double el_rad :
       {std::nextafter(kHalfPi_rad, kInf), -std::nextafter(kHalfPi_rad, kInf), 3.0, -3.0, kTwoPi_rad + 2.0}) {
    BeaconMeasurement z = nominal;
    z.elevation_rad = el_rad;
    EXPECT_FALSE(is_plausible(config, z)) << "elevation_rad = " << el_rad;
    EXPECT_EQ(screen_beacon(config, z, mean_m, cov_m2, consecutive, counters), BeaconVerdict::kOutOfRange)
        << "elevation_rad = " << el_rad;
  }
  EXPECT_EQ(counters.rejected_out_of_range_beacon, 5);
  // The edges and any whole turn are physical: the innovation and the fix wrap them too.
  for (const double el_rad : {kHalfPi_rad, -kHalfPi_rad}) {
    BeaconMeasurement z = nominal;
    z.elevation_rad = el_rad;
    EXPECT_TRUE(is_plausible(config, z)) << "elevation_rad = " << el_rad;
  }
  BeaconMeasurement turned = nominal;
  turned.elevation_rad += kTwoPi_rad;
  turned.azimuth_rad -= 3.0 * kTwoPi_rad;
  EXPECT_EQ(screen_beacon(config, turned, mean_m, cov_m2, consecutive, counters), BeaconVerdict::kFuse);
  EXPECT_EQ(counters.rejected_out_of_range_beacon, 5);
}

TEST(ApplyHealth, EpochsOrCovariance_SetDegraded) {
  FilterConfig config;
  Belief b;
  b.cov_m2 = 0.01 * Eigen::Matrix3d::Identity();
  apply_health(config, config.degraded_after_epochs - 1, b);
  EXPECT_FALSE(b.degraded);
  apply_health(config, config.degraded_after_epochs, b);
  EXPECT_TRUE(b.degraded);
  EXPECT_EQ(b.epochs_since_beacon, config.degraded_after_epochs);
  b.cov_m2(2, 2) = 1.1 * config.degraded_sigma_m * config.degraded_sigma_m;
  apply_health(config, 0, b);
  EXPECT_TRUE(b.degraded);
}

TEST(FilterConfigValidation, BadFields_ThrowNamingTheField) {
  const auto with = [](auto mutate) {
    FilterConfig c;
    mutate(c);
    return [c] { validate(c); };
  };
  expect_invalid(with([](FilterConfig& c) { c.noise.sigma_range_m = -0.1; }), "noise.sigma_range_m = -0.1");
  expect_invalid(with([](FilterConfig& c) { c.noise.sigma_angle_rad = kNaN; }), "noise.sigma_angle_rad");
  expect_invalid(with([](FilterConfig& c) { c.noise.dr_sigma_fraction = kInf; }), "noise.dr_sigma_fraction");
  expect_invalid(with([](FilterConfig& c) { c.num_particles = 0; }), "num_particles = 0");
  expect_invalid(with([](FilterConfig& c) { c.ess_threshold = 0.0; }), "ess_threshold");
  expect_invalid(with([](FilterConfig& c) { c.gate_chi2 = -1.0; }), "gate_chi2");
  expect_invalid(with([](FilterConfig& c) { c.max_beacon_range_m = 0.0; }),
                 "filter.max_beacon_range_m = 0: must be > 0");
  expect_invalid(with([](FilterConfig& c) { c.max_beacon_range_m = -5.0; }), "max_beacon_range_m = -5");
  expect_invalid(with([](FilterConfig& c) { c.max_beacon_range_m = kInf; }), "max_beacon_range_m = inf");
  expect_invalid(with([](FilterConfig& c) { c.max_beacon_range_m = kNaN; }), "max_beacon_range_m = nan");
  expect_invalid(with([](FilterConfig& c) { c.degraded_after_epochs = 0; }), "degraded_after_epochs");
  expect_invalid(with([](FilterConfig& c) { c.min_variance_m2 = 0.0; }), "min_variance_m2");
  expect_invalid(with([](FilterConfig& c) { c.regularization_bandwidth = 1.0; }), "regularization_bandwidth");
  EXPECT_NO_THROW(validate(FilterConfig{}));
}

TEST(FilterConstruction, BadConfigOrBelief_Throws) {
  FilterConfig bad;
  bad.num_particles = -5;
  for (const FilterKind kind : {FilterKind::kEkf, FilterKind::kParticle}) {
    expect_invalid([&] { make_filter(kind, bad, Belief{}, 1); }, "num_particles = -5");
    Belief not_spd;
    not_spd.cov_m2(1, 1) = -1.0;
    expect_invalid([&] { make_filter(kind, FilterConfig{}, not_spd, 1); }, "belief.cov_m2");
    Belief nan_mean;
    nan_mean.mean_m.y() = kNaN;
    expect_invalid([&] { make_filter(kind, FilterConfig{}, nan_mean, 1); }, "belief.mean_m(1)");
  }
  expect_invalid([] { filter_kind_from_string("ukf"); }, "ukf");
  expect_invalid([] { resampling_method_from_string("magic"); }, "magic");
  EXPECT_EQ(resampling_method_from_string("residual"), ResamplingMethod::kResidual);
  EXPECT_EQ(filter_kind_from_string("pf"), FilterKind::kParticle);
}

TEST(SimulatorConfigValidation, BadFields_ThrowNamingTheField) {
  const auto with = [](auto mutate) {
    SimulatorConfig c;
    mutate(c);
    return [c] { SensorSimulator sim(c, 1); };
  };
  expect_invalid(with([](SimulatorConfig& c) { c.sigma_range_m = -1.0; }), "sigma_range_m = -1");
  expect_invalid(with([](SimulatorConfig& c) { c.sigma_angle_rad = kNaN; }), "sigma_angle_rad");
  expect_invalid(with([](SimulatorConfig& c) { c.beacon_period_epochs = 0; }), "beacon_period_epochs = 0");
  expect_invalid(with([](SimulatorConfig& c) { c.outlier_fraction = 1.5; }), "outlier_fraction");
  expect_invalid(with([](SimulatorConfig& c) { c.outages = {{3, -2}}; }), "outages[0].num_epochs");
  expect_invalid(with([](SimulatorConfig& c) { c.dr_sigma_floor_m = kInf; }), "dr_sigma_floor_m");
  expect_invalid(with([](SimulatorConfig& c) { c.sigma_act_m = -0.1; }), "sigma_act_m");
}

}  // namespace
}  // namespace losmimo::localization
