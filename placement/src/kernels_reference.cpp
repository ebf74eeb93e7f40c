// The kernels of kernels.h written plainly: one complex number at a time, the C library's
// cos, sin and log, every sum in index order. The definition the vector builds are tested
// against (tests/placement/kernels_test.cpp), not a fast path.
#include <cmath>
#include <complex>
#include <vector>

#include "losmimo/placement/common/seed.h"
#include "losmimo/placement/kernels.h"

namespace losmimo::placement::kernels {

namespace {
using cd = std::complex<double>;

cd at(const double* re, const double* im, int i) { return {re[i], im[i]}; }
cd gram(const GramPlanes& G, int l, int k) { return at(G.re, G.im, l + k * G.ld); }

void unit_phasors(const double* phase_rad, double* c, double* s, int n) {
  for (int k = 0; k < n; ++k) {
    c[k] = std::cos(phase_rad[k]);
    s[k] = std::sin(phase_rad[k]);
  }
}

// x_k = a_k exp(-j kappa d_k); pads 0.
void row(const RowGeometry& g, const double q[3], double* xr, double* xi) {
  for (int k = 0; k < g.ld; ++k) {
    xr[k] = xi[k] = 0.0;
    if (k >= g.nt) continue;
    const double d = std::sqrt((q[0] - g.ax_m[k]) * (q[0] - g.ax_m[k]) + (q[1] - g.ay_m[k]) * (q[1] - g.ay_m[k]) +
                               (q[2] - g.az_m[k]) * (q[2] - g.az_m[k]));
    const double amplitude = g.exact_gain ? g.range_m / d : 1.0;
    const cd x = amplitude * std::polar(1.0, -g.wavenumber_rad_per_m * d);
    xr[k] = x.real();
    xi[k] = x.imag();
  }
}

void rows_lanes(const RowGeometry& g, const double* px, const double* py, const double* pz, double* Xr, double* Xi) {
  std::vector<double> xr(g.ld), xi(g.ld);
  for (int p = 0; p < kLanes; ++p) {
    const double q[3] = {px[p], py[p], pz[p]};
    row(g, q, xr.data(), xi.data());
    for (int k = 0; k < g.ld; ++k) {
      Xr[k * kLanes + p] = xr[k];
      Xi[k * kLanes + p] = xi[k];
    }
  }
}

// A_lk = G_lk - conj(o_l) o_k
cd leave_one_out(const GramPlanes& G, const double* or_, const double* oi, int l, int k) {
  return gram(G, l, k) - std::conj(at(or_, oi, l)) * at(or_, oi, k);
}

double leave_one_out_energy(const GramPlanes& G, const double* or_, const double* oi) {
  double sum = 0.0;
  for (int l = 0; l < G.n; ++l) {
    for (int k = 0; k < G.n; ++k) {
      if (l != k) sum += std::norm(leave_one_out(G, or_, oi, l, k));
    }
  }
  return sum;
}

// f = F_A + 2 sum_{l != k} Re(conj(x_l) conj(A_lk) x_k) + S^2 - Q
double objective_of_row(const GramPlanes& G, const double* or_, const double* oi, double F_A, const double* xr,
                        const double* xi) {
  double cross = 0.0, S = 0.0, Q = 0.0;
  for (int l = 0; l < G.n; ++l) {
    const double p = std::norm(at(xr, xi, l));
    S += p;
    Q += p * p;
    for (int k = 0; k < G.n; ++k) {
      if (l == k) continue;
      cross += (std::conj(at(xr, xi, l)) * std::conj(leave_one_out(G, or_, oi, l, k)) * at(xr, xi, k)).real();
    }
  }
  return F_A + 2.0 * cross + S * S - Q;
}

void objectives_lanes(const GramPlanes& G, const double* or_, const double* oi, const double* Xr, const double* Xi,
                      double* f) {
  const double F_A = leave_one_out_energy(G, or_, oi);
  std::vector<double> xr(G.ld), xi(G.ld);
  for (int p = 0; p < kLanes; ++p) {
    for (int k = 0; k < G.ld; ++k) {
      xr[k] = Xr[k * kLanes + p];
      xi[k] = Xi[k * kLanes + p];
    }
    f[p] = objective_of_row(G, or_, oi, F_A, xr.data(), xi.data());
  }
}

double objective_at(const RowGeometry& g, const GramPlanes& G, const double* or_, const double* oi, double F_A,
                    const double q[3]) {
  std::vector<double> xr(g.ld), xi(g.ld);
  row(g, q, xr.data(), xi.data());
  return objective_of_row(G, or_, oi, F_A, xr.data(), xi.data());
}

// grad f = 4 sum_l Re(conj(s_l) Q_l) u_l, Q_l = conj(x_l) sum_{k != l} conj(B_lk) x_k,
// B = A + conj(x) x^T, s_l = -j kappa (- 1 / d_l for the exact gain), u_l = (q - p_l) / d_l.
double gradient(const RowGeometry& g, const GramPlanes& G, const double* or_, const double* oi, double F_A,
                const double q[3], double* grad) {
  std::vector<double> xr(g.ld), xi(g.ld);
  row(g, q, xr.data(), xi.data());
  grad[0] = grad[1] = grad[2] = 0.0;
  for (int l = 0; l < g.nt; ++l) {
    const cd xl = at(xr.data(), xi.data(), l);
    cd sum = 0.0;
    for (int k = 0; k < g.nt; ++k) {
      if (k == l) continue;
      const cd B = leave_one_out(G, or_, oi, l, k) + std::conj(xl) * at(xr.data(), xi.data(), k);
      sum += std::conj(B) * at(xr.data(), xi.data(), k);
    }
    const double u[3] = {q[0] - g.ax_m[l], q[1] - g.ay_m[l], q[2] - g.az_m[l]};
    const double d = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    const cd s(g.exact_gain ? -1.0 / d : 0.0, -g.wavenumber_rad_per_m);
    const double w = 4.0 * (std::conj(s) * std::conj(xl) * sum).real();
    for (int i = 0; i < 3; ++i) grad[i] += w * u[i] / d;
  }
  return objective_of_row(G, or_, oi, F_A, xr.data(), xi.data());
}

void gram_update(double* G_re, double* G_im, int n, int ld, const double* xr, const double* xi, const double* or_,
                 const double* oi) {
  for (int k = 0; k < n; ++k) {
    for (int l = 0; l < n; ++l) {
      const cd delta = std::conj(at(xr, xi, l)) * at(xr, xi, k) - std::conj(at(or_, oi, l)) * at(or_, oi, k);
      G_re[l + k * ld] += delta.real();
      G_im[l + k * ld] += delta.imag();
    }
  }
}

void gram_of_rows(const double* Hr, const double* Hi, int nr, int n, int ld, double* G_re, double* G_im) {
  for (int k = 0; k < n; ++k) {
    for (int l = 0; l < ld; ++l) {
      cd sum = 0.0;
      for (int m = 0; m < nr; ++m) sum += std::conj(at(Hr + m * ld, Hi + m * ld, l)) * at(Hr + m * ld, Hi + m * ld, k);
      G_re[l + k * ld] = sum.real();
      G_im[l + k * ld] = sum.imag();
    }
  }
}

void hermitian_matvec(const GramPlanes& G, const double* vr, const double* vi, double* yr, double* yi) {
  for (int l = 0; l < G.ld; ++l) {
    cd sum = 0.0;
    for (int k = 0; k < G.n; ++k) sum += gram(G, l, k) * at(vr, vi, k);
    yr[l] = sum.real();
    yi[l] = sum.imag();
  }
}

int shifted_ldl(const GramPlanes& G, double s, double* Lr, double* Li) {
  const int n = G.n, ld = G.ld;
  std::vector<cd> L(static_cast<std::size_t>(ld) * n);
  for (int k = 0; k < n; ++k) {
    for (int l = 0; l < ld; ++l) L[l + k * ld] = gram(G, l, k) - (l == k ? s : 0.0);
  }
  int result = n;
  for (int j = 0; j < n; ++j) {
    const double d = L[j + j * ld].real();
    if (!(d > 0.0)) {
      result = std::isnan(d) ? -1 : j;
      break;
    }
    L[j + j * ld] = d;
    for (int i = j + 1; i < n; ++i) L[i + j * ld] /= d;
    // A_ik -= L_ij d conj(L_kj)
    for (int k = j + 1; k < n; ++k) {
      for (int i = k; i < n; ++i) L[i + k * ld] -= L[i + j * ld] * d * std::conj(L[k + j * ld]);
    }
  }
  for (std::size_t i = 0; i < L.size(); ++i) {
    Lr[i] = L[i].real();
    Li[i] = L[i].imag();
  }
  return result;
}

double reorthogonalise(const double* Vr, const double* Vi, int ld, int count, double* wr, double* wi) {
  std::vector<cd> c(count);
  for (int j = 0; j < count; ++j) {
    for (int l = 0; l < ld; ++l) c[j] += std::conj(at(Vr + j * ld, Vi + j * ld, l)) * at(wr, wi, l);
  }
  double norm2 = 0.0;
  for (int l = 0; l < ld; ++l) {
    cd w = at(wr, wi, l);
    for (int j = 0; j < count; ++j) w -= c[j] * at(Vr + j * ld, Vi + j * ld, l);
    wr[l] = w.real();
    wi[l] = w.imag();
    norm2 += std::norm(w);
  }
  return norm2;
}

void normals(std::uint64_t key, std::uint64_t first_block, double* out, int blocks) {
  const double ulp = std::ldexp(1.0, -52);
  for (int b = 0; b < blocks; ++b) {
    for (int i = 0; i < 8; ++i) {
      const std::uint64_t pair = 8 * (first_block + b) + i;
      const double u1 = 1.0 - static_cast<double>(common::splitmix64_at(key, 2 * pair) >> 12) * ulp;
      const double u2 = static_cast<double>(common::splitmix64_at(key, 2 * pair + 1) >> 12) * ulp;
      const double r = std::sqrt(-2.0 * std::log(u1));
      out[16 * b + i] = r * std::cos(2.0 * M_PI * u2);
      out[16 * b + 8 + i] = r * std::sin(2.0 * M_PI * u2);
    }
  }
}
}  // namespace

const Kernels& reference_kernels() {
  static const Kernels table = {
      Isa::kSse2,        &unit_phasors,     &row,          &rows_lanes,      &leave_one_out_energy,
      &objectives_lanes, &objective_of_row, &objective_at, &gradient,        &gram_update,
      &gram_of_rows,     &hermitian_matvec, &shifted_ldl,  &reorthogonalise, &normals};
  return table;
}

}  // namespace losmimo::placement::kernels
