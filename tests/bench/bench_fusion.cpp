// Cost of the fusion layer: one sliding-window refinement per UAV per swarm iteration, the
// centralized eq. 4 solution, and the range-only smoother. Windows are drawn before timing
// (tests/fusion/window_simulator.h).
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "fusion/range_track_simulator.h"
#include "fusion/window_simulator.h"
#include "losmimo/fusion/centralized.h"
#include "losmimo/fusion/closed_loop.h"
#include "losmimo/fusion/refinement.h"

namespace {

using losmimo::fusion::RefinementConfig;
using losmimo::test_support::draw_window;
using losmimo::test_support::DrawnWindow;

constexpr int kNumWindows = 64;

// range(0): window epochs W; range(1): 1 with CSI, 0 beacon + dead reckoning only.
void BM_RefineWindow(benchmark::State& state) {
  const losmimo::placement::Scenario scenario;
  const losmimo::placement::ChannelModel model(scenario);
  RefinementConfig config;
  config.window_epochs = static_cast<int>(state.range(0));
  config.use_csi = state.range(1) != 0;
  config.beacon_sigma_angle_rad = 1.8e-4;
  config.csi_noise_variance = scenario.noise_variance();
  std::mt19937_64 rng(61);
  std::vector<DrawnWindow> windows;
  for (int i = 0; i < kNumWindows; ++i) {
    windows.push_back(draw_window(model, config, config.window_epochs, rng));
  }
  int i = 0;
  for (auto _ : state) {
    const auto result = losmimo::fusion::refine_window(model, config, windows[i].epochs);
    benchmark::DoNotOptimize(result.belief.mean_m.data());
    i = (i + 1) % kNumWindows;
  }
}
BENCHMARK(BM_RefineWindow)->Args({5, 1})->Args({5, 0})->Args({10, 1})->Unit(benchmark::kMicrosecond);

void BM_SolveCentralized(benchmark::State& state) {
  const losmimo::placement::Scenario scenario;
  std::mt19937_64 rng(62);
  const Eigen::Matrix3Xd start = losmimo::placement::random_start_positions_m(scenario, rng);
  const losmimo::fusion::CentralizedConfig config;
  for (auto _ : state) {
    const auto result = losmimo::fusion::solve_centralized(scenario, start, config);
    benchmark::DoNotOptimize(result.icn);
  }
}
BENCHMARK(BM_SolveCentralized)->Unit(benchmark::kMillisecond)->Iterations(3);

// One closed-loop placement run on the paper scenario (16 UAVs, beacon 0.18 m cross-range),
// to ICN 0.95. range(0): 0 EKF, 1 EKF + Ceres refinement, 2 particle filter.
void BM_ClosedLoopRun(benchmark::State& state) {
  losmimo::placement::PlacementSettings settings;
  settings.errors.sigma_act_m = 0.02;
  std::mt19937_64 rng(63);
  const Eigen::Matrix3Xd start = losmimo::placement::random_start_positions_m(settings.scenario, rng);
  losmimo::localization::SimulatorConfig sim;
  sim.sigma_angle_rad = 1.8e-4;
  losmimo::fusion::ClosedLoopConfig config = losmimo::fusion::matched_closed_loop_config(sim, settings.scenario);
  config.refine = state.range(0) == 1;
  if (state.range(0) == 2) config.filter_kind = losmimo::localization::FilterKind::kParticle;
  std::uint64_t seed = 1;
  int iterations = 0;
  for (auto _ : state) {
    const auto run = losmimo::fusion::run_closed_loop(settings, start, config, seed++);
    iterations += run.run.iterations;
    benchmark::DoNotOptimize(run.run.final_m.data());
  }
  state.counters["swarm_iterations"] = benchmark::Counter(iterations, benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_ClosedLoopRun)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

// The range-only smoother over a 240-frame synthetic track (tests/fusion/range_track_simulator.h):
// range(0) = window_frames (0: the whole track in one problem).
void BM_SmoothRangeTrack(benchmark::State& state) {
  const losmimo::test_support::Synthetic s = losmimo::test_support::simulate(1, 0.0);
  losmimo::fusion::RangeSmootherConfig config;
  config.window_frames = static_cast<int>(state.range(0));
  for (auto _ : state) {
    const auto result = losmimo::fusion::smooth_range_track(losmimo::test_support::filter_config(),
                                                            losmimo::test_support::four_beacons(), s.frames, config);
    benchmark::DoNotOptimize(result.track.data());
  }
}
BENCHMARK(BM_SmoothRangeTrack)->Arg(0)->Arg(10)->Unit(benchmark::kMillisecond);

}  // namespace
