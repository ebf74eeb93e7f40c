// One filter epoch (prediction + beacon update) per UAV: the EKF and the particle filter with
// 1000 particles, on the nominal 1 km geometry. Built with the tests, not run by ctest:
//   bench_localization --benchmark_repetitions=10 --benchmark_report_aggregates_only=true

#include <benchmark/benchmark.h>

#include <cstdint>
#include <optional>
#include <vector>

#include "losmimo/localization/filter.h"
#include "losmimo/localization/sensor_simulator.h"

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
}

void BM_EkfUpdate(benchmark::State& state) { run_update(state, FilterKind::kEkf); }
void BM_PfUpdate1000(benchmark::State& state) { run_update(state, FilterKind::kParticle); }

BENCHMARK(BM_EkfUpdate);
BENCHMARK(BM_PfUpdate1000);

}  // namespace
}  // namespace losmimo::localization
