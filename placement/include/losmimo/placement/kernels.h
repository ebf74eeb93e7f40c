#pragma once
// The placement hot loops as plain kernels over split real/imaginary arrays, one table per
// instruction set (isa.h), plus a straightforward scalar reference table that tests compare
// them against. Planners reach them through ChannelModel, SwarmChannel, UavObjective and Swarm;
// only those, the benchmarks and the kernel tests call them directly.
//
// Symbols (swarm_channel.h): x the channel row of the UAV being moved (length Nt), o its row
// now (x_o in the formulas), G = H^H H the Gram matrix with o in it, A = G - conj(o) o^T the
// others' Gram matrix ("leave-one-out"), M = conj(A), p_l = |x_l|^2, S = sum_l p_l,
// Q = sum_l p_l^2, F_A = sum_{l != k} |A_lk|^2. The objective with row x in place of o:
//   f(x) = F_A + 2 sum_{l != k} Re(conj(x_l) M_lk x_k) + S^2 - Q
//        = F_A + 4 sum_{l < k} Re(conj(x_l) M_lk x_k) + S^2 - Q.
// Channel row (channel.h): x_k = a_k exp(-j kappa d_k), d_k = |q - p_k|, kappa = 2 pi / lambda,
// a_k = 1 (far field) or R / d_k (exact gain).
//
// Layouts. Nt antennas are padded to ld = padded(Nt) (a multiple of kLanes): every array below
// has ld entries per column, and entries Nt .. ld-1 are 0 (the kernels keep them 0), so vector
// loops need no tails. Split planes: a complex vector v is (v_re[0..ld), v_im[0..ld)); G is
// (G_re, G_im), column-major with leading dimension ld: G(l, k) = G_re[l + k ld] + j G_im[...].
// "Lanes": up to kLanes rows side by side, X_re[k kLanes + p] = Re(row p)_k, so that
// candidate positions (BF's probes, GD's escape grid) fill the vector lanes.
//
// Rounding: the same bits on every instruction set. No multiply-add is fused, elementwise
// arithmetic is the same IEEE operations at any vector width, and every sum over antennas is
// kept as 8 interleaved partial sums added in a fixed order, which an AVX-512 register, two
// AVX2 or four SSE2 registers hold alike. So a process forced to SSE2 (LOSMIMO_ISA) computes
// what an AVX-512 one does, and shards from different x86-64 machines merge byte-identically
// (as far as the C library's own cos/sin/log/pow agree; glibc picks its variants by CPU).
// Fusing would buy nothing on the cores measured (Zen 5: multiply + add reach the FMA peak)
// and a 1-ulp difference in a channel row grows to ~5e-8 in a GD run's final SINR after 1000
// iterations under actuation error (measured). Within one process the kernels are
// deterministic: no dependence on threads, alignment or call history.

#include <cstdint>

#include "losmimo/placement/isa.h"

namespace losmimo::placement::kernels {

inline constexpr int kLanes = 8;
// Numbers per block of the normals kernel: kLanes Box-Muller pairs, the cosines then the sines.
inline constexpr int kNormalsPerBlock = 2 * kLanes;
constexpr int padded(int n) { return (n + kLanes - 1) / kLanes * kLanes; }

// The BS array as the row kernels see it.
struct RowGeometry {
  int nt = 0;                    // antennas
  int ld = 0;                    // padded(nt)
  const double* ax_m = nullptr;  // antenna coordinates (m), ld entries (pads: 0)
  const double* ay_m = nullptr;
  const double* az_m = nullptr;
  const double* valid = nullptr;  // 1 for an antenna, 0 for a pad (ld entries)
  double wavenumber_rad_per_m = 0.0;
  double range_m = 0.0;     // R of the exact gain's R / d
  bool exact_gain = false;  // GainModel::kExact
};

// A Hermitian matrix (the Gram matrix) in split planes, n x n with leading dimension ld.
struct GramPlanes {
  int n = 0;
  int ld = 0;
  const double* re = nullptr;
  const double* im = nullptr;
};

// Complex vectors below are split planes of ld entries: (re, im).
struct Kernels {
  Isa isa;
  // c[k] = cos(phase[k]), s[k] = sin(phase[k]), k < n (any n, no padding needed), within
  // ~1 ulp of glibc for |phase| < 2e8 rad; beyond that (and for non-finite phases) the C
  // library's cos and sin.
  void (*unit_phasors)(const double* phase_rad, double* c, double* s, int n);
  // The channel row at q_m into (xr, xi).
  void (*row)(const RowGeometry& g, const double q_m[3], double* xr, double* xi);
  // The rows at kLanes positions (px[p], py[p], pz[p]) into the lanes layout (ld x kLanes).
  void (*rows_lanes)(const RowGeometry& g, const double* px_m, const double* py_m, const double* pz_m, double* Xr,
                     double* Xi);
  // F_A = sum_{l != k} |A_lk|^2 for the row o = (or_, oi).
  double (*leave_one_out_energy)(const GramPlanes& G, const double* or_, const double* oi);
  // f of each of the kLanes rows of (Xr, Xi) in place of o (the triangle form above, F_A from
  // the same pass over M's triangle).
  void (*objectives_lanes)(const GramPlanes& G, const double* or_, const double* oi, const double* Xr, const double* Xi,
                           double* f);
  // f of one row x in place of o (the full Hermitian form, one matrix-vector product).
  double (*objective_of_row)(const GramPlanes& G, const double* or_, const double* oi, double F_A, const double* xr,
                             const double* xi);
  // f of the row at q_m: row + objective_of_row, the same bits.
  double (*objective_at)(const RowGeometry& g, const GramPlanes& G, const double* or_, const double* oi, double F_A,
                         const double q_m[3]);
  // grad f at q_m into grad[3] (swarm_channel.h); returns f at q_m, bit for bit objective_at's.
  double (*gradient)(const RowGeometry& g, const GramPlanes& G, const double* or_, const double* oi, double F_A,
                     const double q_m[3], double* grad);
  // G += conj(x) x^T - conj(o) o^T over the whole matrix: entry (k, l) gets exactly the
  // conjugate of entry (l, k), so G stays Hermitian bit for bit. G must not overlap x or o.
  void (*gram_update)(double* G_re, double* G_im, int n, int ld, const double* xr, const double* xi, const double* or_,
                      const double* oi);
  // G = sum_m conj(h_m) h_m^T of the nr rows h_m = (Hr + m ld, Hi + m ld), the whole n x n
  // matrix, each entry summed in row order (m = 0 first): entry (k, l) is exactly the
  // conjugate of entry (l, k). For a swarm whose every row changed (no rank updates).
  void (*gram_of_rows)(const double* Hr, const double* Hi, int nr, int n, int ld, double* G_re, double* G_im);
  // y = G v.
  void (*hermitian_matvec)(const GramPlanes& G, const double* vr, const double* vi, double* yr, double* yi);
  // The factorisation G - sI = L D L^H from G's lower triangle (what is above it does not
  // matter): L unit lower triangular below the diagonal of (Lr, Li) (ld x n, column-major), the
  // real pivots d_j on it (Li 0 there; the entries above are scratch). No square roots: it only
  // proves (a pivot d_j <= 0 says G - sI is not positive definite). The vector builds are
  // left-looking (simd/gram.inc: column j from G's column j less every earlier column's
  // update, in column order; the same bits on every build); the scalar reference is
  // right-looking and agrees with them to rounding, not bit for bit.
  // Returns n if every pivot is positive; else the first column j whose pivot is not (columns
  // 0 .. j-1 complete), or -1 if that pivot is NaN (nothing proved).
  int (*shifted_ldl)(const GramPlanes& G, double s, double* Lr, double* Li);
  // One Gram-Schmidt pass of w against the `count` orthonormal vectors v_j = (Vr + j ld,
  // Vi + j ld): c_j = v_j^H w for every j first, then w -= c_j v_j in j order; returns |w|^2
  // after. Each sum over antennas in 8 partial sums combined as ((s0 + s2) + (s4 + s6)) +
  // ((s1 + s3) + (s5 + s7)): the order of the same pass with fixed-size Eigen arrays, whose bits
  // it gives (tests/placement/reorthogonalise_test.cpp).
  double (*reorthogonalise)(const double* Vr, const double* Vi, int ld, int count, double* wr, double* wi);
  // Standard normal numbers of the counter-based stream `key`: blocks first_block ..
  // first_block + blocks - 1, kNormalsPerBlock numbers each, into out (kNormalsPerBlock blocks
  // doubles). Number i of a stream depends on (key, i) only (swarm.h has the definition).
  void (*normals)(std::uint64_t key, std::uint64_t first_block, double* out, int blocks);
};

// The table of an instruction set; throws std::invalid_argument if this CPU cannot run it.
const Kernels& kernels_for(Isa isa);
// The table of active_isa().
const Kernels& active_kernels();
// The scalar reference: the formulas above written plainly (std::complex, std::cos/std::sin,
// std::log), for tests and as the readable definition. isa is kSse2; not fast.
const Kernels& reference_kernels();

}  // namespace losmimo::placement::kernels
