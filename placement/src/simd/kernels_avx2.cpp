// The placement kernels built for avx2 (flags in placement/CMakeLists.txt).
#define KW 4
#define KISA Isa::kAvx2
#define KTABLE kAvx2Table
#include "kernels.inc"
