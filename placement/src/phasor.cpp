#include "losmimo/placement/phasor.h"

#include "losmimo/placement/kernels.h"

namespace losmimo::placement {

void unit_phasors(const double* phase_rad, double* c, double* s, int n) {
  kernels::active_kernels().unit_phasors(phase_rad, c, s, n);
}

}  // namespace losmimo::placement
