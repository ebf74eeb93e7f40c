// The placement kernels built for avx512 (flags in placement/CMakeLists.txt).
#define KW 8
#define KISA Isa::kAvx512
#define KTABLE kAvx512Table
#include "kernels.inc"
