#pragma once
// A synthetic range-only track with known truth and the EKF's beliefs along it, for the range
// smoother's tests and benchmark (fusion/range_smoother.h): a robot driving 1.5 laps of a 6.25 m
// circle among four beacons, ranges every frame (0.1 m), MRPT's default Gaussian odometry noise,
// the UWB demo's sensor offset. Seeded.
#include <cstdint>
#include <vector>

#include "losmimo/fusion/range_smoother.h"
#include "losmimo/localization/pose/initial_pose.h"
#include "losmimo/localization/pose/simulator.h"

namespace losmimo::test_support {

struct Synthetic {
  std::vector<Eigen::Vector4d> truth;
  std::vector<fusion::SmootherFrame> frames;  // with the EKF's beliefs
};

inline constexpr int kSteps = 240;
inline const Eigen::Vector4d kTrueIncrement(0.25, 0.0, 0.0, 0.04);

inline localization::BeaconMap four_beacons() {
  localization::BeaconMap map;
  map.add(1, {0.0, 0.0, 1.0});
  map.add(2, {10.0, 0.0, 2.0});
  map.add(3, {10.0, 16.0, 0.5});
  map.add(4, {0.0, 16.0, 1.5});
  return map;
}

inline localization::PoseFilterConfig filter_config() {
  localization::PoseFilterConfig c;
  c.use_observation_std = true;
  return c;
}

inline Synthetic simulate(std::uint64_t seed, double outlier_fraction) {
  localization::RangeSimulatorConfig sc;
  sc.sigma_range_m = 0.1;
  sc.sensor_on_robot_m = Eigen::Vector3d(0.16, 0.0, 1.12);
  sc.outlier_fraction = outlier_fraction;
  sc.outlier_sigma_range_m = 2.0;
  localization::RangeSensorSimulator sim(sc, four_beacons(), seed);
  Synthetic s;
  Eigen::Vector4d x(5.0, 2.0, 0.0, 0.0);
  localization::PoseBelief start;
  start.mean = x;
  start.cov = Eigen::Vector4d(0.01, 0.01, 1e-6, 1e-3).asDiagonal();
  auto ekf = localization::make_pose_filter(localization::FilterKind::kEkf, filter_config(), four_beacons(),
                                            localization::initial_pose(localization::PosePrior(start)), seed);
  s.truth.push_back(x);
  s.frames.push_back({{}, {}, ekf->belief()});
  for (int k = 1; k < kSteps; ++k) {
    x = localization::compose(x, kTrueIncrement);
    fusion::SmootherFrame f;
    f.odometry = sim.measure_odometry(kTrueIncrement);
    if (auto scan = sim.measure_ranges(x, k)) f.scans.push_back(*scan);
    ekf->step(f.odometry, f.scans);
    f.filter_belief = ekf->belief();
    s.truth.push_back(x);
    s.frames.push_back(f);
  }
  return s;
}

}  // namespace losmimo::test_support
