// The landmark pose filters' shared rules (pose/landmark_filter.h): association by ID and by
// gated global nearest neighbour, the planar constraint, and both filters on a simulated run.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "losmimo/localization/pose/landmark_filter.h"
#include "losmimo/localization/range_az_el.h"

namespace losmimo::localization {
namespace {

constexpr double kPi = 3.14159265358979323846;

BeaconMap square_map() {
  BeaconMap m;
  m.add(1, Eigen::Vector3d(5.0, 0.0, 1.0));
  m.add(2, Eigen::Vector3d(0.0, 5.0, -1.0));
  m.add(3, Eigen::Vector3d(-5.0, 0.0, 2.0));
  m.add(4, Eigen::Vector3d(0.0, -5.0, 0.5));
  return m;
}

// An exact scan of `ids` from `robot`; id_in_reading false writes -1 (no identification).
BearingScan exact_scan(const BeaconMap& map, const Pose6& robot, const std::vector<std::int32_t>& ids,
                       bool id_in_reading) {
  BearingScan s;
  s.sigma = Eigen::Vector3d(0.01, 0.002, 0.002);
  for (const std::int32_t id : ids) {
    s.readings.push_back({id_in_reading ? id : -1, landmark_predict(robot, s.sensor_on_robot, *map.find(id))});
  }
  return s;
}

LandmarkBelief tight(const Pose6& mean) {
  LandmarkBelief b;
  b.mean = mean;
  b.cov = 1e-4 * Matrix6d::Identity();
  return b;
}

TEST(LandmarkAssociation, ById_TakesTheMappedLandmarkAndCountsAnUnknownId) {
  const BeaconMap map = square_map();
  BearingScan scan = exact_scan(map, Pose6::Zero(), {1, 3}, true);
  scan.readings.push_back({99, Eigen::Vector3d(3.0, 0.1, 0.0)});
  LandmarkCounters c;
  const auto fused = associate({}, map, {scan}, tight(Pose6::Zero()), c);
  ASSERT_EQ(fused.size(), 2u);
  EXPECT_EQ(fused[0].landmark_id, 1);
  EXPECT_EQ(fused[1].landmark_id, 3);
  EXPECT_EQ(c.unknown_id, 1);
  EXPECT_EQ(c.readings, 3);
  EXPECT_EQ(c.fused, 2);
}

TEST(LandmarkAssociation, NearestNeighbour_FindsEachLandmarkOnceAndGatesAStrayReading) {
  // GIVEN: readings without IDs of landmarks 4, 2, 1 (shuffled) and one pointing at nothing.
  const BeaconMap map = square_map();
  const Pose6 robot = (Pose6() << 0.3, -0.2, 0.1, 0.4, 0.05, -0.03).finished();
  BearingScan scan = exact_scan(map, robot, {4, 2, 1}, false);
  scan.readings.push_back({-1, Eigen::Vector3d(2.0, 2.5, 0.3)});
  LandmarkCounters c;
  // WHEN
  const auto fused = associate({}, map, {scan}, tight(robot), c);
  // THEN: one-to-one, right landmarks, the stray reading gated, no ambiguity.
  ASSERT_EQ(fused.size(), 3u);
  std::vector<std::int32_t> ids;
  for (const auto& r : fused) ids.push_back(r.landmark_id);
  std::sort(ids.begin(), ids.end());
  EXPECT_EQ(ids, (std::vector<std::int32_t>{1, 2, 4}));
  EXPECT_EQ(c.gated, 1);
  EXPECT_EQ(c.ambiguous, 0);
  // AND: each reading carries its own landmark (the one whose exact prediction it is).
  for (const auto& r : fused) {
    EXPECT_LT(range_az_el_innovation(r.z, landmark_predict(robot, Pose6::Zero(), r.landmark_m)).norm(), 1e-12);
  }
}

TEST(LandmarkAssociation, NearestNeighbour_TwoLandmarksInsideOneGateAreCountedAmbiguous) {
  BeaconMap map;
  map.add(1, Eigen::Vector3d(5.0, 0.0, 0.0));
  map.add(2, Eigen::Vector3d(5.0, 0.01, 0.0));  // 1 cm apart, 5 m away: both inside a wide prior's gate
  const BearingScan scan = exact_scan(map, Pose6::Zero(), {1}, false);
  LandmarkCounters c;
  LandmarkBelief wide = tight(Pose6::Zero());
  wide.cov = 0.01 * Matrix6d::Identity();
  const auto fused = associate({}, map, {scan}, wide, c);
  ASSERT_EQ(fused.size(), 1u);
  EXPECT_EQ(fused[0].landmark_id, 1);  // the nearer in Mahalanobis distance
  EXPECT_EQ(c.ambiguous, 1);
}

// A circle at 0.1 m per frame with exact odometry readings and noisy bearing-range readings.
struct SimRun {
  std::vector<Pose6> truth;
  std::vector<OdometryIncrement6> odometry;
  std::vector<std::vector<BearingScan>> scans;
};

SimRun simulate(const BeaconMap& map, bool planar, int frames) {
  std::mt19937_64 rng(17);
  std::normal_distribution<double> n(0.0, 1.0);
  SimRun run;
  Pose6 x = Pose6::Zero();
  Pose6 step;
  step << 0.1, 0.0, planar ? 0.0 : 0.01, 0.05, planar ? 0.0 : 0.01, planar ? 0.0 : -0.01;
  for (int k = 0; k < frames; ++k) {
    OdometryIncrement6 u;
    if (k > 0) {
      u.cov = Matrix6d(Pose6::Constant(1e-4).asDiagonal());
      x = compose_pose6(x, step);
      u.delta = step;
      for (int i = 0; i < 6; ++i) u.delta(i) += 0.01 * n(rng);
    }
    BearingScan s = exact_scan(map, x, {1, 2, 3, 4}, true);
    for (auto& r : s.readings) {
      r.z(0) += 0.01 * n(rng);
      r.z(1) += 0.002 * n(rng);
      r.z(2) += planar ? 0.0 : 0.002 * n(rng);
    }
    run.truth.push_back(x);
    run.odometry.push_back(u);
    run.scans.push_back({s});
  }
  return run;
}

double position_rmse(LandmarkPoseFilter& f, const SimRun& run, bool check_planar) {
  double e2 = 0.0;
  for (std::size_t k = 0; k < run.truth.size(); ++k) {
    f.step(run.odometry[k], run.scans[k]);
    const LandmarkBelief b = f.belief();
    e2 += (b.mean.head<3>() - run.truth[k].head<3>()).squaredNorm();
    if (check_planar) {
      EXPECT_EQ(b.mean(kP6Z), 0.0);
      EXPECT_EQ(b.mean(kP6Pitch), 0.0);
      EXPECT_EQ(b.mean(kP6Roll), 0.0);
    }
  }
  return std::sqrt(e2 / static_cast<double>(run.truth.size()));
}

TEST(LandmarkFilters, SimulatedCircle_EkfAndParticleFilterTrackToCentimetresAndAgree) {
  // Odometry alone drifts by ~1 cm per frame (its noise); the readings pin the pose.
  const BeaconMap map = square_map();
  for (const bool planar : {true, false}) {
    const SimRun run = simulate(map, planar, 60);
    LandmarkFilterConfig config;
    config.planar = planar;
    config.num_particles = 50;
    LandmarkBelief start;
    start.cov.setZero();
    const auto ekf = make_landmark_filter(FilterKind::kEkf, config, map, start, 1);
    const auto pf = make_landmark_filter(FilterKind::kParticle, config, map, start, 1);
    const double ekf_rmse = position_rmse(*ekf, run, planar);
    const double pf_rmse = position_rmse(*pf, run, planar);
    EXPECT_LT(ekf_rmse, 0.02) << "planar " << planar;
    EXPECT_LT(pf_rmse, 0.02) << "planar " << planar;
    EXPECT_LT((ekf->belief().mean - pf->belief().mean).head<3>().norm(), 0.02);
    // Consistency: mean NIS of the fused readings near its 3 dof (2 when planar: the elevation
    // carries nothing).
    const double nis = ekf->counters().nis_sum / static_cast<double>(ekf->counters().fused);
    EXPECT_GT(nis, planar ? 1.0 : 1.5);
    EXPECT_LT(nis, planar ? 3.0 : 4.5);
  }
}

TEST(LandmarkFilters, ParticleFilter_SameSeedSameBitsEveryFrame_OtherSeedOtherBeliefs) {
  // 200 particles: the proposals run split over two threads on a machine with two cores; the
  // beliefs must not depend on which thread finishes first.
  const BeaconMap map = square_map();
  const SimRun run = simulate(map, false, 30);
  LandmarkFilterConfig config;
  config.num_particles = 200;
  LandmarkBelief start;
  start.cov = Matrix6d(Pose6::Constant(1e-4).asDiagonal());
  const auto a = make_landmark_filter(FilterKind::kParticle, config, map, start, 7);
  const auto b = make_landmark_filter(FilterKind::kParticle, config, map, start, 7);
  const auto c = make_landmark_filter(FilterKind::kParticle, config, map, start, 8);
  bool c_differs = false;
  for (std::size_t k = 0; k < run.truth.size(); ++k) {
    for (const auto* f : {&a, &b, &c}) (*f)->step(run.odometry[k], run.scans[k]);
    const LandmarkBelief ba = a->belief(), bb = b->belief(), bc = c->belief();
    ASSERT_EQ(std::memcmp(ba.mean.data(), bb.mean.data(), sizeof(double) * 6), 0) << "frame " << k;
    ASSERT_EQ(std::memcmp(ba.cov.data(), bb.cov.data(), sizeof(double) * 36), 0) << "frame " << k;
    c_differs = c_differs || ba.mean != bc.mean;
  }
  EXPECT_TRUE(c_differs);
  EXPECT_LT((a->belief().mean.head<3>() - run.truth.back().head<3>()).norm(), 0.05);
}

TEST(LandmarkFilters, BadConfig_IsRefusedNamingTheField) {
  LandmarkFilterConfig config;
  config.gate_chi2 = -1.0;
  try {
    make_landmark_filter(FilterKind::kEkf, config, square_map(), LandmarkBelief{}, 1);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("gate_chi2"), std::string::npos) << e.what();
  }
  (void)kPi;
}

}  // namespace
}  // namespace losmimo::localization
