// The placement kernels (kernels.h) per instruction set, against this core's measured peak.
// Part of bench_placement. Arguments: BS side (Nt = side^2: 16, 64, 256) and instruction set
// (0 sse2, 1 avx2, 2 avx512; unsupported ones are skipped).
//
//   bench_placement --benchmark_filter='Peak|Kernel'
//
// Counters: flops (flops per second of CPU time, by the counts below) and pct_peak (that
// against BM_PeakFlops of the same instruction set, measured once in the same process: SSE2
// multiply + add, AVX2 and AVX-512 FMA: the machine's limit, although the kernels use no FMA,
// kernels.h says why). Flop counts, a multiply-add counted as 2:
//   phase -> (cos, sin): 45 (reduction 9, two degree-7 polynomials 24, the rest 12);
//   channel row entry: 55 (distance 9, phase 1, sincos 45);
//   objectives_lanes: 6 n kLanes (S, Q) + 6 n^2 (M's triangle and F_A) + 32 n^2 (4 multiply-adds per lane per
//     pair l < k, 8 lanes) + 6 n kLanes: 38 n^2 + 96 n;
//   BF UAV step = rows_lanes + objectives_lanes: 440 n + 38 n^2 + 96 n;
//   objective_of_row: 8 n^2 (conj(G) x) + 36 n; objective_at: + 55 n; gradient: + 30 n more;
//   gram_update: 14 n^2; gram_of_rows: 8 nr n (n + 1) / 2 (the entries on and below the diagonal,
//     8 per row each; the kernel copies the rest; nr = n rows); leave_one_out_energy: 12 n^2;
//   hermitian_matvec: 8 n^2; shifted_ldl (to the end): 8 n^3 / 6 (n^3 / 6 complex
//     multiply-adds in the updates; the divisions not counted);
//   normals: 83 per pair (log 31, sincos 45, the rest 7).
// BM_MemoryRead: read bandwidth for a working set, to judge the Nt = 256 kernels, whose
// Gram matrix (2 planes x 256 x 256 doubles = 1 MiB) does not fit this core's L1/L2.

#include <benchmark/benchmark.h>

#include <map>
#include <mutex>
#include <random>
#include <vector>

#include "losmimo/placement/kernels.h"
#include "losmimo/placement/swarm_channel.h"
#include "peak_flops.h"
#include "support/scenarios.h"

namespace losmimo::placement {
namespace {

namespace lk = kernels;
using bench::PeakVariant;

constexpr Isa kIsas[] = {Isa::kSse2, Isa::kAvx2, Isa::kAvx512};

PeakVariant peak_variant(Isa isa) {
  switch (isa) {
    case Isa::kSse2:
      return PeakVariant::kSse2;
    case Isa::kAvx2:
      return PeakVariant::kAvx2Fma;
    case Isa::kAvx512:
      return PeakVariant::kAvx512Fma;
  }
  return PeakVariant::kSse2;
}

// Measured once per process, before the first kernel benchmark of that instruction set.
double peak_flops_per_s(Isa isa) {
  static std::mutex mutex;
  static std::map<Isa, double> peaks;
  const std::lock_guard<std::mutex> lock(mutex);
  auto it = peaks.find(isa);
  if (it == peaks.end()) it = peaks.emplace(isa, bench::measure_peak_flops_per_s(peak_variant(isa))).first;
  return it->second;
}

void set_flop_counters(benchmark::State& state, Isa isa, double flops_per_iteration) {
  const double flops = flops_per_iteration * static_cast<double>(state.iterations());
  state.counters["flops"] = benchmark::Counter(flops, benchmark::Counter::kIsRate);
  state.counters["pct_peak"] = benchmark::Counter(100.0 * flops / peak_flops_per_s(isa), benchmark::Counter::kIsRate);
}

// The kernels of state.range(1), or nullptr (and the benchmark skipped) if this CPU cannot.
const lk::Kernels* kernels_of(benchmark::State& state, int arg = 1) {
  const Isa isa = kIsas[state.range(arg)];
  if (!isa_supported(isa)) {
    state.SkipWithError("instruction set not supported by this CPU");
    return nullptr;
  }
  peak_flops_per_s(isa);  // outside the timed loop
  state.SetLabel(to_string(isa));
  return &lk::kernels_for(isa);
}

// A random swarm of side^2 UAVs on a side x side BS array (the paper's geometry), its Gram
// matrix in split planes, every row (hr, hi: row m at m ld), and UAV 3's row.
struct Inputs {
  Scenario scenario;
  ChannelModel model;
  std::vector<double> gr, gi, hr, hi, or_, oi;
  double F_A = 0.0;
  Eigen::Vector3d q;
  explicit Inputs(int side) : scenario(make_scenario(side)), model(scenario) {
    std::mt19937_64 rng(7);
    const Eigen::Matrix3Xd start = random_start_positions_m(scenario, rng);
    const SwarmChannel channel(model, start);
    const int n = model.num_antennas(), ld = lk::padded(n);
    gr.assign(static_cast<std::size_t>(ld) * n, 0.0);
    gi.assign(static_cast<std::size_t>(ld) * n, 0.0);
    for (int k = 0; k < n; ++k) {
      for (int l = 0; l < n; ++l) {
        gr[l + k * ld] = channel.gram()(l, k).real();
        gi[l + k * ld] = channel.gram()(l, k).imag();
      }
    }
    hr.assign(channel.row_re(0), channel.row_re(0) + static_cast<std::ptrdiff_t>(ld) * channel.num_uavs());
    hi.assign(channel.row_im(0), channel.row_im(0) + static_cast<std::ptrdiff_t>(ld) * channel.num_uavs());
    or_.assign(ld, 0.0);
    oi.assign(ld, 0.0);
    for (int k = 0; k < n; ++k) {
      or_[k] = channel.H()(3, k).real();
      oi[k] = channel.H()(3, k).imag();
    }
    q = start.col(3);
    F_A = lk::reference_kernels().leave_one_out_energy(gram(), or_.data(), oi.data());
  }
  static Scenario make_scenario(int side) { return test_support::square_array_scenario(side); }
  lk::GramPlanes gram() const { return {model.num_antennas(), lk::padded(model.num_antennas()), gr.data(), gi.data()}; }
  int n() const { return model.num_antennas(); }
  int ld() const { return lk::padded(n()); }
};

void KernelArgs(benchmark::internal::Benchmark* b) {
  b->ArgNames({"side", "isa"});
  for (int side : {4, 8, 16}) {
    for (int isa = 0; isa < 3; ++isa) b->Args({side, isa});
  }
}

void BM_PeakFlops(benchmark::State& state) {
  const auto v = static_cast<PeakVariant>(state.range(0));
  if (!bench::supported(v)) {
    state.SkipWithError("not supported by this CPU");
    return;
  }
  constexpr std::int64_t kReps = 100000;
  for (auto _ : state) benchmark::DoNotOptimize(bench::run_peak(v, kReps));
  state.SetLabel(bench::name(v));
  state.counters["flops"] = benchmark::Counter(bench::peak_flops(v, kReps) * static_cast<double>(state.iterations()),
                                               benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PeakFlops)->DenseRange(0, bench::kNumPeakVariants - 1);

void BM_Kernel_UnitPhasors(benchmark::State& state) {
  const lk::Kernels* k = kernels_of(state);
  if (!k) return;
  const int n = static_cast<int>(state.range(0) * state.range(0));
  std::vector<double> phase(n), c(n), s(n);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-1.3e6, -1.2e6);
  for (double& p : phase) p = u(rng);
  for (auto _ : state) {
    k->unit_phasors(phase.data(), c.data(), s.data(), n);
    benchmark::DoNotOptimize(c.data());
    benchmark::ClobberMemory();
  }
  set_flop_counters(state, k->isa, 45.0 * n);
}
BENCHMARK(BM_Kernel_UnitPhasors)->Apply(KernelArgs);

void BM_Kernel_Row(benchmark::State& state) {
  const lk::Kernels* k = kernels_of(state);
  if (!k) return;
  const Inputs in(static_cast<int>(state.range(0)));
  std::vector<double> xr(in.ld()), xi(in.ld());
  double q[3] = {in.q.x(), in.q.y(), in.q.z()};
  for (auto _ : state) {
    k->row(in.model.geometry(), q, xr.data(), xi.data());
    benchmark::DoNotOptimize(xr.data());
    benchmark::ClobberMemory();
    q[1] += 1e-3;
  }
  set_flop_counters(state, k->isa, 55.0 * in.n());
}
BENCHMARK(BM_Kernel_Row)->Apply(KernelArgs);

// The 8 candidate positions of a BF step (stay, 6 probes, one spare).
void lane_positions(const Eigen::Vector3d& q, double* px, double* py, double* pz) {
  const double dx[lk::kLanes] = {0, 0.3, -0.3, 0, 0, 0, 0, 0};
  const double dy[lk::kLanes] = {0, 0, 0, 0.3, -0.3, 0, 0, 0};
  const double dz[lk::kLanes] = {0, 0, 0, 0, 0, 0.3, -0.3, 0};
  for (int p = 0; p < lk::kLanes; ++p) {
    px[p] = q.x() + dx[p];
    py[p] = q.y() + dy[p];
    pz[p] = q.z() + dz[p];
  }
}

void BM_Kernel_RowsLanes(benchmark::State& state) {
  const lk::Kernels* k = kernels_of(state);
  if (!k) return;
  const Inputs in(static_cast<int>(state.range(0)));
  std::vector<double> Xr(in.ld() * lk::kLanes), Xi(in.ld() * lk::kLanes);
  double px[lk::kLanes], py[lk::kLanes], pz[lk::kLanes];
  lane_positions(in.q, px, py, pz);
  for (auto _ : state) {
    k->rows_lanes(in.model.geometry(), px, py, pz, Xr.data(), Xi.data());
    benchmark::DoNotOptimize(Xr.data());
    benchmark::ClobberMemory();
    py[0] += 1e-3;
  }
  set_flop_counters(state, k->isa, 55.0 * in.n() * lk::kLanes);
}
BENCHMARK(BM_Kernel_RowsLanes)->Apply(KernelArgs);

void BM_Kernel_ObjectivesLanes(benchmark::State& state) {
  const lk::Kernels* k = kernels_of(state);
  if (!k) return;
  const Inputs in(static_cast<int>(state.range(0)));
  std::vector<double> Xr(in.ld() * lk::kLanes), Xi(in.ld() * lk::kLanes);
  double px[lk::kLanes], py[lk::kLanes], pz[lk::kLanes], f[lk::kLanes];
  lane_positions(in.q, px, py, pz);
  k->rows_lanes(in.model.geometry(), px, py, pz, Xr.data(), Xi.data());
  for (auto _ : state) {
    k->objectives_lanes(in.gram(), in.or_.data(), in.oi.data(), Xr.data(), Xi.data(), f);
    benchmark::DoNotOptimize(f);
    benchmark::ClobberMemory();
  }
  const double n = in.n();
  set_flop_counters(state, k->isa, 38.0 * n * n + 96.0 * n);
}
BENCHMARK(BM_Kernel_ObjectivesLanes)->Apply(KernelArgs);

// One BF UAV step: the rows of the 8 lanes and their f values (the stay value and 6 probes).
void BM_Kernel_BfStep(benchmark::State& state) {
  const lk::Kernels* k = kernels_of(state);
  if (!k) return;
  const Inputs in(static_cast<int>(state.range(0)));
  std::vector<double> Xr(in.ld() * lk::kLanes), Xi(in.ld() * lk::kLanes);
  double px[lk::kLanes], py[lk::kLanes], pz[lk::kLanes], f[lk::kLanes];
  lane_positions(in.q, px, py, pz);
  for (auto _ : state) {
    k->rows_lanes(in.model.geometry(), px, py, pz, Xr.data(), Xi.data());
    k->objectives_lanes(in.gram(), in.or_.data(), in.oi.data(), Xr.data(), Xi.data(), f);
    benchmark::DoNotOptimize(f);
    benchmark::ClobberMemory();
    py[1] += 1e-6;
  }
  const double n = in.n();
  set_flop_counters(state, k->isa, 55.0 * n * lk::kLanes + 38.0 * n * n + 96.0 * n);
}
BENCHMARK(BM_Kernel_BfStep)->Apply(KernelArgs);

void BM_Kernel_ObjectiveAt(benchmark::State& state) {
  const lk::Kernels* k = kernels_of(state);
  if (!k) return;
  const Inputs in(static_cast<int>(state.range(0)));
  double q[3] = {in.q.x(), in.q.y(), in.q.z()};
  for (auto _ : state) {
    benchmark::DoNotOptimize(k->objective_at(in.model.geometry(), in.gram(), in.or_.data(), in.oi.data(), in.F_A, q));
    q[2] += 1e-3;
  }
  const double n = in.n();
  set_flop_counters(state, k->isa, 8.0 * n * n + 91.0 * n);
}
BENCHMARK(BM_Kernel_ObjectiveAt)->Apply(KernelArgs);

void BM_Kernel_Gradient(benchmark::State& state) {
  const lk::Kernels* k = kernels_of(state);
  if (!k) return;
  const Inputs in(static_cast<int>(state.range(0)));
  double q[3] = {in.q.x(), in.q.y(), in.q.z()}, grad[3];
  for (auto _ : state) {
    benchmark::DoNotOptimize(k->gradient(in.model.geometry(), in.gram(), in.or_.data(), in.oi.data(), in.F_A, q, grad));
    benchmark::DoNotOptimize(grad);
    q[2] += 1e-3;
  }
  const double n = in.n();
  set_flop_counters(state, k->isa, 8.0 * n * n + 121.0 * n);
}
BENCHMARK(BM_Kernel_Gradient)->Apply(KernelArgs);

void BM_Kernel_LeaveOneOutEnergy(benchmark::State& state) {
  const lk::Kernels* k = kernels_of(state);
  if (!k) return;
  const Inputs in(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(k->leave_one_out_energy(in.gram(), in.or_.data(), in.oi.data()));
  const double n = in.n();
  set_flop_counters(state, k->isa, 12.0 * n * n);
}
BENCHMARK(BM_Kernel_LeaveOneOutEnergy)->Apply(KernelArgs);

void BM_Kernel_GramUpdate(benchmark::State& state) {
  const lk::Kernels* k = kernels_of(state);
  if (!k) return;
  Inputs in(static_cast<int>(state.range(0)));
  std::vector<double> xr(in.ld()), xi(in.ld());
  const double q[3] = {in.q.x() + 0.1, in.q.y(), in.q.z()};
  k->row(in.model.geometry(), q, xr.data(), xi.data());
  bool forth = true;
  for (auto _ : state) {
    // Alternately in and out, so that G stays the Gram matrix of a real swarm.
    if (forth) {
      k->gram_update(in.gr.data(), in.gi.data(), in.n(), in.ld(), xr.data(), xi.data(), in.or_.data(), in.oi.data());
    } else {
      k->gram_update(in.gr.data(), in.gi.data(), in.n(), in.ld(), in.or_.data(), in.oi.data(), xr.data(), xi.data());
    }
    forth = !forth;
    benchmark::ClobberMemory();
  }
  const double n = in.n();
  set_flop_counters(state, k->isa, 14.0 * n * n);
}
BENCHMARK(BM_Kernel_GramUpdate)->Apply(KernelArgs);

void BM_Kernel_GramOfRows(benchmark::State& state) {
  const lk::Kernels* k = kernels_of(state);
  if (!k) return;
  Inputs in(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    k->gram_of_rows(in.hr.data(), in.hi.data(), in.n(), in.n(), in.ld(), in.gr.data(), in.gi.data());
    benchmark::ClobberMemory();
  }
  // The Hermitian product's own work: the n (n + 1) / 2 entries on and below the diagonal
  // (the kernel copies the rest), 8 flops per row each.
  const double n = in.n();
  set_flop_counters(state, k->isa, 8.0 * n * n * (n + 1) / 2);
}
BENCHMARK(BM_Kernel_GramOfRows)->Apply(KernelArgs);

void BM_Kernel_HermitianMatvec(benchmark::State& state) {
  const lk::Kernels* k = kernels_of(state);
  if (!k) return;
  const Inputs in(static_cast<int>(state.range(0)));
  std::vector<double> yr(in.ld()), yi(in.ld());
  for (auto _ : state) {
    k->hermitian_matvec(in.gram(), in.or_.data(), in.oi.data(), yr.data(), yi.data());
    benchmark::DoNotOptimize(yr.data());
    benchmark::ClobberMemory();
  }
  const double n = in.n();
  set_flop_counters(state, k->isa, 8.0 * n * n);
}
BENCHMARK(BM_Kernel_HermitianMatvec)->Apply(KernelArgs);

// The whole factorisation (s = 0: G is positive definite), icn_below's longest case.
void BM_Kernel_ShiftedLdl(benchmark::State& state) {
  const lk::Kernels* k = kernels_of(state);
  if (!k) return;
  const Inputs in(static_cast<int>(state.range(0)));
  std::vector<double> lr(in.gr.size()), li(in.gr.size());
  int result = 0;
  for (auto _ : state) {
    result = k->shifted_ldl(in.gram(), 0.0, lr.data(), li.data());
    benchmark::DoNotOptimize(lr.data());
    benchmark::ClobberMemory();
  }
  if (result != in.n()) state.SkipWithError("the benchmark's G is not positive definite");
  const double n = in.n();
  set_flop_counters(state, k->isa, 8.0 * n * n * n / 6);
}
BENCHMARK(BM_Kernel_ShiftedLdl)->Apply(KernelArgs);

void BM_Kernel_Normals(benchmark::State& state) {
  const lk::Kernels* k = kernels_of(state, 0);
  if (!k) return;
  constexpr int kBlocks = 16;  // 256 numbers, a Swarm's buffer
  std::vector<double> out(16 * kBlocks);
  std::uint64_t block = 0;
  for (auto _ : state) {
    k->normals(0x5eed, block, out.data(), kBlocks);
    block += kBlocks;
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * 16 * kBlocks);
  set_flop_counters(state, k->isa, 83.0 / 2 * 16 * kBlocks);
}
BENCHMARK(BM_Kernel_Normals)->ArgName("isa")->DenseRange(0, 2);

// OR of a buffer of range(0) KiB, read over and over with 32-byte loads: bytes per second.
__attribute__((target("avx2"), noinline)) std::uint64_t or_reduce_avx2(const std::uint64_t* p, std::size_t n) {
  std::uint64_t acc[8] = {};
  for (std::size_t i = 0; i + 8 <= n; i += 8) {
#pragma GCC unroll 8
    for (int j = 0; j < 8; ++j) acc[j] |= p[i + j];
  }
  return acc[0] | acc[1] | acc[2] | acc[3] | acc[4] | acc[5] | acc[6] | acc[7];
}

void BM_MemoryRead(benchmark::State& state) {
  if (!isa_supported(Isa::kAvx2)) {
    state.SkipWithError("needs AVX2");
    return;
  }
  const std::size_t n = static_cast<std::size_t>(state.range(0)) * 1024 / sizeof(std::uint64_t);
  std::vector<std::uint64_t> buf(n, 1);
  for (auto _ : state) benchmark::DoNotOptimize(or_reduce_avx2(buf.data(), n));
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * n * sizeof(std::uint64_t)));
}
BENCHMARK(BM_MemoryRead)->ArgName("KiB")->Arg(32)->Arg(512)->Arg(1024)->Arg(4096)->Arg(65536);

}  // namespace
}  // namespace losmimo::placement
