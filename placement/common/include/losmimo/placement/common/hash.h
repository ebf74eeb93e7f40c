#pragma once
// FNV-1a, 64 bit: a fast non-cryptographic digest of bytes (rawlog integrity marks, experiment
// records) and of names (a sweep's name in its seed path). It detects accidental change, not
// tampering.

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace losmimo::common {

inline constexpr std::uint64_t kFnvOffset = 0xcbf29ce484222325ULL;

// Continues from `hash` (kFnvOffset for a fresh digest).
inline std::uint64_t fnv1a64(const void* data, std::size_t size, std::uint64_t hash = kFnvOffset) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= p[i];
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

inline std::uint64_t fnv1a64(std::string_view text, std::uint64_t hash = kFnvOffset) {
  return fnv1a64(text.data(), text.size(), hash);
}

}  // namespace losmimo::common
