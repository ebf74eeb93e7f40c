// Placement hot paths on the paper's geometry (1 km, 60 GHz, BS spacing 0.25 m), at
// Nt = Nr = 16, 64, 256 (BS 4x4, 8x8, 16x16). Built with the tests, not run by ctest:
//   bench_placement --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
//   bench_placement --benchmark_filter=Swarm256      (256 UAVs to ICN 0.95: GD, URAs)
//
// - Probe: BF's probe evaluation: UAV m's channel row at a probe point (Nt sincos) and f with
//   the others fixed (one Nt x Nt Hermitian form); items/s = probes/s.
// - Gradient: GD's grad f of one UAV at a believed position (O(Nt^2)).
// - UavObjective: the leave-one-out view each UAV builds once per turn (O(Nt^2)).
// - IterationGd / IterationBf / IterationUra: one pass over every UAV under actuation error 0.02 m
//   (sigma_loc 0.1 m for GD; 0.1 m for the URA, which 0.02 m leaves above ICN 0.95), including
//   the per-iteration ICN check of run_placement; floor_ms is the kernels' flops at this core's
//   peak, pct_peak the iteration's share of it:
//   bench_placement --benchmark_filter='Iteration(Gd|Bf)/16|CapUavTurn/16'   (256 UAVs)
// - CapUavTurn: one UAV's turn of the capacity planner (Eigen's products and eigen-solvers).
// - Icn: the exact eigen-solve, and icn_below's cheap proof that ICN < 0.95.
// - UavsByRedundancy: the escapes' order of the UAVs (smallest eigenvector of G).

#include <benchmark/benchmark.h>

#include <Eigen/Eigenvalues>

#include <chrono>
#include <cmath>
#include <random>

#include "losmimo/placement/bf.h"
#include "losmimo/placement/capacity.h"
#include "losmimo/placement/gd.h"
#include "losmimo/placement/isa.h"
#include "losmimo/placement/run.h"
#include "losmimo/placement/stall.h"
#include "losmimo/placement/ura.h"
#include "peak_flops.h"
#include "support/scenarios.h"

namespace losmimo::placement {
namespace {

constexpr std::uint64_t kSeed = 7;

Scenario scenario_with_side(int side) { return test_support::square_array_scenario(side); }

Eigen::Matrix3Xd start_positions(const Scenario& s) {
  std::mt19937_64 rng(kSeed);
  return random_start_positions_m(s, rng);
}

void BM_Probe(benchmark::State& state) {
  const Scenario s = scenario_with_side(static_cast<int>(state.range(0)));
  const ChannelModel model(s);
  const SwarmChannel channel(model, start_positions(s));
  const int m = 3;
  const UavObjective view(channel, m);
  const Eigen::Vector3d q = start_positions(s).col(m);
  const Eigen::Vector3d probes[] = {{0.3, 0, 0}, {-0.3, 0, 0}, {0, 0.3, 0}, {0, -0.3, 0}, {0, 0, 0.3}, {0, 0, -0.3}};
  int k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(view.objective_of_row(model.row(q + probes[k])));
    k = (k + 1) % 6;
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["Nt"] = s.num_bs_antennas();
}
BENCHMARK(BM_Probe)->Arg(4)->Arg(8)->Arg(16);

void BM_ChannelRow(benchmark::State& state) {
  const Scenario s = scenario_with_side(static_cast<int>(state.range(0)));
  const ChannelModel model(s);
  Eigen::Vector3d q = start_positions(s).col(0);
  for (auto _ : state) {
    benchmark::DoNotOptimize(model.row(q));
    q.y() += 1e-3;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ChannelRow)->Arg(4)->Arg(8)->Arg(16);

void BM_Gradient(benchmark::State& state) {
  const Scenario s = scenario_with_side(static_cast<int>(state.range(0)));
  const ChannelModel model(s);
  const SwarmChannel channel(model, start_positions(s));
  const UavObjective view(channel, 3);
  Eigen::Vector3d q = start_positions(s).col(3);
  for (auto _ : state) {
    benchmark::DoNotOptimize(view.gradient_at(q));
    q.z() += 1e-3;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Gradient)->Arg(4)->Arg(8)->Arg(16);

void BM_UavObjective(benchmark::State& state) {
  const Scenario s = scenario_with_side(static_cast<int>(state.range(0)));
  const ChannelModel model(s);
  const SwarmChannel channel(model, start_positions(s));
  int m = 0;
  for (auto _ : state) {
    const UavObjective view(channel, m);
    benchmark::DoNotOptimize(&view);
    m = (m + 1) % s.num_uavs;
  }
}
BENCHMARK(BM_UavObjective)->Arg(4)->Arg(8)->Arg(16);

void BM_Icn(benchmark::State& state) {
  const Scenario s = scenario_with_side(static_cast<int>(state.range(0)));
  const ChannelModel model(s);
  const SwarmChannel channel(model, start_positions(s));
  const bool cheap = state.range(1) != 0;
  for (auto _ : state) {
    if (cheap) {
      benchmark::DoNotOptimize(icn_below(channel.gram(), channel.num_uavs(), 0.95));
    } else {
      benchmark::DoNotOptimize(icn_from_gram(channel.gram(), channel.num_uavs()));
    }
  }
}
BENCHMARK(BM_Icn)->ArgNames({"side", "bound"})->Args({4, 0})->Args({4, 1})->Args({8, 0})->Args({8, 1});

// The escapes' redundancy order (Lanczos + a real tridiagonal solve), against Eigen's complex
// Hermitian solver for the same smallest eigenvector (solver:1).
void BM_UavsByRedundancy(benchmark::State& state) {
  const Scenario s = scenario_with_side(static_cast<int>(state.range(0)));
  const ChannelModel model(s);
  const SwarmChannel channel(model, start_positions(s));
  const bool eigen_solver = state.range(1) != 0;
  for (auto _ : state) {
    if (eigen_solver) {
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXcd> eig(channel.gram());
      benchmark::DoNotOptimize(eig.eigenvectors()(0, 0));
    } else {
      benchmark::DoNotOptimize(uavs_by_redundancy(channel));
    }
  }
}
BENCHMARK(BM_UavsByRedundancy)->ArgNames({"side", "solver"})->Args({4, 0})->Args({4, 1})->Args({8, 0})->Args({8, 1});

// The arithmetic floor of an iteration: its kernels' flops (counted as in bench_kernels.cpp) at
// the peak of the instruction set the kernels run on (BM_PeakFlops' FMA variant; SSE2 multiply +
// add), measured once per process.
double active_peak_flops_per_s() {
  static const double peak = [] {
    switch (active_isa()) {
      case Isa::kAvx512:
        return bench::measure_peak_flops_per_s(bench::PeakVariant::kAvx512Fma);
      case Isa::kAvx2:
        return bench::measure_peak_flops_per_s(bench::PeakVariant::kAvx2Fma);
      case Isa::kSse2:
        break;
    }
    return bench::measure_peak_flops_per_s(bench::PeakVariant::kSse2);
  }();
  return peak;
}

// Counters of a benchmark whose unit of work has `flops` flops: floor_ms (flops at the peak) and
// pct_peak (the flops per second of CPU time against the peak).
void set_floor_counters(benchmark::State& state, double flops) {
  const double peak = active_peak_flops_per_s();
  state.counters["floor_ms"] = 1e3 * flops / peak;
  state.counters["pct_peak"] =
      benchmark::Counter(100.0 * flops * static_cast<double>(state.iterations()) / peak, benchmark::Counter::kIsRate);
}

// Flops of one swarm iteration's kernels, n = Nt antennas, nr UAVs (bench_kernels.cpp's counts;
// escapes, the ICN check and the draws not counted). GD: gradient (8 n^2 + 121 n), the line
// search's first point (objective_at, 8 n^2 + 91 n), the kept move's row (55 n) and Gram update
// (14 n^2). BF: rows_lanes (440 n), objectives_lanes (38 n^2 + 96 n), the kept move's row and
// Gram update.
double gd_iteration_flops(double n, double nr) { return nr * (30 * n * n + 267 * n); }
double bf_iteration_flops(double n, double nr) { return nr * (52 * n * n + 591 * n); }

// One planner iteration plus run_placement's ICN check, on a swarm kept away from the target
// (it starts random and the errors keep it moving); Nr = Nt.
template <typename MakePlanner, typename Flops>
void iterate(benchmark::State& state, const ErrorModel& errors, MakePlanner make_planner, Flops iteration_flops) {
  const Scenario s = scenario_with_side(static_cast<int>(state.range(0)));
  const ChannelModel model(s);
  Swarm swarm(model, start_positions(s), errors, kSeed);
  auto planner = make_planner(s);
  planner.start(swarm);
  active_peak_flops_per_s();  // outside the timed loop
  int iteration = 0;
  IcnWarmStart warm_start;
  for (auto _ : state) {
    planner.iterate(swarm, ++iteration);
    const SwarmChannel& ch = swarm.channel();
    if (!icn_below(ch, 0.95, &warm_start)) {
      benchmark::DoNotOptimize(icn_from_gram(ch.gram(), ch.num_uavs()));
    }
  }
  state.counters["Nt"] = s.num_bs_antennas();
  set_floor_counters(state, iteration_flops(s.num_bs_antennas(), s.num_uavs));
}

void BM_IterationGd(benchmark::State& state) {
  iterate(
      state, ErrorModel{0.1, 0.02}, [](const Scenario& s) { return GradientDescentPlanner(s, GdOptions{}); },
      gd_iteration_flops);
}
BENCHMARK(BM_IterationGd)->Arg(4)->Arg(8)->Arg(16)->Unit(benchmark::kMillisecond);

void BM_IterationBf(benchmark::State& state) {
  iterate(
      state, ErrorModel{0.0, 0.02}, [](const Scenario& s) { return BruteForcePlanner(s, BfOptions{}); },
      bf_iteration_flops);
}
BENCHMARK(BM_IterationBf)->Arg(4)->Arg(8)->Arg(16)->Unit(benchmark::kMillisecond);

void BM_IterationUra(benchmark::State& state) {
  iterate(
      state, ErrorModel{0.0, 0.1}, [](const Scenario& s) { return UraPlanner(s, UraVariant::kRigid); },
      [](double n, double nr) { return 55 * n * nr + 8 * nr * n * (n + 1) / 2 + 8 * n * n * n / 6; });
}
BENCHMARK(BM_IterationUra)->Arg(4)->Arg(8)->Unit(benchmark::kMicrosecond);

// One UAV's turn of the capacity planner (its gradient, then the backtracking's first check):
// an iteration is Nr of these plus one capacity. Its arithmetic is Eigen's, per turn: K = H H^H
// twice (8 nr^2 n each, the full product), a Hermitian eigen-decomposition with vectors
// (36 nr^3: 9 nr^3 real flops, times 4 for complex) and one without (16 nr^3 / 3).
void BM_CapUavTurn(benchmark::State& state) {
  const Scenario s = scenario_with_side(static_cast<int>(state.range(0)));
  const ChannelModel model(s);
  Swarm swarm(model, start_positions(s), ErrorModel{}, kSeed);
  CapacityPlanner planner(s, CapOptions{});
  planner.start(swarm);
  active_peak_flops_per_s();
  int m = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(planner.plan_step(swarm, m, swarm.true_positions_m().col(m), 1.0));
    m = (m + 1) % swarm.num_uavs();
  }
  const double n = s.num_bs_antennas(), nr = s.num_uavs;
  state.counters["Nt"] = n;
  set_floor_counters(state, 2 * 8 * nr * nr * n + 36 * nr * nr * nr + 16 * nr * nr * nr / 3);
}
BENCHMARK(BM_CapUavTurn)->Arg(4)->Arg(8)->Arg(16)->Unit(benchmark::kMillisecond);

// A 256-UAV swarm (BS 16 x 16) from a random start in the 50 m cube to ICN 0.95, without
// errors: wall time, iterations and the mean travel per UAV as counters.
template <typename MakePlanner>
void swarm256(benchmark::State& state, MakePlanner make_planner) {
  const Scenario s = scenario_with_side(16);
  const ChannelModel model(s);
  RunOptions options;
  options.max_iterations = 5000;
  options.full_icn_trace = false;
  for (auto _ : state) {
    Swarm swarm(model, start_positions(s), ErrorModel{}, kSeed);
    auto planner = make_planner(s);
    const auto t0 = std::chrono::steady_clock::now();
    const RunResult r = run_placement(planner, swarm, options);
    state.counters["wall_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    state.counters["converged"] = r.converged();
    state.counters["iterations"] = r.iterations;
    state.counters["final_icn"] = icn_from_gram(swarm.channel().gram(), swarm.num_uavs());
    state.counters["travel_m"] = r.placement_dist_m.mean();
    state.counters["dist_to_icn095_m"] = r.icn095.reached ? r.icn095.placement_dist_m : std::nan("");
  }
}

void BM_Swarm256_Gd(benchmark::State& state) {
  swarm256(state, [](const Scenario& s) { return GradientDescentPlanner(s, GdOptions{}); });
}
BENCHMARK(BM_Swarm256_Gd)->Iterations(1)->Unit(benchmark::kSecond);

// GD scaled to the 16 x 16 array (gd.h): a 17 x 17 escape grid (slots are period / 16 apart),
// 32 UAVs per stall, a 10-iteration stall window, and depth steps x1000 (the Fresnel phase).
GdOptions large_swarm_gd() {
  GdOptions o;
  o.escape_half_grid = 8;
  o.escape_uavs = 32;
  o.stall_window = 10;
  o.depth_step_gain = 1000.0;
  return o;
}

void BM_Swarm256_GdLargeEscape(benchmark::State& state) {
  swarm256(state, [](const Scenario& s) { return GradientDescentPlanner(s, large_swarm_gd()); });
}
BENCHMARK(BM_Swarm256_GdLargeEscape)->Iterations(1)->Unit(benchmark::kSecond);

void BM_Swarm256_Ura(benchmark::State& state) {
  swarm256(state, [](const Scenario& s) { return UraPlanner(s, UraVariant::kRigid); });
}
BENCHMARK(BM_Swarm256_Ura)->Iterations(1)->Unit(benchmark::kSecond);

void BM_Swarm256_UraLattice(benchmark::State& state) {
  swarm256(state, [](const Scenario& s) { return UraPlanner(s, UraVariant::kLattice); });
}
BENCHMARK(BM_Swarm256_UraLattice)->Iterations(1)->Unit(benchmark::kSecond);

void BM_Swarm256_UraLatticeExact(benchmark::State& state) {
  swarm256(state, [](const Scenario& s) { return UraPlanner(s, UraVariant::kLatticeExact); });
}
BENCHMARK(BM_Swarm256_UraLatticeExact)->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace
}  // namespace losmimo::placement
