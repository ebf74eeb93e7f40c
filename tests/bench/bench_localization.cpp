// One filter epoch per vehicle, built with the tests, not run by ctest:
//   bench_localization --benchmark_repetitions=10 --benchmark_report_aggregates_only=true
// - position filters (prediction + BS beacon update), EKF and particle filter with 1000
//   particles, on the nominal 1 km geometry;
// - pose filters (odometry + ranges to 15 beacons, the size of MRPT's RO-SLAM demo), EKF and
//   particle filter with 1000 particles: items_per_second of the PF is particle updates per
//   second. For scale: MRPT's stock pf-localization runs that demo's 99 steps at ~1000
//   particles in ~0.4 s, i.e. ~4 ms per step.

#include <benchmark/benchmark.h>

#include <cstdint>
#include <optional>
#include <vector>

#include "losmimo/localization/position/filter.h"
#include "losmimo/localization/pose/initial_pose.h"
#include "losmimo/localization/pose/filter.h"
#include "losmimo/localization/pose/simulator.h"
#include "losmimo/localization/position/simulator.h"

namespace losmimo::localization {
namespace {

constexpr int kBenchParticles = 1000;
constexpr std::uint64_t kSeed = 7;

// Measurements are simulated before timing: the truth steps back and forth, so replaying the
// kReplayEpochs epochs in a loop keeps the belief in the nominal geometry.
constexpr int kReplayEpochs = 256;

void run_update(benchmark::State& state, FilterKind kind) {
  FilterConfig config;
  config.num_particles = kBenchParticles;
  Belief initial;
  const Eigen::Vector3d start_m(1000.0, 5.0, 20.0);
  initial.mean_m = start_m;
  initial.cov_m2 = 0.04 * Eigen::Matrix3d::Identity();
  auto filter = make_filter(kind, config, initial, kSeed);

  SensorSimulator sim(SimulatorConfig{}, kSeed);
  std::vector<Eigen::Vector3d> d_meas_m;
  std::vector<std::optional<BeaconMeasurement>> beacons;
  Eigen::Vector3d q_m = start_m;
  const Eigen::Vector3d d_m(0.5, 0.3, 0.0);
  for (int k = 0; k < kReplayEpochs; ++k) {
    const Eigen::Vector3d step_m = (k % 2 == 0) ? d_m : Eigen::Vector3d(-d_m);
    q_m += step_m;
    d_meas_m.push_back(sim.measure_displacement(step_m));
    beacons.push_back(sim.measure_beacon(q_m, k));
  }

  std::size_t k = 0;
  for (auto _ : state) {
    filter->step(d_meas_m[k], beacons[k]);
    benchmark::DoNotOptimize(filter->belief());
    k = (k + 1) % kReplayEpochs;
  }
  if (kind == FilterKind::kParticle) state.SetItemsProcessed(state.iterations() * kBenchParticles);
}

void BM_EkfUpdate(benchmark::State& state) { run_update(state, FilterKind::kEkf); }
void BM_PfUpdate1000(benchmark::State& state) { run_update(state, FilterKind::kParticle); }

BENCHMARK(BM_EkfUpdate);
BENCHMARK(BM_PfUpdate1000);

constexpr int kBenchBeacons = 15;

// 15 beacons on a 10 m x 10 m area at heights 0..2 m (RO-SLAM demo size), a robot driving a
// circle of radius 2 m in it with an offset sensor; odometry and scans simulated before timing.
void run_pose_step(benchmark::State& state, FilterKind kind) {
  BeaconMap map;
  for (int b = 0; b < kBenchBeacons; ++b) {
    map.add(b, {-5.0 + 10.0 * (b % 4) / 3.0, -5.0 + 10.0 * (b / 4) / 3.0, 0.5 * (b % 5)});
  }
  RangeSimulatorConfig sim_config;
  sim_config.sigma_range_m = 0.01;
  sim_config.sensor_on_robot_m = Eigen::Vector3d(0.2, 0.0, 0.3);
  RangeSensorSimulator sim(sim_config, map, kSeed);
  PoseFilterConfig config;
  config.filter.num_particles = kBenchParticles;
  config.use_observation_std = true;
  PoseBelief start;
  start.mean = Eigen::Vector4d(0.0, -2.0, 0.0, 0.0);
  start.cov = Eigen::Vector4d(0.01, 0.01, 0.01, 0.01).asDiagonal();
  auto filter = make_pose_filter(kind, config, map, initial_pose(start), kSeed);

  // One full circle (126 steps of 0.1 m, 0.05 rad) returns to the start: replaying it in a loop
  // keeps the belief on the path.
  constexpr int kSteps = 126;
  std::vector<OdometryIncrement> odometry;
  std::vector<std::vector<BeaconRangeScan>> scans;
  Eigen::Vector4d truth = start.mean;
  const Eigen::Vector4d u(0.1, 0.0, 0.0, 2.0 * 3.14159265358979323846 / kSteps);
  for (int k = 0; k < kSteps; ++k) {
    truth = compose(truth, u);
    odometry.push_back(sim.measure_odometry(u));
    scans.push_back({*sim.measure_ranges(truth, k)});
  }
  std::size_t k = 0;
  for (auto _ : state) {
    filter->step(odometry[k], scans[k]);
    benchmark::DoNotOptimize(filter->belief());
    k = (k + 1) % kSteps;
  }
  if (kind == FilterKind::kParticle) state.SetItemsProcessed(state.iterations() * kBenchParticles);
}

void BM_PoseEkfStep15Beacons(benchmark::State& state) { run_pose_step(state, FilterKind::kEkf); }
void BM_PosePfStep1000Particles15Beacons(benchmark::State& state) { run_pose_step(state, FilterKind::kParticle); }

BENCHMARK(BM_PoseEkfStep15Beacons);
BENCHMARK(BM_PosePfStep1000Particles15Beacons);

}  // namespace
}  // namespace losmimo::localization
