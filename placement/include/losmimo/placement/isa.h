#pragma once
// The instruction set the placement kernels run on (kernels.h), chosen once per process.
//
// Default: the widest this CPU supports (AVX-512 > AVX2 > SSE2, the x86-64 baseline). The
// environment variable LOSMIMO_ISA = sse2 | avx2 | avx512 forces one (experiment_isa_test runs
// the app both ways). The kernels are written to give the same bits on every instruction set
// (kernels.h): the choice changes speed, not results.

#include <string>
#include <vector>

namespace losmimo::placement {

enum class Isa {
  kSse2,    // 2 doubles per vector (the x86-64 baseline)
  kAvx2,    // AVX2: 4 doubles per vector
  kAvx512,  // AVX-512 F/DQ/VL: 8 doubles per vector
};

inline constexpr Isa kAllIsas[] = {Isa::kSse2, Isa::kAvx2, Isa::kAvx512};  // narrowest first

std::string to_string(Isa isa);  // "sse2", "avx2", "avx512"
// "must be sse2, avx2 or avx512": what an error message says of a name that is none of them.
std::string isa_name_requirement();
// Parses the names above; throws std::invalid_argument naming the text otherwise.
Isa isa_from_string(const std::string& text);

bool isa_supported(Isa isa);
std::vector<Isa> supported_isas();  // narrowest first

inline constexpr const char* kIsaEnvironmentVariable = "LOSMIMO_ISA";

// The process's instruction set: LOSMIMO_ISA if set, else the widest supported. Decided at
// the first call. Throws std::invalid_argument naming LOSMIMO_ISA and its value if that is not
// a known name or this CPU cannot run it (every later call throws the same).
Isa active_isa();

}  // namespace losmimo::placement
