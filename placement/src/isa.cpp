#include "losmimo/placement/isa.h"

#include "losmimo/placement/common/text.h"

#include <cstdlib>
#include <iterator>
#include <stdexcept>

namespace losmimo::placement {

std::string to_string(Isa isa) {
  switch (isa) {
    case Isa::kSse2:
      return "sse2";
    case Isa::kAvx2:
      return "avx2";
    case Isa::kAvx512:
      return "avx512";
  }
  return "unknown";
}

std::string isa_name_requirement() {
  std::string names;
  const std::size_t count = std::size(kAllIsas);
  for (std::size_t i = 0; i < count; ++i) {
    names += (i == 0 ? "" : i + 1 == count ? " or " : ", ") + to_string(kAllIsas[i]);
  }
  return "must be " + names;
}

Isa isa_from_string(const std::string& text) {
  for (const Isa isa : kAllIsas) {
    if (text == to_string(isa)) return isa;
  }
  throw std::invalid_argument("instruction set '" + text + "': " + isa_name_requirement());
}

bool isa_supported(Isa isa) {
#if defined(__x86_64__) && defined(__GNUC__)
  __builtin_cpu_init();
  switch (isa) {
    case Isa::kSse2:
      return true;  // the x86-64 baseline
    case Isa::kAvx2:
      return __builtin_cpu_supports("avx2");
    case Isa::kAvx512:
      // The AVX-512 kernels also use DQ (64-bit integer multiplies, conversions) and VL.
      return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
             __builtin_cpu_supports("avx512vl");
  }
  return false;
#else
  return isa == Isa::kSse2;  // the portable build: GCC vector extensions at 2 lanes
#endif
}

std::vector<Isa> supported_isas() {
  std::vector<Isa> out;
  for (const Isa isa : kAllIsas) {
    if (isa_supported(isa)) out.push_back(isa);
  }
  return out;
}

namespace {
Isa choose_isa() {
  const char* forced = std::getenv(kIsaEnvironmentVariable);
  if (forced == nullptr || *forced == '\0') return supported_isas().back();
  Isa isa = Isa::kSse2;
  try {
    isa = isa_from_string(forced);
  } catch (const std::invalid_argument&) {
    throw std::invalid_argument(std::string(kIsaEnvironmentVariable) + " = '" + forced +
                                "': " + isa_name_requirement());
  }
  if (!isa_supported(isa)) {
    const std::string have = common::join_with(supported_isas(), [](Isa s) { return to_string(s); });
    throw std::invalid_argument(std::string(kIsaEnvironmentVariable) + " = '" + forced +
                                "': this CPU does not support it (it supports " + have + ")");
  }
  return isa;
}
}  // namespace

Isa active_isa() {
  static const Isa isa = choose_isa();  // a throw leaves it unset: the next call throws again
  return isa;
}

}  // namespace losmimo::placement
