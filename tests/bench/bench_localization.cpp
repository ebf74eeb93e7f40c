// One filter epoch (prediction + beacon update) per UAV: the EKF and the particle filter with
// 1000 particles, on the nominal 1 km geometry. Built with the tests, not run by ctest:
//   bench_localization --benchmark_repetitions=10 --benchmark_report_aggregates_only=true

#include <benchmark/benchmark.h>

#include <cstdint>

#include "losmimo/localization/filter.h"
#include "losmimo/localization/sensor_simulator.h"

namespace losmimo::localization {
namespace {

constexpr int kBenchParticles = 1000;
constexpr std::uint64_t kSeed = 7;

void run_update(benchmark::State& state, FilterKind kind) {
  FilterConfig config;
  config.num_particles = kBenchParticles;
  Belief initial;
  const Eigen::Vector3d start_m(1000.0, 5.0, 20.0);
  initial.mean_m = start_m;
  initial.cov_m2 = 0.04 * Eigen::Matrix3d::Identity();
  auto filter = make_filter(kind, config, initial, kSeed);
  SensorSimulator sim(SimulatorConfig{}, kSeed);
  Eigen::Vector3d q_m = start_m;
  const Eigen::Vector3d d_m(0.5, 0.3, 0.0);
  int epoch = 0;
  for (auto _ : state) {
    // The truth walks back and forth so the belief stays in the nominal geometry.
    const Eigen::Vector3d step_m = (epoch % 2 == 0) ? d_m : Eigen::Vector3d(-d_m);
    state.PauseTiming();
    q_m += step_m;
    const Eigen::Vector3d d_meas_m = sim.measure_displacement(step_m);
    const auto beacon = sim.measure_beacon(q_m, epoch);
    state.ResumeTiming();
    filter->step(d_meas_m, beacon);
    benchmark::DoNotOptimize(filter->belief());
    ++epoch;
  }
}

void BM_EkfUpdate(benchmark::State& state) { run_update(state, FilterKind::kEkf); }
void BM_PfUpdate1000(benchmark::State& state) { run_update(state, FilterKind::kParticle); }

BENCHMARK(BM_EkfUpdate);
BENCHMARK(BM_PfUpdate1000);

}  // namespace
}  // namespace losmimo::localization
