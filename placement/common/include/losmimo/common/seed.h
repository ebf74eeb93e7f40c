#pragma once
// Seeds: every random stream in losmimo comes from a base seed and a path of indices, so a
// trial's numbers depend on (seed, path) only, never on threads, shards or resumes.
//
//   splitmix64(x)  the SplitMix64 finaliser (Steele, Lea, Flood 2014): nearby inputs give
//                  unrelated outputs
//   derive_seed(base, {p1, p2, ...}, salt)
//                  h = splitmix64(base); h = splitmix64(h ^ splitmix64(p_i + salt)) per index.
// The experiment's streams use the default salt; the closed loop's per-UAV streams use salt 0
// (their seeds predate the shared function, and recorded missions replay bit for bit only if
// they stay as they are).

#include <cstdint>
#include <initializer_list>

namespace losmimo::common {

inline constexpr std::uint64_t kDefaultSeedSalt = 0x632be59bd9b4e019ULL;

constexpr std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

constexpr std::uint64_t derive_seed(std::uint64_t base, std::initializer_list<std::uint64_t> path,
                                    std::uint64_t salt = kDefaultSeedSalt) {
  std::uint64_t h = splitmix64(base);
  for (const std::uint64_t p : path) h = splitmix64(h ^ splitmix64(p + salt));
  return h;
}

}  // namespace losmimo::common
