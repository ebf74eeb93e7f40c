#pragma once
// This core's peak double-precision multiply-add rate, per instruction set, for the
// benchmarks' "percent of peak" counters.
//
// Each variant runs kChains independent chains acc = acc * b + c: enough to cover the
// multiply-add latency on every FP pipe, so the loop is throughput-bound. 2 flops per lane per
// multiply-add, fused or not. One translation unit holds every variant through
// __attribute__((target)); run only the ones isa_supported() allows.

#include <immintrin.h>

#include <algorithm>
#include <chrono>
#include <cstdint>

namespace losmimo::bench {

enum class PeakVariant { kScalar, kScalarFma, kSse2, kAvx2NoFma, kAvx2Fma, kAvx512NoFma, kAvx512Fma };
inline constexpr int kNumPeakVariants = 7;

inline const char* name(PeakVariant v) {
  switch (v) {
    case PeakVariant::kScalar:
      return "scalar";
    case PeakVariant::kScalarFma:
      return "scalar_fma";
    case PeakVariant::kSse2:
      return "sse2";
    case PeakVariant::kAvx2NoFma:
      return "avx2_nofma";
    case PeakVariant::kAvx2Fma:
      return "avx2_fma";
    case PeakVariant::kAvx512NoFma:
      return "avx512_nofma";
    case PeakVariant::kAvx512Fma:
      return "avx512_fma";
  }
  return "?";
}

inline bool supported(PeakVariant v) {
  __builtin_cpu_init();
  switch (v) {
    case PeakVariant::kScalar:
    case PeakVariant::kSse2:
      return true;
    case PeakVariant::kScalarFma:
      return __builtin_cpu_supports("fma");
    case PeakVariant::kAvx2NoFma:
      return __builtin_cpu_supports("avx2");
    case PeakVariant::kAvx2Fma:
      return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    case PeakVariant::kAvx512NoFma:
    case PeakVariant::kAvx512Fma:
      return __builtin_cpu_supports("avx512f");
  }
  return false;
}

namespace detail {
// Chains: latency (4 cycles for FMA, 3 + 2 for MUL + ADD on Zen, 4 + 4 on Intel) times two
// pipes, within the register file (16 xmm / ymm registers, 32 zmm).
constexpr int kChainsNarrow = 12;
constexpr int kChainsWide = 24;

#define LOSMIMO_PEAK_BODY(VEC, SET1, OP, CH)                                         \
  VEC acc[CH];                                                                       \
  for (int i = 0; i < CH; ++i) acc[i] = SET1(1.0 + i * 1e-3);                        \
  const VEC b = SET1(0.9999999);                                                     \
  const VEC c = SET1(1e-7);                                                          \
  for (std::int64_t r = 0; r < reps; ++r) {                                          \
    _Pragma("GCC unroll 32") for (int i = 0; i < CH; ++i) acc[i] = OP(acc[i], b, c); \
  }                                                                                  \
  double sum = 0.0;                                                                  \
  for (int i = 0; i < CH; ++i) {                                                     \
    double t[8];                                                                     \
    __builtin_memcpy(t, &acc[i], sizeof(double));                                    \
    sum += t[0];                                                                     \
  }                                                                                  \
  return sum;

inline __m128d sd_muladd(__m128d a, __m128d b, __m128d c) { return _mm_add_sd(_mm_mul_sd(a, b), c); }
__attribute__((target("fma"))) inline __m128d sd_fma(__m128d a, __m128d b, __m128d c) { return _mm_fmadd_sd(a, b, c); }
inline __m128d pd2_muladd(__m128d a, __m128d b, __m128d c) { return _mm_add_pd(_mm_mul_pd(a, b), c); }
__attribute__((target("avx2"))) inline __m256d pd4_muladd(__m256d a, __m256d b, __m256d c) {
  return _mm256_add_pd(_mm256_mul_pd(a, b), c);
}
__attribute__((target("avx2,fma"))) inline __m256d pd4_fma(__m256d a, __m256d b, __m256d c) {
  return _mm256_fmadd_pd(a, b, c);
}
__attribute__((target("avx512f"))) inline __m512d pd8_muladd(__m512d a, __m512d b, __m512d c) {
  return _mm512_add_pd(_mm512_mul_pd(a, b), c);
}
__attribute__((target("avx512f"))) inline __m512d pd8_fma(__m512d a, __m512d b, __m512d c) {
  return _mm512_fmadd_pd(a, b, c);
}

__attribute__((noinline)) inline double run_scalar(std::int64_t reps) {
  LOSMIMO_PEAK_BODY(__m128d, _mm_set1_pd, sd_muladd, kChainsNarrow)
}
__attribute__((noinline, target("fma"))) inline double run_scalar_fma(std::int64_t reps) {
  LOSMIMO_PEAK_BODY(__m128d, _mm_set1_pd, sd_fma, kChainsNarrow)
}
__attribute__((noinline)) inline double run_sse2(std::int64_t reps) {
  LOSMIMO_PEAK_BODY(__m128d, _mm_set1_pd, pd2_muladd, kChainsNarrow)
}
__attribute__((noinline, target("avx2"))) inline double run_avx2(std::int64_t reps) {
  LOSMIMO_PEAK_BODY(__m256d, _mm256_set1_pd, pd4_muladd, kChainsNarrow)
}
__attribute__((noinline, target("avx2,fma"))) inline double run_avx2_fma(std::int64_t reps) {
  LOSMIMO_PEAK_BODY(__m256d, _mm256_set1_pd, pd4_fma, kChainsNarrow)
}
__attribute__((noinline, target("avx512f"))) inline double run_avx512(std::int64_t reps) {
  LOSMIMO_PEAK_BODY(__m512d, _mm512_set1_pd, pd8_muladd, kChainsWide)
}
__attribute__((noinline, target("avx512f"))) inline double run_avx512_fma(std::int64_t reps) {
  LOSMIMO_PEAK_BODY(__m512d, _mm512_set1_pd, pd8_fma, kChainsWide)
}
#undef LOSMIMO_PEAK_BODY
}  // namespace detail

// Runs `reps` rounds of variant v; returns a value to keep.
inline double run_peak(PeakVariant v, std::int64_t reps) {
  using namespace detail;
  switch (v) {
    case PeakVariant::kScalar:
      return run_scalar(reps);
    case PeakVariant::kScalarFma:
      return run_scalar_fma(reps);
    case PeakVariant::kSse2:
      return run_sse2(reps);
    case PeakVariant::kAvx2NoFma:
      return run_avx2(reps);
    case PeakVariant::kAvx2Fma:
      return run_avx2_fma(reps);
    case PeakVariant::kAvx512NoFma:
      return run_avx512(reps);
    case PeakVariant::kAvx512Fma:
      return run_avx512_fma(reps);
  }
  return 0.0;
}

// Flops done by run_peak(v, reps).
inline double peak_flops(PeakVariant v, std::int64_t reps) {
  int lanes = 1, chains = detail::kChainsNarrow;
  switch (v) {
    case PeakVariant::kScalar:
    case PeakVariant::kScalarFma:
      lanes = 1;
      break;
    case PeakVariant::kSse2:
      lanes = 2;
      break;
    case PeakVariant::kAvx2NoFma:
    case PeakVariant::kAvx2Fma:
      lanes = 4;
      break;
    case PeakVariant::kAvx512NoFma:
    case PeakVariant::kAvx512Fma:
      lanes = 8;
      chains = detail::kChainsWide;
      break;
  }
  return 2.0 * static_cast<double>(reps) * chains * lanes;
}

// Peak flops/s of v, the best of 7 runs of ~3 ms each (thread CPU time would be better, but
// these runs are short enough that preemption shows as an outlier the max discards).
inline double measure_peak_flops_per_s(PeakVariant v) {
  constexpr std::int64_t kReps = 200000;
  double best = 0.0;
  volatile double sink = 0.0;
  for (int i = 0; i < 7; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    sink = sink + run_peak(v, kReps);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (s > 0.0) best = std::max(best, peak_flops(v, kReps) / s);
  }
  return best;
}

}  // namespace losmimo::bench
