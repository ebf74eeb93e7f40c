// The placement kernels built for sse2 (flags in placement/CMakeLists.txt).
#define KW 2
#define KISA Isa::kSse2
#define KTABLE kSse2Table
#include "kernels.inc"
