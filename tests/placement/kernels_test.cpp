// Every instruction-set build of the placement kernels (kernels.h) against the plain scalar
// reference on random inputs, at Nt = 12 (padded), 16 and 64, and the properties the planners
// rely on: the Gram update keeps G Hermitian bit for bit and is the same on every build, the
// gradient's f is objective_at's, and the counter-based normals are the stream kernels.h
// defines.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "losmimo/placement/kernels.h"
#include "losmimo/placement/scenario.h"

namespace lp = losmimo::placement;
namespace lk = losmimo::placement::kernels;

namespace {
constexpr double kEps = 2.220446049250313e-16;

// The BS array of a Scenario in the kernels' padded layout, and a random swarm's Gram matrix.
struct KernelInputs {
  std::vector<double> ax, ay, az, valid;
  lk::RowGeometry geometry;
  std::vector<double> gr, gi;  // G, split planes (ld x n)
  std::vector<double> hr, hi;  // the rows, one per UAV, each ld long
  int nr = 0;
  lk::GramPlanes gram() const { return {geometry.nt, geometry.ld, gr.data(), gi.data()}; }
  const double* row_re(int m) const { return hr.data() + m * geometry.ld; }
  const double* row_im(int m) const { return hi.data() + m * geometry.ld; }
};

KernelInputs make_inputs(int rows, int cols, bool exact_gain, std::uint64_t seed) {
  lp::Scenario s;
  s.bs_rows = rows;
  s.bs_cols = cols;
  s.num_uavs = rows * cols;
  s.gain_model = exact_gain ? lp::GainModel::kExact : lp::GainModel::kFarField;
  const Eigen::Matrix3Xd p = lp::bs_antenna_positions_m(s);
  KernelInputs out;
  const int nt = s.num_bs_antennas(), ld = lk::padded(nt);
  out.ax.assign(ld, 0.0);
  out.ay.assign(ld, 0.0);
  out.az.assign(ld, 0.0);
  out.valid.assign(ld, 0.0);
  for (int k = 0; k < nt; ++k) {
    out.ax[k] = p(0, k);
    out.ay[k] = p(1, k);
    out.az[k] = p(2, k);
    out.valid[k] = 1.0;
  }
  out.geometry = {nt,
                  ld,
                  out.ax.data(),
                  out.ay.data(),
                  out.az.data(),
                  out.valid.data(),
                  2 * M_PI / s.wavelength_m(),
                  s.range_m(),
                  exact_gain};
  std::mt19937_64 rng(seed);
  const Eigen::Matrix3Xd q = lp::random_start_positions_m(s, rng);
  out.nr = s.num_uavs;
  out.hr.assign(static_cast<std::size_t>(ld) * out.nr, 0.0);
  out.hi.assign(static_cast<std::size_t>(ld) * out.nr, 0.0);
  for (int m = 0; m < out.nr; ++m) {
    const double qm[3] = {q(0, m), q(1, m), q(2, m)};
    lk::reference_kernels().row(out.geometry, qm, out.hr.data() + m * ld, out.hi.data() + m * ld);
  }
  // G = sum_m conj(h_m) h_m^T, in long double, rounded once.
  out.gr.assign(static_cast<std::size_t>(ld) * nt, 0.0);
  out.gi.assign(static_cast<std::size_t>(ld) * nt, 0.0);
  for (int k = 0; k < nt; ++k) {
    for (int l = 0; l < nt; ++l) {
      long double re = 0, im = 0;
      for (int m = 0; m < out.nr; ++m) {
        const long double ar = out.hr[m * ld + l], ai = out.hi[m * ld + l];
        const long double br = out.hr[m * ld + k], bi = out.hi[m * ld + k];
        re += ar * br + ai * bi;
        im += ar * bi - ai * br;
      }
      out.gr[l + k * ld] = static_cast<double>(re);
      out.gi[l + k * ld] = static_cast<double>(im);
    }
  }
  return out;
}

std::vector<const lk::Kernels*> builds() {
  std::vector<const lk::Kernels*> out;
  for (const lp::Isa isa : lp::supported_isas()) out.push_back(&lk::kernels_for(isa));
  return out;
}

// Positions around UAV m's: kLanes of them, up to 2 m away.
void random_lanes(const KernelInputs& s, std::mt19937_64& rng, double* px, double* py, double* pz) {
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int p = 0; p < lk::kLanes; ++p) {
    px[p] = 1000.0 + u(rng) * 10;
    py[p] = u(rng) * 10;
    pz[p] = u(rng) * 10;
  }
  (void)s;
}

struct Size {
  int rows, cols;
  bool exact;
};
const Size kSizes[] = {{4, 4, false}, {3, 4, false}, {8, 8, false}, {4, 4, true}};
}  // namespace

TEST(Kernels, UnitPhasors_AgreeWithGlibcToOneUlpOnEveryBuild) {
  std::mt19937_64 rng(1);
  std::vector<double> phase;
  std::uniform_real_distribution<double> small(-10.0, 10.0), channel(-1.4e6, -1.1e6), large(-1.9e8, 1.9e8);
  for (int i = 0; i < 30000; ++i) phase.insert(phase.end(), {small(rng), channel(rng), large(rng)});
  for (int j = -16; j <= 16; ++j) {  // quadrant boundaries and their neighbours
    const double b = j * M_PI_4;
    phase.insert(phase.end(), {b, std::nextafter(b, 100.0), std::nextafter(b, -100.0)});
  }
  phase.insert(phase.end(), {0.0, -0.0, 1e-300, 5e-324});
  const int n = static_cast<int>(phase.size());  // not a multiple of any vector width: tails too
  for (const lk::Kernels* k : builds()) {
    std::vector<double> c(n), s(n);
    k->unit_phasors(phase.data(), c.data(), s.data(), n);
    double worst = 0.0;
    for (int i = 0; i < n; ++i) {
      worst = std::max({worst, std::abs(c[i] - std::cos(phase[i])), std::abs(s[i] - std::sin(phase[i]))});
    }
    EXPECT_LE(worst, kEps) << lp::to_string(k->isa);
  }
}

TEST(Kernels, UnitPhasors_HugeAndNonFinitePhases_TakeTheLibraryPathInsideABlock) {
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<double> phase = {1.0, 1e12, -7.3e15, 2.0, std::nan(""), inf, -inf, 3.0, 2.5e8};
  const int n = static_cast<int>(phase.size());
  for (const lk::Kernels* k : builds()) {
    std::vector<double> c(n), s(n);
    k->unit_phasors(phase.data(), c.data(), s.data(), n);
    for (int i : {0, 1, 2, 3, 7, 8}) {
      EXPECT_NEAR(c[i], std::cos(phase[i]), kEps) << lp::to_string(k->isa) << " " << phase[i];
      EXPECT_NEAR(s[i], std::sin(phase[i]), kEps) << lp::to_string(k->isa) << " " << phase[i];
    }
    for (int i : {4, 5, 6}) EXPECT_TRUE(std::isnan(c[i]) && std::isnan(s[i])) << lp::to_string(k->isa);
  }
}

TEST(Kernels, Rows_MatchTheReferenceAndKeepPadsZero) {
  for (const Size& size : kSizes) {
    const KernelInputs s = make_inputs(size.rows, size.cols, size.exact, 11);
    const lk::RowGeometry& g = s.geometry;
    std::mt19937_64 rng(12);
    double px[lk::kLanes], py[lk::kLanes], pz[lk::kLanes];
    random_lanes(s, rng, px, py, pz);
    std::vector<double> ref_r(g.ld * lk::kLanes), ref_i(g.ld * lk::kLanes);
    lk::reference_kernels().rows_lanes(g, px, py, pz, ref_r.data(), ref_i.data());
    for (const lk::Kernels* k : builds()) {
      std::vector<double> Xr(g.ld * lk::kLanes, 7.0), Xi(g.ld * lk::kLanes, 7.0);
      k->rows_lanes(g, px, py, pz, Xr.data(), Xi.data());
      for (int p = 0; p < lk::kLanes; ++p) {
        std::vector<double> xr(g.ld, 7.0), xi(g.ld, 7.0);
        const double q[3] = {px[p], py[p], pz[p]};
        k->row(g, q, xr.data(), xi.data());
        for (int a = 0; a < g.ld; ++a) {
          // The phase (~1.3e6 rad) is the same double on every path; only sincos differs.
          const double amplitude = size.exact ? 1.1 : 1.0;
          EXPECT_NEAR(xr[a], ref_r[a * lk::kLanes + p], 2 * amplitude * kEps) << lp::to_string(k->isa);
          EXPECT_NEAR(xi[a], ref_i[a * lk::kLanes + p], 2 * amplitude * kEps) << lp::to_string(k->isa);
          // The lanes path computes each entry with the same operations as the single row.
          EXPECT_EQ(xr[a], Xr[a * lk::kLanes + p]);
          EXPECT_EQ(xi[a], Xi[a * lk::kLanes + p]);
          if (a >= g.nt) {
            EXPECT_TRUE(xr[a] == 0.0 && xi[a] == 0.0 && Xr[a * lk::kLanes + p] == 0.0);
          }
        }
      }
    }
  }
}

TEST(Kernels, Objectives_MatchTheReferenceAndTheDirectSumOfSquaredGramEntries) {
  for (const Size& size : kSizes) {
    const KernelInputs s = make_inputs(size.rows, size.cols, size.exact, 21);
    const lk::RowGeometry& g = s.geometry;
    const lk::GramPlanes G = s.gram();
    std::mt19937_64 rng(22);
    for (int m : {0, s.nr / 2, s.nr - 1}) {
      const double* o_r = s.row_re(m);
      const double* o_i = s.row_im(m);
      const double F_A = lk::reference_kernels().leave_one_out_energy(G, o_r, o_i);
      double px[lk::kLanes], py[lk::kLanes], pz[lk::kLanes];
      random_lanes(s, rng, px, py, pz);
      std::vector<double> Xr(g.ld * lk::kLanes), Xi(g.ld * lk::kLanes);
      lk::reference_kernels().rows_lanes(g, px, py, pz, Xr.data(), Xi.data());
      double f_ref[lk::kLanes];
      lk::reference_kernels().objectives_lanes(G, o_r, o_i, Xr.data(), Xi.data(), f_ref);
      // The reference itself against f = sum_{l != k} |B_lk|^2 of the Gram matrix with the row
      // replaced, in long double (lane 0).
      {
        long double direct = 0;
        for (int l = 0; l < g.nt; ++l) {
          for (int k = 0; k < g.nt; ++k) {
            if (l == k) continue;
            const auto e = [&](const double* re, const double* im, int a, int b, long double& rr, long double& ii) {
              rr = static_cast<long double>(re[a]) * re[b] + static_cast<long double>(im[a]) * im[b];
              ii = static_cast<long double>(re[a]) * im[b] - static_cast<long double>(im[a]) * re[b];
            };
            long double xr_ = 0, xi_ = 0, or__ = 0, oi_ = 0;
            std::vector<double> x0r(g.ld), x0i(g.ld);
            for (int a = 0; a < g.ld; ++a) {
              x0r[a] = Xr[a * lk::kLanes];
              x0i[a] = Xi[a * lk::kLanes];
            }
            e(x0r.data(), x0i.data(), l, k, xr_, xi_);
            e(o_r, o_i, l, k, or__, oi_);
            const long double br = G.re[l + k * g.ld] - or__ + xr_;
            const long double bi = G.im[l + k * g.ld] - oi_ + xi_;
            direct += br * br + bi * bi;
          }
        }
        EXPECT_NEAR(f_ref[0], static_cast<double>(direct), 1e-11 * static_cast<double>(direct));
      }
      const double scale = F_A + g.nt * g.nt;  // the size of the terms that cancel
      for (const lk::Kernels* k : builds()) {
        const std::string isa = lp::to_string(k->isa);
        EXPECT_NEAR(k->leave_one_out_energy(G, o_r, o_i), F_A, 1e-13 * scale) << isa;
        double f[lk::kLanes];
        k->objectives_lanes(G, o_r, o_i, Xr.data(), Xi.data(), f);
        for (int p = 0; p < lk::kLanes; ++p) {
          EXPECT_NEAR(f[p], f_ref[p], 1e-13 * scale) << isa << " lane " << p;
          const double q[3] = {px[p], py[p], pz[p]};
          const double f1 = k->objective_at(g, G, o_r, o_i, F_A, q);
          EXPECT_NEAR(f1, f_ref[p], 1e-13 * scale) << isa << " lane " << p;
          double grad[3];
          // The gradient's f is objective_at's, bit for bit.
          EXPECT_EQ(k->gradient(g, G, o_r, o_i, F_A, q, grad), f1) << isa;
        }
      }
    }
  }
}

TEST(Kernels, Gradient_MatchesTheReferenceAndCentralDifferences) {
  for (const Size& size : kSizes) {
    const KernelInputs s = make_inputs(size.rows, size.cols, size.exact, 31);
    const lk::RowGeometry& g = s.geometry;
    const lk::GramPlanes G = s.gram();
    std::mt19937_64 rng(32);
    double px[lk::kLanes], py[lk::kLanes], pz[lk::kLanes];
    random_lanes(s, rng, px, py, pz);
    const int m = 1;
    const double F_A = lk::reference_kernels().leave_one_out_energy(G, s.row_re(m), s.row_im(m));
    for (int p = 0; p < 3; ++p) {
      const double q[3] = {px[p], py[p], pz[p]};
      double ref[3];
      lk::reference_kernels().gradient(g, G, s.row_re(m), s.row_im(m), F_A, q, ref);
      // Five-point central differences of the reference objective, step 1e-4 m: the phase
      // (~1.3e6 rad) is rounded to ~2e-10 rad, which a smaller step would amplify; the
      // truncation error is ~(kappa h)^4 / 30 ~ 3e-6 relative.
      double fd[3];
      for (int i = 0; i < 3; ++i) {
        constexpr double h = 1e-4;
        const auto f_at = [&](double offset) {
          double a[3] = {q[0], q[1], q[2]};
          a[i] += offset;
          return lk::reference_kernels().objective_at(g, G, s.row_re(m), s.row_im(m), F_A, a);
        };
        fd[i] = (-f_at(2 * h) + 8 * f_at(h) - 8 * f_at(-h) + f_at(-2 * h)) / (12 * h);
      }
      const double norm = std::sqrt(ref[0] * ref[0] + ref[1] * ref[1] + ref[2] * ref[2]);
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(fd[i], ref[i], 1e-5 * norm) << i;
      for (const lk::Kernels* k : builds()) {
        double grad[3];
        k->gradient(g, G, s.row_re(m), s.row_im(m), F_A, q, grad);
        for (int i = 0; i < 3; ++i) EXPECT_NEAR(grad[i], ref[i], 1e-11 * norm) << lp::to_string(k->isa) << " " << i;
      }
    }
  }
}

TEST(Kernels, GramUpdate_StaysHermitianBitForBitAndIsTheSameOnEveryBuild) {
  const KernelInputs s = make_inputs(4, 4, false, 41);
  const int ld = s.geometry.ld, n = s.geometry.nt;
  std::vector<std::vector<double>> results;
  for (const lk::Kernels* k : builds()) {
    std::vector<double> gr = s.gr, gi = s.gi;
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> u(-3.0, 3.0);
    for (int step = 0; step < 500; ++step) {
      const int m = step % s.nr;
      std::vector<double> xr(ld, 0.0), xi(ld, 0.0);
      const double q[3] = {1000.0 + u(rng), u(rng) * 5, u(rng) * 5};
      lk::reference_kernels().row(s.geometry, q, xr.data(), xi.data());  // the same rows for every build
      k->gram_update(gr.data(), gi.data(), n, ld, xr.data(), xi.data(), s.row_re(m), s.row_im(m));
      for (int l = 0; l < n; ++l) {
        ASSERT_EQ(gi[l + l * ld], 0.0);
        for (int j = 0; j < n; ++j) {
          ASSERT_EQ(gr[l + j * ld], gr[j + l * ld]);
          ASSERT_EQ(gi[l + j * ld], -gi[j + l * ld]);
        }
      }
      // Undo, so that the next update removes a row that is really in G.
      k->gram_update(gr.data(), gi.data(), n, ld, s.row_re(m), s.row_im(m), xr.data(), xi.data());
    }
    // Against the reference update of the same inputs.
    std::vector<double> rr = s.gr, ri = s.gi, kr = s.gr, ki = s.gi;
    lk::reference_kernels().gram_update(rr.data(), ri.data(), n, ld, s.row_re(1), s.row_im(1), s.row_re(0),
                                        s.row_im(0));
    k->gram_update(kr.data(), ki.data(), n, ld, s.row_re(1), s.row_im(1), s.row_re(0), s.row_im(0));
    for (int i = 0; i < ld * n; ++i) {
      EXPECT_NEAR(kr[i], rr[i], 1e-13 * n);
      EXPECT_NEAR(ki[i], ri[i], 1e-13 * n);
    }
    gr.insert(gr.end(), gi.begin(), gi.end());
    results.push_back(gr);
  }
  for (std::size_t b = 1; b < results.size(); ++b) {
    EXPECT_EQ(std::memcmp(results[b].data(), results[0].data(), results[0].size() * sizeof(double)), 0) << b;
  }
}

TEST(Kernels, HermitianMatvec_MatchesTheReference) {
  const KernelInputs s = make_inputs(8, 8, false, 51);
  const lk::GramPlanes G = s.gram();
  std::mt19937_64 rng(52);
  std::normal_distribution<double> n01;
  std::vector<double> vr(G.ld, 0.0), vi(G.ld, 0.0);
  for (int l = 0; l < G.n; ++l) {
    vr[l] = n01(rng);
    vi[l] = n01(rng);
  }
  std::vector<double> rr(G.ld), ri(G.ld);
  lk::reference_kernels().hermitian_matvec(G, vr.data(), vi.data(), rr.data(), ri.data());
  for (const lk::Kernels* k : builds()) {
    std::vector<double> yr(G.ld), yi(G.ld);
    k->hermitian_matvec(G, vr.data(), vi.data(), yr.data(), yi.data());
    for (int l = 0; l < G.ld; ++l) {
      EXPECT_NEAR(yr[l], rr[l], 1e-12 * G.n * 8) << lp::to_string(k->isa);
      EXPECT_NEAR(yi[l], ri[l], 1e-12 * G.n * 8) << lp::to_string(k->isa);
    }
  }
}

TEST(Kernels, Normals_AreTheCounterStreamOfTheReferenceWhereverTheyStart) {
  constexpr int kBlocks = 301;  // odd: the last step is half used
  std::vector<double> ref(16 * kBlocks);
  lk::reference_kernels().normals(0x1234567890abcdefULL, 5, ref.data(), kBlocks);
  for (const lk::Kernels* k : builds()) {
    std::vector<double> all(16 * kBlocks);
    k->normals(0x1234567890abcdefULL, 5, all.data(), kBlocks);
    for (int i = 0; i < 16 * kBlocks; ++i) {
      ASSERT_NEAR(all[i], ref[i], 8 * kEps * std::max(1.0, std::abs(ref[i]))) << lp::to_string(k->isa) << " " << i;
    }
    // Counter-based: block b is the same whether drawn alone or inside a longer call.
    std::vector<double> one(16);
    k->normals(0x1234567890abcdefULL, 5 + 77, one.data(), 1);
    EXPECT_EQ(std::memcmp(one.data(), all.data() + 16 * 77, 16 * sizeof(double)), 0) << lp::to_string(k->isa);
  }
}

TEST(Kernels, Normals_HaveStandardNormalMomentsAndNoLagOneCorrelation) {
  // 2^20 numbers from 4 adjacent keys: standard errors of the mean 1e-3, of the variance
  // 1.4e-3, of the third moment 3.8e-3, of the lag-1 correlation 1e-3. Bounds at ~5 of them.
  constexpr int kBlocks = 1 << 14;
  std::vector<double> z(16 * kBlocks);
  double sum = 0, sum2 = 0, sum3 = 0, lag = 0;
  long long count = 0;
  for (std::uint64_t key = 1; key <= 4; ++key) {
    lk::active_kernels().normals(key, 0, z.data(), kBlocks);
    for (std::size_t i = 0; i < z.size(); ++i) {
      sum += z[i];
      sum2 += z[i] * z[i];
      sum3 += z[i] * z[i] * z[i];
      if (i > 0) lag += z[i] * z[i - 1];
      ++count;
    }
  }
  EXPECT_NEAR(sum / count, 0.0, 5e-3);
  EXPECT_NEAR(sum2 / count, 1.0, 7e-3);
  EXPECT_NEAR(sum3 / count, 0.0, 2e-2);
  EXPECT_NEAR(lag / count, 0.0, 5e-3);
}

TEST(Kernels, EveryBuild_GivesTheSameBits) {
  // GIVEN: the same inputs to each supported build, at a padded size (Nt = 12) and 64
  const std::vector<const lk::Kernels*> all = builds();
  for (const Size& size : {Size{3, 4, false}, Size{8, 8, true}}) {
    const KernelInputs s = make_inputs(size.rows, size.cols, size.exact, 61);
    const lk::RowGeometry& g = s.geometry;
    const lk::GramPlanes G = s.gram();
    std::mt19937_64 rng(62);
    double px[lk::kLanes], py[lk::kLanes], pz[lk::kLanes];
    random_lanes(s, rng, px, py, pz);
    const double q[3] = {px[0], py[0], pz[0]};
    // Everything each kernel returns, as one vector of doubles per build.
    std::vector<std::vector<double>> out;
    for (const lk::Kernels* k : all) {
      std::vector<double> o;
      std::vector<double> Xr(g.ld * lk::kLanes), Xi(g.ld * lk::kLanes), xr(g.ld), xi(g.ld), f(lk::kLanes);
      k->rows_lanes(g, px, py, pz, Xr.data(), Xi.data());
      k->row(g, q, xr.data(), xi.data());
      const double F_A = k->leave_one_out_energy(G, s.row_re(2), s.row_im(2));
      k->objectives_lanes(G, s.row_re(2), s.row_im(2), Xr.data(), Xi.data(), f.data());
      double grad[3];
      const double fg = k->gradient(g, G, s.row_re(2), s.row_im(2), F_A, q, grad);
      std::vector<double> yr(g.ld), yi(g.ld), z(16 * 9), gr = s.gr, gi = s.gi;
      k->hermitian_matvec(G, xr.data(), xi.data(), yr.data(), yi.data());
      k->normals(99, 3, z.data(), 9);
      k->gram_update(gr.data(), gi.data(), g.nt, g.ld, xr.data(), xi.data(), s.row_re(2), s.row_im(2));
      for (const auto* v : {&Xr, &Xi, &xr, &xi, &f, &yr, &yi, &z, &gr, &gi}) o.insert(o.end(), v->begin(), v->end());
      o.insert(o.end(), {F_A, fg, grad[0], grad[1], grad[2],
                         k->objective_of_row(G, s.row_re(2), s.row_im(2), F_A, xr.data(), xi.data())});
      out.push_back(o);
    }
    // THEN: byte-identical results (kernels.h: no fused multiply-adds, fixed summation order)
    for (std::size_t b = 1; b < out.size(); ++b) {
      ASSERT_EQ(out[b].size(), out[0].size());
      for (std::size_t i = 0; i < out[0].size(); ++i) {
        ASSERT_EQ(std::memcmp(&out[b][i], &out[0][i], sizeof(double)), 0)
            << lp::to_string(all[b]->isa) << " vs " << lp::to_string(all[0]->isa) << " at " << i;
      }
    }
  }
}
