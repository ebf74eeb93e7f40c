#include "losmimo/placement/kernels.h"

#include <stdexcept>

namespace losmimo::placement::kernels {

// One table per instruction-set build (simd/kernels_*.cpp).
extern const Kernels kSse2Table;
#if defined(LOSMIMO_HAVE_X86_KERNELS)
extern const Kernels kAvx2Table;
extern const Kernels kAvx512Table;
#endif

const Kernels& kernels_for(Isa isa) {
  if (!isa_supported(isa)) {
    throw std::invalid_argument("kernels: this CPU cannot run the " + to_string(isa) + " build");
  }
  switch (isa) {
#if defined(LOSMIMO_HAVE_X86_KERNELS)
    case Isa::kAvx512:
      return kAvx512Table;
    case Isa::kAvx2:
      return kAvx2Table;
#else
    case Isa::kAvx512:
    case Isa::kAvx2:
      break;
#endif
    case Isa::kSse2:
      return kSse2Table;
  }
  return kSse2Table;
}

const Kernels& active_kernels() {
  static const Kernels& table = kernels_for(active_isa());
  return table;
}

}  // namespace losmimo::placement::kernels
