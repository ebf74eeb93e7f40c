// Fewer UAVs than BS antennas (Nr < Nt): one stream per UAV, the UAV-side Gram matrix K = H H^H
// (metrics.h, swarm_channel.h). Every metric against a direct computation (eigenvalues of K,
// an explicit pseudo-inverse precoder, explicit sums), the swarm's cached K and f against full
// recomputes, the O(Nr Nt) gradient against central differences, and the planners and the URA
// on 8 x 8 and 16 x 16 arrays with 16 UAVs.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <cmath>
#include <random>

#include "losmimo/placement/bf.h"
#include "losmimo/placement/gd.h"
#include "losmimo/placement/metrics.h"
#include "losmimo/placement/swarm.h"
#include "losmimo/placement/swarm_channel.h"
#include "losmimo/placement/ura.h"
#include "support/numdiff.h"

namespace lp = losmimo::placement;

namespace {
using cd = std::complex<double>;
constexpr double kNoiseVariance = 0.1;  // SNR 10 dB
constexpr double kRelTolerance = 1e-9;

Eigen::MatrixXcd random_channel(int nr, int nt, std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, std::sqrt(0.5));
  Eigen::MatrixXcd H(nr, nt);
  for (Eigen::Index i = 0; i < H.size(); ++i) H(i) = cd(n(rng), n(rng));
  return H;
}

void expect_rel_near(double a, double b, const std::string& what) {
  EXPECT_LE(std::abs(a - b), kRelTolerance * std::max({1.0, std::abs(a), std::abs(b)}))
      << what << ": " << a << " vs " << b;
}

lp::Scenario array_of(int side, int num_uavs = 16) {
  lp::Scenario s;
  s.bs_rows = s.bs_cols = side;
  s.num_uavs = num_uavs;
  return s;
}

Eigen::Matrix3Xd random_start(const lp::Scenario& s, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  return lp::random_start_positions_m(s, rng);
}
}  // namespace

TEST(UavStreams, RandomWideChannels_MatchEigenvaluesPseudoInverseAndExplicitSums) {
  std::mt19937_64 rng(16);
  for (const auto& [nr, nt] : std::vector<std::pair<int, int>>{{4, 16}, {16, 64}, {3, 5}, {16, 256}}) {
    for (int rep = 0; rep < 5; ++rep) {
      const Eigen::MatrixXcd H = random_channel(nr, nt, rng);
      const lp::LinkMetrics m = lp::evaluate_link(H, kNoiseVariance);
      ASSERT_EQ(m.sinr.zf.size(), nr);
      // ICN over the Nr nonzero singular values, from the eigenvalues of K = H H^H.
      const Eigen::MatrixXcd K = H * H.adjoint();
      const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXcd>(K).eigenvalues();
      expect_rel_near(m.icn, std::sqrt(ev(0) / ev(nr - 1)), "icn");
      // ZF: the BS's pseudo-inverse precoder, each beam normalised to unit power: no leakage, and
      // SINR_n = |h_n w_n|^2 / psi^2.
      Eigen::JacobiSVD<Eigen::MatrixXcd> svd(H, Eigen::ComputeThinU | Eigen::ComputeThinV);
      Eigen::MatrixXcd W = svd.matrixV() * svd.singularValues().cwiseInverse().asDiagonal() * svd.matrixU().adjoint();
      for (int n = 0; n < nr; ++n) W.col(n).normalize();
      const Eigen::MatrixXcd HW = H * W;
      double sum_zf = 0.0, sum_nv = 0.0;
      for (int n = 0; n < nr; ++n) {
        for (int j = 0; j < nr; ++j) {
          if (j != n) {
            EXPECT_LT(std::abs(HW(n, j)), 1e-9 * std::abs(HW(n, n))) << "ZF leakage";
          }
        }
        const double zf = std::norm(HW(n, n)) / kNoiseVariance;
        expect_rel_near(m.sinr.zf(n), zf, "zf stream " + std::to_string(n));
        // NV: the BS's matched filter on UAV n's signature h_n (uplink MRC), explicit sums.
        double signal = 0.0, interference = 0.0, norm2 = 0.0;
        for (int j = 0; j < nr; ++j) {
          cd inner = 0.0;
          for (int k = 0; k < nt; ++k) inner += H(j, k) * std::conj(H(n, k));
          if (j == n)
            signal = std::norm(inner);
          else
            interference += std::norm(inner);
        }
        for (int k = 0; k < nt; ++k) norm2 += std::norm(H(n, k));
        const double nv = signal / (interference + norm2 * kNoiseVariance);
        expect_rel_near(m.sinr.nv(n), nv, "nv stream " + std::to_string(n));
        expect_rel_near(m.sinr.mf(n), norm2 / kNoiseVariance, "mf stream " + std::to_string(n));
        sum_zf += std::log2(1.0 + zf);
        sum_nv += std::log2(1.0 + nv);
      }
      expect_rel_near(m.sum_rate_zf_bps_hz, sum_zf, "zf sum rate");
      expect_rel_near(m.sum_rate_nv_bps_hz, sum_nv, "nv sum rate");
      double f = 0.0;
      for (int n = 0; n < nr; ++n) {
        for (int j = 0; j < nr; ++j) f += j == n ? 0.0 : std::norm(K(n, j));
      }
      expect_rel_near(m.objective, f, "objective over UAV pairs");
    }
  }
}

TEST(UavStreams, TallChannels_KeepOneStreamPerAntennaWithAReceiveZeroForcer) {
  // Nr >= Nt is the paper's case: streams are the BS antennas, ZF combining at the UAVs.
  std::mt19937_64 rng(17);
  for (int rep = 0; rep < 5; ++rep) {
    const Eigen::MatrixXcd H = random_channel(20, 16, rng);
    const lp::LinkMetrics m = lp::evaluate_link(H, kNoiseVariance);
    ASSERT_EQ(m.sinr.zf.size(), 16);
    Eigen::JacobiSVD<Eigen::MatrixXcd> svd(H, Eigen::ComputeThinU | Eigen::ComputeThinV);
    const Eigen::MatrixXcd pinv =
        svd.matrixV() * svd.singularValues().cwiseInverse().asDiagonal() * svd.matrixU().adjoint();
    for (int k = 0; k < 16; ++k) {
      // w_k^H = row k of pinv(H): w_k^H h_k = 1, w_k^H h_l = 0; SINR = 1 / (psi^2 |w_k|^2).
      expect_rel_near(m.sinr.zf(k), 1.0 / (kNoiseVariance * pinv.row(k).squaredNorm()), "zf");
    }
    const Eigen::VectorXd sv = svd.singularValues();
    expect_rel_near(m.icn, sv(15) / sv(0), "icn");
  }
}

TEST(UavSideSwarmChannel, CachedGramAndObjective_MatchFullRecomputeAfterManyMoves) {
  for (const int side : {8, 16}) {
    const lp::Scenario s = array_of(side);
    const lp::ChannelModel model(s);
    Eigen::Matrix3Xd q = random_start(s, side);
    lp::SwarmChannel swarm(model, q);
    ASSERT_EQ(swarm.gram_side(), lp::SwarmChannel::GramSide::kUavs);
    std::mt19937_64 rng(3);
    std::normal_distribution<double> step(0.0, 0.3);
    for (int i = 0; i < 300; ++i) {
      const int m = i % s.num_uavs;
      q.col(m) += Eigen::Vector3d(step(rng), step(rng), step(rng));
      swarm.set_position(m, q.col(m));
    }
    const Eigen::MatrixXcd H = model.matrix(q);
    const Eigen::MatrixXcd K = H * H.adjoint();
    ASSERT_EQ(swarm.gram().rows(), s.num_uavs);
    EXPECT_LT((swarm.gram() - K).norm(), 1e-12 * K.norm());
    expect_rel_near(swarm.objective(), lp::objective(H), "objective");
    // UAV m's view: f with its row replaced, against a full recompute.
    const lp::UavObjective view(swarm, 5);
    const Eigen::Vector3d elsewhere = q.col(5) + Eigen::Vector3d(0.3, -1.1, 0.7);
    Eigen::Matrix3Xd moved = q;
    moved.col(5) = elsewhere;
    EXPECT_LE(std::abs(view.objective_at(elsewhere) - lp::objective(model.matrix(moved))),
              1e-10 * lp::objective(model.matrix(moved)));
    EXPECT_LE(std::abs(view.objective_at(q.col(5)) - swarm.objective()), 1e-10 * swarm.objective());
    // The candidates' form agrees with the single one.
    Eigen::Matrix3Xd candidates(3, 3);
    candidates << elsewhere, q.col(5), q.col(2);
    double f[4];
    view.objectives_at(candidates, true, f);
    EXPECT_DOUBLE_EQ(f[0], view.objective_of_row(swarm.H().row(5).transpose()));
    for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(f[c + 1], view.objective_at(candidates.col(c)));
  }
}

TEST(UavSideSwarmChannel, Gradient_MatchesCentralDifferencesAndTheColumnObjectivesInTheFarField) {
  constexpr double kStep_m = 1e-5;
  for (const lp::GainModel gm : {lp::GainModel::kFarField, lp::GainModel::kExact}) {
    lp::Scenario s = array_of(8);
    s.gain_model = gm;
    const lp::ChannelModel model(s);
    for (int seed = 0; seed < 3; ++seed) {
      const Eigen::Matrix3Xd q = random_start(s, 40 + seed);
      const int m = 3 * seed;
      const lp::SwarmChannel swarm(model, q);
      double f_at = 0.0;
      const Eigen::Vector3d analytic = lp::UavObjective(swarm, m).gradient_at(q.col(m), &f_at);
      EXPECT_DOUBLE_EQ(f_at, lp::UavObjective(swarm, m).objective_at(q.col(m)));
      const auto full = [&](const Eigen::Vector3d& qm, bool columns) {
        Eigen::Matrix3Xd moved = q;
        moved.col(m) = qm;
        const Eigen::MatrixXcd H = model.matrix(moved);
        if (!columns) return lp::objective(H);
        const Eigen::MatrixXcd G = H.adjoint() * H;  // the paper's column objective
        return G.squaredNorm() - G.diagonal().squaredNorm();
      };
      const Eigen::Vector3d numeric = losmimo::test_support::central_gradient<3>(
          [&](const Eigen::Vector3d& x) { return full(x, false); }, q.col(m), kStep_m);
      EXPECT_LT((analytic - numeric).norm(), 1e-4 * numeric.norm())
          << analytic.transpose() << " | " << numeric.transpose();
      if (gm == lp::GainModel::kFarField) {
        // Far field: f_col - f_row = Nr Nt (Nt - Nr), a constant, so the gradients agree.
        const Eigen::Vector3d columns = losmimo::test_support::central_gradient<3>(
            [&](const Eigen::Vector3d& x) { return full(x, true); }, q.col(m), kStep_m);
        EXPECT_LT((analytic - columns).norm(), 1e-3 * columns.norm());
        EXPECT_NEAR(full(q.col(m), true) - full(q.col(m), false), 16.0 * 64.0 * (64.0 - 16.0),
                    1e-6 * full(q.col(m), true));
      }
    }
  }
}

TEST(UavSidePlanners, GdAndBfOn8x8Array_ReachIcn095OverTheUavStreams) {
  const lp::Scenario s = array_of(8);
  const lp::ChannelModel model(s);
  lp::RunOptions run;
  run.max_iterations = 400;
  for (const bool gd : {true, false}) {
    lp::Swarm swarm(model, random_start(s, 5), {}, 5);
    lp::GradientDescentPlanner gd_planner(s, {});
    lp::BruteForcePlanner bf_planner(s, {});
    lp::Planner& planner = gd ? static_cast<lp::Planner&>(gd_planner) : bf_planner;
    const lp::RunResult r = lp::run_placement(planner, swarm, run);
    EXPECT_TRUE(r.converged()) << planner.name() << " " << lp::to_string(r.status) << " after " << r.iterations;
    EXPECT_GE(lp::inverse_condition_number(model.matrix(r.final_m)), 0.95) << planner.name();
    EXPECT_TRUE(r.icn095.reached) << planner.name();
  }
}

TEST(UavSideUra, SixteenUavsOn64And256Antennas_PickSlotsWithOrthogonalRows) {
  for (const int side : {8, 16}) {
    const lp::Scenario s = array_of(side);
    const lp::ChannelModel model(s);
    for (const lp::UraVariant v : {lp::UraVariant::kRigid, lp::UraVariant::kLattice}) {
      lp::Swarm swarm(model, random_start(s, 9), {}, 9);
      lp::UraPlanner ura(s, v);
      lp::RunOptions run;
      run.max_iterations = 2;
      const lp::RunResult r = lp::run_placement(ura, swarm, run);
      // The rigid grid's slots are orthogonal up to the near field; the lattice variant's depth
      // shifts by whole periods cost a little more of it.
      const double floor = v == lp::UraVariant::kRigid ? 0.99 : 0.98;
      EXPECT_GE(lp::inverse_condition_number(model.matrix(r.final_m)), floor)
          << ura.name() << " on " << side << "x" << side;
      // The targets are 16 distinct slots of the Nt-slot grid.
      for (int a = 0; a < s.num_uavs; ++a) {
        for (int b = a + 1; b < s.num_uavs; ++b)
          EXPECT_GT((ura.targets_m().col(a) - ura.targets_m().col(b)).norm(), 0.1);
      }
    }
  }
  lp::Scenario more = array_of(4, 17);  // more UAVs than antennas: no URA of the BS's size
  EXPECT_THROW(lp::UraPlanner(more, lp::UraVariant::kRigid), std::invalid_argument);
}
