#pragma once
// Seeds: every random stream in losmimo comes from a base seed and a path of indices, so a
// trial's numbers depend on (seed, path) only, never on threads, shards or resumes.
//
//   splitmix64(x)  the SplitMix64 finaliser (Steele, Lea, Flood 2014): nearby inputs give
//                  unrelated outputs; splitmix64(x) = splitmix64_mix(x + kSplitMix64Gamma)
//   splitmix64_at(key, j)
//                  output j (j = 0, 1, ...) of the SplitMix64 generator seeded with key:
//                  splitmix64_mix(key + (j + 1) gamma), any j directly (counter-based streams)
//   derive_seed(base, {p1, p2, ...}, salt)
//                  h = splitmix64(base); h = splitmix64(h ^ splitmix64(p_i + salt)) per index.
//   tagged_seed(base, tag)
//                  base ^ tag: a stream keyed by the base seed and a fixed tag, unmixed, for a
//                  generator that spreads its seed over its state itself (std::mt19937_64). The
//                  recorder's CSI stream (rawlog/recorder.h) is one: its logs' CSI depends on it.
// The experiment's streams use the default salt; the closed loop's per-UAV streams use salt 0
// (the seeds of the recorded missions, which replay bit for bit only with them).

#include <cstdint>
#include <initializer_list>

namespace losmimo::common {

inline constexpr std::uint64_t kDefaultSeedSalt = 0x632be59bd9b4e019ULL;

inline constexpr std::uint64_t kSplitMix64Gamma = 0x9e3779b97f4a7c15ULL;  // the state's increment

// SplitMix64's output function of a state z (the vector kernels, placement/src/simd/normals.inc,
// apply it lane by lane).
constexpr std::uint64_t splitmix64_mix(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

constexpr std::uint64_t splitmix64(std::uint64_t x) { return splitmix64_mix(x + kSplitMix64Gamma); }

constexpr std::uint64_t splitmix64_at(std::uint64_t key, std::uint64_t j) {
  return splitmix64_mix(key + (j + 1) * kSplitMix64Gamma);
}

constexpr std::uint64_t derive_seed(std::uint64_t base, std::initializer_list<std::uint64_t> path,
                                    std::uint64_t salt = kDefaultSeedSalt) {
  std::uint64_t h = splitmix64(base);
  for (const std::uint64_t p : path) h = splitmix64(h ^ splitmix64(p + salt));
  return h;
}

constexpr std::uint64_t tagged_seed(std::uint64_t base, std::uint64_t tag) { return base ^ tag; }

}  // namespace losmimo::common
