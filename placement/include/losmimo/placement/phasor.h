#pragma once
// Unit phasors exp(j phase) of a block of phases: the Nt sincos of every channel row.
//
// The phase is reduced by the nearest multiple n of pi/2, with pi/2 in three parts so that
// the reduced argument is accurate to ~1e-16 rad for |phase| < 2e8 rad (channel phases at
// 1 km and 60 GHz are ~1.3e6 rad), then truncated Taylor series on |y| <= pi/4 give sin and
// cos within 1 ulp of the correctly rounded values (tested against glibc). Beyond 2e8 rad, and
// for non-finite phases, std::cos / std::sin (NaN stays NaN). The same bits on every
// instruction set (kernels.h).

namespace losmimo::placement {

// c[k] = cos(phase_rad[k]), s[k] = sin(phase_rad[k]) for k < n, with this process's kernels
// (isa.h). The arrays may not overlap.
void unit_phasors(const double* phase_rad, double* c, double* s, int n);

}  // namespace losmimo::placement
