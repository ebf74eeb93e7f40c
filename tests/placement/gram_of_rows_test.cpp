// The Gram matrix built from all rows at once (kernels gram_of_rows, SwarmChannel::
// set_positions, Swarm::sync_channels) against a long-double sum, the scalar reference and the
// one-UAV-at-a-time rank updates it replaces for the URA baseline.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <stdexcept>
#include <vector>

#include "losmimo/placement/channel.h"
#include "losmimo/placement/channel_conditions.h"
#include "losmimo/placement/kernels.h"
#include "losmimo/placement/scenario.h"
#include "losmimo/placement/swarm.h"
#include "losmimo/placement/swarm_channel.h"

namespace lp = losmimo::placement;
namespace lk = losmimo::placement::kernels;

namespace {

lp::Scenario array_scenario(int rows, int cols, int num_uavs, bool exact_gain) {
  lp::Scenario s;
  s.bs_rows = rows;
  s.bs_cols = cols;
  s.num_uavs = num_uavs;
  s.gain_model = exact_gain ? lp::GainModel::kExact : lp::GainModel::kFarField;
  return s;
}

Eigen::Matrix3Xd moved(const Eigen::Matrix3Xd& q, double sigma_m, std::mt19937_64& rng) {
  std::normal_distribution<double> step(0.0, sigma_m);
  Eigen::Matrix3Xd out = q;
  for (Eigen::Index i = 0; i < out.size(); ++i) out(i) += step(rng);
  return out;
}

}  // namespace

TEST(Kernels, GramOfRows_IsExactlyHermitian_TheSameOnEveryBuild_AndTheSumOfTheRows) {
  struct Case {
    int rows, cols, uavs;
    bool exact;
  };
  for (const Case c : {Case{4, 4, 16, false}, Case{3, 4, 12, false}, Case{4, 4, 23, true}, Case{8, 8, 64, false}}) {
    const lp::Scenario s = array_scenario(c.rows, c.cols, c.uavs, c.exact);
    const lp::ChannelModel model(s);
    std::mt19937_64 rng(11);
    const lp::SwarmChannel channel(model, lp::random_start_positions_m(s, rng));
    const int n = model.num_antennas(), ld = lk::padded(n), nr = c.uavs;
    const Eigen::MatrixXcd& H = channel.H();
    std::vector<double> first;
    for (const lp::Isa isa : lp::supported_isas()) {
      const lk::Kernels& k = lk::kernels_for(isa);
      std::vector<double> gr(static_cast<std::size_t>(ld) * n, -1.0), gi(gr.size(), -1.0);
      k.gram_of_rows(channel.row_re(0), channel.row_im(0), nr, n, ld, gr.data(), gi.data());
      for (int kk = 0; kk < n; ++kk) {
        for (int l = 0; l < ld; ++l) {
          const double re = gr[l + kk * ld], im = gi[l + kk * ld];
          if (l >= n) {
            ASSERT_EQ(re, 0.0);  // pad rows of G stay 0
            ASSERT_EQ(im, 0.0);
            continue;
          }
          ASSERT_EQ(re, gr[kk + l * ld]) << l << "," << kk;
          ASSERT_EQ(im, -gi[kk + l * ld]) << l << "," << kk;
          long double sr = 0, si = 0;
          for (int m = 0; m < nr; ++m) {
            const long double ar = H(m, l).real(), ai = H(m, l).imag(), br = H(m, kk).real(), bi = H(m, kk).imag();
            sr += ar * br + ai * bi;
            si += ar * bi - ai * br;
          }
          const double scale = c.exact ? H.cwiseAbs2().maxCoeff() * nr : nr;
          EXPECT_NEAR(re, static_cast<double>(sr), 4e-16 * scale) << lp::to_string(isa);
          EXPECT_NEAR(im, static_cast<double>(si), 4e-16 * scale) << lp::to_string(isa);
        }
      }
      std::vector<double> rr(gr.size()), ri(gr.size());
      lk::reference_kernels().gram_of_rows(channel.row_re(0), channel.row_im(0), nr, n, ld, rr.data(), ri.data());
      for (std::size_t i = 0; i < rr.size(); ++i) ASSERT_NEAR(gr[i], rr[i], 1e-13 * nr) << i;
      gr.insert(gr.end(), gi.begin(), gi.end());
      if (first.empty()) first = gr;
      EXPECT_EQ(std::memcmp(gr.data(), first.data(), first.size() * sizeof(double)), 0) << lp::to_string(isa);
    }
  }
}

TEST(SwarmChannel, SetPositions_GivesTheRowsAndGramOfMovingEveryUavInTurn) {
  // The BS side (16 UAVs, 16 antennas) and the UAV side (10 UAVs: the swarm keeps K = H H^H).
  for (const int uavs : {16, 10}) {
    const lp::Scenario s = array_scenario(4, 4, uavs, false);
    const lp::ChannelModel model(s);
    std::mt19937_64 rng(21);
    const Eigen::Matrix3Xd start = lp::random_start_positions_m(s, rng);
    lp::SwarmChannel one_by_one(model, start), all_at_once(model, start);
    Eigen::Matrix3Xd q = start;
    for (int round = 0; round < 300; ++round) {  // past the rank updates' periodic refresh
      q = moved(q, 0.05, rng);
      for (int m = 0; m < uavs; ++m) one_by_one.set_position(m, q.col(m));
      const std::uint64_t version = all_at_once.version();
      all_at_once.set_positions(q);
      ASSERT_NE(all_at_once.version(), version);
    }
    EXPECT_TRUE(all_at_once.H() == one_by_one.H());  // the same row kernel: the same bits
    EXPECT_TRUE(all_at_once.H() == model.matrix(q));
    const Eigen::MatrixXcd exact = uavs < 16 ? Eigen::MatrixXcd(model.matrix(q) * model.matrix(q).adjoint())
                                             : Eigen::MatrixXcd(model.matrix(q).adjoint() * model.matrix(q));
    EXPECT_LT((all_at_once.gram() - exact).cwiseAbs().maxCoeff(), 1e-12 * uavs) << uavs;
    EXPECT_LT((one_by_one.gram() - exact).cwiseAbs().maxCoeff(), 1e-11 * uavs) << uavs;
    EXPECT_NEAR(all_at_once.objective(), one_by_one.objective(), 1e-9 * one_by_one.objective()) << uavs;
    EXPECT_THROW(all_at_once.set_positions(q.leftCols(uavs - 1)), std::invalid_argument);
  }
}

TEST(Swarm, SyncChannels_WithNoisyCsi_DrawsWhatSyncingEachUavAfterItsMoveDraws) {
  // The URA moves every UAV and syncs once: with channel conditions each UAV still measures in
  // UAV order, so the CSI noise stream gives the same rows as syncing after every move.
  const lp::Scenario s = array_scenario(4, 4, 16, false);
  const lp::ChannelModel model(s);
  std::mt19937_64 rng(31);
  const Eigen::Matrix3Xd start = lp::random_start_positions_m(s, rng);
  lp::ChannelSettings settings;
  settings.rician_k_db = 10.0;
  settings.csi_snr_db = 20.0;
  const lp::ChannelConditions conditions(settings, 16, 16, 5, 6);
  const lp::ErrorModel errors{0.0, 0.03};
  lp::Swarm each(model, start, errors, 77), once(model, start, errors, 77);
  each.set_channel_conditions(conditions);
  once.set_channel_conditions(conditions);
  for (int iteration = 1; iteration <= 5; ++iteration) {
    each.begin_iteration(iteration);
    once.begin_iteration(iteration);
    for (int m = 0; m < 16; ++m) {
      const Eigen::Vector3d r(0.1, -0.05 * m, 0.02);
      each.move(m, r, lp::MotionKind::kPlacement);
      once.move(m, r, lp::MotionKind::kPlacement, false);
    }
    once.sync_channels();
    ASSERT_TRUE(once.true_positions_m() == each.true_positions_m());
    ASSERT_TRUE(once.channel().H() == each.channel().H()) << iteration;
  }
}
