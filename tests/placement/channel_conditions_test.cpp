// Rician fading and CSI estimation noise (channel_conditions.h): the draws' moments against
// their definitions (5-sigma bounds on fixed seeds), the block keying, the measured-f noise floor
// against Monte Carlo, the faded evaluation against an explicit average and its LoS limit, and
// the pure LoS channel bit for bit when both are off.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "losmimo/placement/common/field_error.h"
#include "losmimo/placement/common/seed.h"
#include "losmimo/placement/bf.h"
#include "losmimo/placement/channel_conditions.h"
#include "losmimo/placement/gd.h"
#include "losmimo/placement/metrics.h"
#include "losmimo/placement/swarm.h"
#include "losmimo/placement/ura.h"

namespace lp = losmimo::placement;

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kSigmas = 5.0;

lp::ChannelSettings conditions(double k_db, double csi_db, int coherence = 1) {
  lp::ChannelSettings c;
  c.rician_k_db = k_db;
  c.csi_snr_db = csi_db;
  c.coherence_iterations = coherence;
  return c;
}

Eigen::Matrix3Xd random_start(const lp::Scenario& s, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  return lp::random_start_positions_m(s, rng);
}
}  // namespace

TEST(ChannelConditions, Off_IsInactiveAndLeavesRowsAsTheyAre) {
  const lp::ChannelConditions c(lp::ChannelSettings{}, 16, 16, 1, 2);
  EXPECT_FALSE(c.active());
  EXPECT_EQ(c.noise_floor_objective(), 0.0);
  EXPECT_EQ(c.scatter().size(), 0);
  lp::ChannelConditions copy = c;
  Eigen::VectorXcd x = Eigen::VectorXcd::LinSpaced(16, 0.5, 2.0);
  const Eigen::VectorXcd before = x;
  copy.measure_row(3, x);
  EXPECT_TRUE(x == before);
}

TEST(ChannelConditions, ScatterAndNoise_HaveTheirDefinedMoments) {
  // GIVEN K = 0 dB (a^2 = b^2 = 1/2) on a 64 x 256 channel
  constexpr int kNr = 64, kNt = 256, kN = kNr * kNt;
  lp::ChannelConditions c(conditions(0.0, 20.0), kNr, kNt, 11, 12);
  EXPECT_NEAR(c.los_weight() * c.los_weight(), 0.5, 1e-15);
  EXPECT_NEAR(c.scatter_weight() * c.scatter_weight(), 0.5, 1e-15);
  EXPECT_NEAR(c.noise_sigma(), 0.1, 1e-15);
  // THEN the scatter is CN(0, 1): mean 0, E|S|^2 = 1 (Var |S|^2 = 1), E S^2 = 0 (circular)
  const Eigen::MatrixXcd& S = c.scatter();
  EXPECT_NEAR(std::abs(S.mean()), 0.0, kSigmas * std::sqrt(1.0 / kN));
  EXPECT_NEAR(S.cwiseAbs2().mean(), 1.0, kSigmas * std::sqrt(1.0 / kN));
  EXPECT_NEAR(std::abs(S.array().square().mean()), 0.0, kSigmas * std::sqrt(1.0 / kN));
  // AND a faded LoS row keeps its power and has mean a x (averaged over blocks)
  constexpr int kBlocks = 400;
  Eigen::VectorXcd x(kNt), sum = Eigen::VectorXcd::Zero(kNt);
  double power = 0.0;
  for (int b = 1; b <= kBlocks; ++b) {
    c.begin_iteration(b);
    Eigen::VectorXcd y = Eigen::VectorXcd::Constant(kNt, std::polar(1.0, 0.7));
    c.fade_row(5, y);
    sum += y;
    power += y.squaredNorm() / kNt;
  }
  EXPECT_NEAR(power / kBlocks, 1.0, kSigmas * std::sqrt(0.5 * 0.5 * 1.0 / (kBlocks * kNt)) + 1e-12);
  const std::complex<double> mean_entry = sum.mean() / static_cast<double>(kBlocks);
  EXPECT_NEAR(std::abs(mean_entry - c.los_weight() * std::polar(1.0, 0.7)), 0.0,
              kSigmas * std::sqrt(0.5 / (kBlocks * kNt)));
  // AND the estimation noise has variance sigma_e^2 per entry, fresh at every measurement
  const lp::ChannelSettings csi_only = conditions(kInf, 20.0);
  lp::ChannelConditions noisy(csi_only, 1, kN, 3, 4);
  Eigen::VectorXcd first = Eigen::VectorXcd::Zero(kN), second = Eigen::VectorXcd::Zero(kN);
  noisy.measure_row(0, first);
  noisy.measure_row(0, second);
  EXPECT_NEAR(first.cwiseAbs2().mean(), 0.01, kSigmas * 0.01 / std::sqrt(kN));
  EXPECT_GT((first - second).norm(), 0.0);
  // AND the same seeds give the same numbers
  lp::ChannelConditions again(csi_only, 1, kN, 3, 4);
  Eigen::VectorXcd replay = Eigen::VectorXcd::Zero(kN);
  again.measure_row(0, replay);
  EXPECT_TRUE(replay == first);
}

TEST(ChannelConditions, Blocks_ChangeEveryCoherenceIterationsAndDependOnTheBlockOnly) {
  lp::ChannelConditions walked(conditions(10.0, kInf, 3), 4, 16, 99, 0);
  EXPECT_EQ(walked.block_of(0), 0);
  EXPECT_EQ(walked.block_of(1), 0);
  EXPECT_EQ(walked.block_of(3), 0);
  EXPECT_EQ(walked.block_of(4), 1);
  EXPECT_EQ(walked.block_of(7), 2);
  Eigen::MatrixXcd block0 = walked.scatter();
  for (int i = 1; i <= 9; ++i) {
    const bool changed = walked.begin_iteration(i);
    EXPECT_EQ(changed, i == 4 || i == 7) << i;  // 1 + k c
    if (i <= 3) {
      EXPECT_TRUE(walked.scatter() == block0);
    }
  }
  // Jumping straight to block 2 draws what walking there drew: no dependence on history.
  lp::ChannelConditions jumped(conditions(10.0, kInf, 3), 4, 16, 99, 0);
  jumped.begin_iteration(8);
  EXPECT_TRUE(jumped.scatter() == walked.scatter());
  // Another K scales the same draws (common random numbers across sweep points).
  const lp::ChannelConditions other_k(conditions(0.0, kInf, 3), 4, 16, 99, 0);
  EXPECT_TRUE(other_k.scatter() == block0);
  EXPECT_FALSE(lp::ChannelConditions(conditions(10.0, kInf, 3), 4, 16, 98, 0).scatter() == block0);
}

TEST(ChannelConditions, NoiseFloor_MatchesMonteCarloAtThePerfectUra) {
  // GIVEN the paper's 16 UAVs at the rigid URA (orthogonal LoS columns), K = 20 dB, CSI 20 dB
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  const Eigen::MatrixXcd L = model.matrix(lp::optimal_ura_positions_m(s));
  ASSERT_LT(lp::objective(L), 1e-3);  // near-field exact phases: not exactly 0, far below F0
  lp::ChannelConditions c(conditions(20.0, 20.0), 16, 16, 5, 6);
  // WHEN f of measured CSI is averaged over many blocks
  constexpr int kDraws = 300;
  std::vector<double> f;
  for (int d = 1; d <= kDraws; ++d) {
    c.begin_iteration(d);
    Eigen::MatrixXcd Y(16, 16);
    for (int n = 0; n < 16; ++n) {
      Eigen::VectorXcd row = L.row(n).transpose();
      c.measure_row(n, row);
      Y.row(n) = row.transpose();
    }
    f.push_back(lp::objective(Y));
  }
  double mean = 0.0, var = 0.0;
  for (const double v : f) mean += v / kDraws;
  for (const double v : f) var += (v - mean) * (v - mean) / (kDraws - 1);
  // THEN it is F0 = P (P - 1) Q (2 a^2 v + v^2)
  EXPECT_NEAR(mean, c.noise_floor_objective(), kSigmas * std::sqrt(var / kDraws));
  EXPECT_GT(c.noise_floor_objective(), 50.0);
}

TEST(ChannelConditions, FadedEvaluation_IsTheExplicitAverageAndTendsToLoS) {
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  const Eigen::MatrixXcd L = model.matrix(random_start(s, 4));
  lp::ChannelSettings c = conditions(5.0, kInf);
  c.fading_eval_draws = 12;
  const lp::FadedLinkMetrics m = lp::evaluate_link_faded(L, s.noise_variance(), c, 77);
  EXPECT_EQ(m.draws, 12);
  const double a = std::sqrt(std::pow(10.0, 0.5) / (std::pow(10.0, 0.5) + 1.0));
  const double b = std::sqrt(1.0 / (std::pow(10.0, 0.5) + 1.0));
  double icn = 0.0, zf = 0.0, nv_db0 = 0.0;
  for (int d = 0; d < 12; ++d) {
    std::vector<std::complex<double>> z(256);
    lp::complex_normals(losmimo::common::derive_seed(77, {static_cast<std::uint64_t>(d)}), 0, 256, z.data());
    Eigen::MatrixXcd H(16, 16);
    for (int n = 0; n < 16; ++n) {
      for (int k = 0; k < 16; ++k) H(n, k) = a * L(n, k) + b * std::abs(L(n, k)) * z[n * 16 + k];
    }
    const lp::LinkMetrics one = lp::evaluate_link(H, s.noise_variance());
    icn += one.icn / 12;
    zf += one.sum_rate_zf_bps_hz / 12;
    nv_db0 += lp::to_db(one.sinr.nv(0)) / 12;
  }
  EXPECT_NEAR(m.icn, icn, 1e-12);
  EXPECT_NEAR(m.sum_rate_zf_bps_hz, zf, 1e-9);
  EXPECT_NEAR(m.sinr_nv_db(0), nv_db0, 1e-9);
  // K = 100 dB is LoS to ~1e-5 in amplitude.
  c.rician_k_db = 100.0;
  const lp::FadedLinkMetrics los = lp::evaluate_link_faded(L, s.noise_variance(), c, 77);
  EXPECT_NEAR(los.sum_rate_zf_bps_hz, los.los.sum_rate_zf_bps_hz, 1e-3 * los.los.sum_rate_zf_bps_hz);
  EXPECT_NEAR(los.icn, los.los.icn, 1e-3);
  // Without fading nothing is drawn: the means are the LoS values.
  c.rician_k_db = kInf;
  const lp::FadedLinkMetrics off = lp::evaluate_link_faded(L, s.noise_variance(), c, 77);
  EXPECT_EQ(off.draws, 0);
  EXPECT_EQ(off.sum_rate_nv_bps_hz, off.los.sum_rate_nv_bps_hz);
}

TEST(ChannelConditions, BadValues_NameTheField) {
  const auto field_of = [](const lp::ChannelSettings& c) {
    try {
      lp::validate(c);
    } catch (const losmimo::common::FieldError& e) {
      return e.field();
    }
    return std::string("accepted");
  };
  EXPECT_EQ(field_of(conditions(std::nan(""), kInf)), "rician_k_db");
  EXPECT_EQ(field_of(conditions(-kInf, kInf)), "rician_k_db");
  EXPECT_EQ(field_of(conditions(101.0, kInf)), "rician_k_db");
  EXPECT_EQ(field_of(conditions(kInf, std::nan(""))), "csi_snr_db");
  EXPECT_EQ(field_of(conditions(kInf, kInf, 0)), "coherence_iterations");
  lp::ChannelSettings no_draws;
  no_draws.fading_eval_draws = 0;
  EXPECT_EQ(field_of(no_draws), "fading_eval_draws");
  EXPECT_EQ(field_of(conditions(-50.0, -50.0, 1000000)), "accepted");
}

TEST(ChannelConditionsRun, ConditionsOff_GiveTodaysRunsBitForBit) {
  // GIVEN runs with errors, once plain and once with explicitly inactive conditions set
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  const Eigen::Matrix3Xd start = random_start(s, 21);
  lp::RunOptions run;
  run.max_iterations = 60;
  run.trace_sinr = true;
  for (int algorithm = 0; algorithm < 3; ++algorithm) {
    std::vector<lp::RunResult> results;
    for (const bool explicit_off : {false, true}) {
      lp::Swarm swarm(model, start, {0.05, 0.02}, 8);
      if (explicit_off) swarm.set_channel_conditions(lp::ChannelConditions(lp::ChannelSettings{}, 16, 16, 1, 2));
      lp::GradientDescentPlanner gd(s, {});
      lp::BruteForcePlanner bf(s, {});
      lp::UraPlanner ura(s, lp::UraVariant::kLattice);
      lp::Planner& p = algorithm == 0   ? static_cast<lp::Planner&>(gd)
                       : algorithm == 1 ? static_cast<lp::Planner&>(bf)
                                        : ura;
      results.push_back(lp::run_placement(p, swarm, run));
    }
    // THEN positions, distances and the trace are the same bits
    EXPECT_TRUE(results[0].final_m == results[1].final_m) << algorithm;
    EXPECT_TRUE(results[0].probe_dist_m == results[1].probe_dist_m) << algorithm;
    ASSERT_EQ(results[0].trace.size(), results[1].trace.size());
    for (std::size_t i = 0; i < results[0].trace.size(); ++i) {
      EXPECT_EQ(results[0].trace[i].objective, results[1].trace[i].objective);
      EXPECT_EQ(results[0].trace[i].sinr_zf_db, results[1].trace[i].sinr_zf_db);
    }
  }
}

TEST(ChannelConditionsRun, Fading_StopsOnMeasuredCsiAndCountsMilestonesOnTheLoSGeometry) {
  // GIVEN GD under K = 10 dB from the perfect URA: the LoS ICN is 1 from the start
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  lp::Swarm swarm(model, lp::optimal_ura_positions_m(s), {}, 3);
  swarm.set_channel_conditions(lp::ChannelConditions(conditions(10.0, 30.0), 16, 16, 4, 5));
  lp::GradientDescentPlanner gd(s, {});
  lp::RunOptions run;
  run.max_iterations = 5;
  const lp::RunResult r = lp::run_placement(gd, swarm, run);
  // THEN the milestones are reached at the start (geometry), but the stop test, which reads the
  // measured channel (ICN ~0.5 at K = 10 dB), does not certify 0.95
  EXPECT_TRUE(r.icn095.reached);
  EXPECT_EQ(r.icn095.iteration, 0);
  EXPECT_GT(r.trace[0].icn_los, 0.999);
  EXPECT_LT(r.trace[0].icn, 0.9);
  EXPECT_EQ(r.status, lp::RunStatus::kIterationCap);
  // AND the master's Gram matrix is the measured one, not the LoS one
  const Eigen::MatrixXcd L = model.matrix(r.final_m);
  EXPECT_GT((swarm.channel().H() - L).norm(), 0.1 * L.norm());
}

TEST(ChannelConditionsRun, CoherenceBlocks_RedrawTheSwarmsScatterOnlyAtBlockStarts) {
  // GIVEN K = 10 dB, perfect CSI, blocks of 3 iterations, a swarm that does not move
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  lp::Swarm swarm(model, lp::optimal_ura_positions_m(s), {}, 3);
  swarm.set_channel_conditions(lp::ChannelConditions(conditions(10.0, kInf, 3), 16, 16, 4, 5));
  Eigen::MatrixXcd previous = swarm.true_channel();
  for (int i = 1; i <= 8; ++i) {
    swarm.begin_iteration(i);
    const Eigen::MatrixXcd now = swarm.true_channel();
    // THEN the true channel changes exactly at iterations 1 + k c (k >= 1)
    EXPECT_EQ(now != previous, i == 4 || i == 7) << i;
    // AND every cached row was measured again: without estimation noise, the true channel
    EXPECT_TRUE(swarm.channel().H().isApprox(now, 1e-12)) << i;
    previous = now;
  }
}
