#pragma once
// Unit phasors exp(j phase) of a block of phases: the Nt sincos of every channel row.
//
// Arguments are reduced exactly modulo the double nearest 2 pi (remainder_two_pi; it differs from
// 2 pi by 2.4e-16, so a phase of n turns moves by ~2.4e-16 n rad, 5e-11 rad at 1 km and 60 GHz,
// far below the rounding of the distance itself), then by quadrant to
// |y| <= pi/4 + 1e-15, where truncated Taylor series (up to y^15 for sin, y^16 for cos) are
// accurate to 1 ulp of the result (tested against std::sin/std::cos: <= 2 ulp worst case).
// Written here rather than taken from libmvec/SLEEF so that the loop vectorises with the
// compiler's baseline ISA and every lane does the same IEEE operations: results are the same
// bits on every x86-64 machine (no FMA contraction, no CPU-dependent dispatch), which keeps
// sharded and merged runs byte-identical across a heterogeneous cluster.
// Phases outside |x| < 4e8 rad or non-finite go through std::cos / std::sin (NaN stays NaN).

namespace losmimo::placement {

// std::remainder(x, 2 pi), bit for bit, without glibc's slow generic path (phase reduction
// of the channel rows: |x| ~ 1e6 rad at 1 km and 60 GHz).
double remainder_two_pi(double x);

// c[k] = cos(phase_rad[k]), s[k] = sin(phase_rad[k]) for k < n. The arrays may not overlap.
void unit_phasors(const double* phase_rad, double* c, double* s, int n);

}  // namespace losmimo::placement
