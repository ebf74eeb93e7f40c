// The swarm-size sweep (experiment/num_uavs_sweep.h) and the capacity-claim columns
// (experiment/capacity_claims.h): the array of each point, the refusals, GD beating random
// placement at every size, and the claim columns against hand values and an orthogonal swarm.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/experiment/capacity_claims.h"
#include "losmimo/placement/experiment/engine.h"
#include "losmimo/placement/experiment/num_uavs_sweep.h"
#include "losmimo/placement/experiment/settings.h"
#include "losmimo/placement/channel.h"
#include "losmimo/placement/ura.h"

namespace losmimo::experiment {
namespace {

constexpr double kRoundoff = 1e-9;
constexpr double kParaxial = 1e-7;  // the URA's slots are orthogonal to the paraxial approximation

ExperimentSettings settings_of(const std::string& extra) {
  const std::string text =
      "[placement]\nmax_iterations = 60\n[errors]\nsigma_loc_m = 0\nsigma_act_m = 0\n"
      "[experiment]\ntrials = 2\nsweeps = num_uavs\nnum_uavs_values = 4, 9\n" +
      extra;
  return load_experiment_settings(common::IniConfig::from_string(text, "c.ini"), {num_uavs_extension()});
}

std::string error_of(const std::string& extra) {
  try {
    settings_of(extra);
  } catch (const common::InputError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(NumUavsSweep, SquareArraySide_IsTheSmallestSquareHoldingTheSwarm) {
  for (int n_uavs = 1; n_uavs <= 4096; ++n_uavs) {
    int side = 1;  // by counting up, independent of the square root
    while (side * side < n_uavs) ++side;
    ASSERT_EQ(square_array_side(n_uavs), side) << n_uavs;
  }
  EXPECT_EQ(square_array_side(256), 16);
  EXPECT_EQ(square_array_side(257), 17);
}

TEST(NumUavsSweep, FixedArray_RefusesAPointAboveTheAntennaCountNamingIt) {
  // GIVEN a 2 x 2 BS: 4 UAVs fit, 9 do not.
  const std::string bs = "[scenario]\nbs_rows = 2\nbs_cols = 2\n[experiment]\n";
  EXPECT_EQ(error_of(bs + "num_uavs_array = square\n"), "accepted");
  const std::string refused = error_of(bs + "num_uavs_array = fixed\n");
  EXPECT_NE(refused.find("num_uavs_values"), std::string::npos) << refused;
  EXPECT_NE(refused.find("point 9 UAVs"), std::string::npos) << refused;
  EXPECT_NE(error_of("num_uavs_array = round\n").find("'round' is not square or fixed"), std::string::npos);
  EXPECT_NE(error_of("num_uavs_values = 0\n").find("num_uavs_values"), std::string::npos);
}

TEST(NumUavsSweep, EveryPoint_RunsItsSwarmOnItsArrayAndGdBeatsRandom) {
  // GIVEN points 4 and 9 on square arrays (2 x 2, 3 x 3); cap only up to 4 UAVs.
  const ExperimentSettings s =
      settings_of("algorithms = random, gd, cap\nnum_uavs_cap_max = 4\ncapacity_columns = true\n");
  const ExperimentResults results = run_experiment(s, {num_uavs_extension()}, 2);
  std::map<std::pair<double, int>, std::map<std::string, const TrialRecord*>> by_run;
  for (const TrialRecord& r : results.records) by_run[{r.value, r.trial}][r.algorithm] = &r;
  ASSERT_EQ(by_run.size(), 4u);  // 2 points x 2 trials
  const std::vector<std::string> extra = extra_metric_names(s, {num_uavs_extension()});
  ASSERT_EQ(extra.front(), kBsAntennas.name);
  ASSERT_EQ(extra.size(), 1 + capacity_claim_metrics().size());
  int improved = 0;
  for (const auto& [run, algorithms] : by_run) {
    const int n_uavs = static_cast<int>(run.first);
    // THEN the swarm has the point's size, the array is the smallest square holding it,
    EXPECT_EQ(algorithms.size(), n_uavs <= 4 ? 3u : 2u) << "cap runs up to num_uavs_cap_max only";
    for (const auto& [name, r] : algorithms) {
      EXPECT_EQ(r->final_m.cols(), n_uavs) << name;
      const double nt = r->extra.at(0);
      EXPECT_GE(nt, n_uavs) << name;
      EXPECT_LT((std::sqrt(nt) - 1) * (std::sqrt(nt) - 1), n_uavs) << name;
      EXPECT_EQ(r->start_m, algorithms.at("random")->start_m) << "one start per trial and point";
    }
    // AND GD ends at least as orthogonal as its random start (a real placement property).
    EXPECT_GE(algorithms.at("gd")->final_icn, algorithms.at("random")->final_icn) << n_uavs;
    EXPECT_GE(algorithms.at("gd")->extra.at(1), algorithms.at("random")->extra.at(1) - kRoundoff) << n_uavs;
    improved += algorithms.at("gd")->final_icn > algorithms.at("random")->final_icn ? 1 : 0;
    EXPECT_EQ(algorithms.at("random")->extra.at(4), 0.0) << "random placement does not move";
  }
  EXPECT_GT(improved, 0) << "GD moved no swarm: the comparison above tested nothing";
}

TEST(NumUavsSweep, Threads_GiveTheSameRecordsWithTheClaimColumns) {
  const ExperimentSettings s = settings_of("algorithms = random, gd, cap\ncapacity_columns = true\n");
  const ExperimentResults one = run_experiment(s, {num_uavs_extension()}, 1);
  const ExperimentResults two = run_experiment(s, {num_uavs_extension()}, 2);
  ASSERT_EQ(one.records.size(), two.records.size());
  for (std::size_t i = 0; i < one.records.size(); ++i) {
    EXPECT_EQ(one.records[i].algorithm, two.records[i].algorithm) << i;
    EXPECT_TRUE(one.records[i].final_m == two.records[i].final_m) << i;
    EXPECT_EQ(one.records[i].extra, two.records[i].extra) << i;  // NaN-free here: compared exactly
  }
}

TEST(CapacityClaims, Quantiles_MatchHandValues) {
  std::vector<double> one_to_twenty;
  for (int i = 20; i >= 1; --i) one_to_twenty.push_back(i);
  EXPECT_DOUBLE_EQ(median(one_to_twenty), 10.5);
  EXPECT_DOUBLE_EQ(nearest_rank_quantile(one_to_twenty, 0.95), 19.0);  // the 19th smallest
  EXPECT_DOUBLE_EQ(nearest_rank_quantile(one_to_twenty, 1.0), 20.0);
  EXPECT_DOUBLE_EQ(median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_TRUE(std::isnan(median({})));
}

TEST(CapacityClaims, OrthogonalSwarm_ReachesTheBoundAndACollocatedOneDoesNot) {
  // GIVEN the paper's 16 UAVs at the rigid URA's slots (orthogonal columns, far field).
  placement::Scenario sc;
  const Eigen::Matrix3Xd ura_m = placement::optimal_ura_positions_m(sc);
  const placement::ChannelModel model(sc);
  Eigen::Matrix3Xd start_m = ura_m;
  for (Eigen::Index n = 0; n < start_m.cols(); ++n) start_m(2, n) -= static_cast<double>(n + 1);  // moved n + 1 m
  const MetricValues v = capacity_claim_values(sc, placement::CapPower::kEqual, model.matrix(ura_m), start_m, ura_m);
  // THEN C = C_max (the bound is reached exactly at orthogonality),
  EXPECT_NEAR(v.at(metrics::kCapacityFraction), 1.0, kParaxial);
  // AND the translations are 1..16 m: median 8.5, p95 the 16th (ceil(15.2)), max 16, per d_r = 5 m.
  EXPECT_NEAR(v.at(metrics::kTranslationMedianM), 8.5, kRoundoff);
  EXPECT_NEAR(v.at(metrics::kTranslationP95M), 16.0, kRoundoff);
  EXPECT_NEAR(v.at(metrics::kTranslationMaxM), 16.0, kRoundoff);
  const double slot_m = sc.wavelength_m() * sc.range_m() / (sc.bs_rows * sc.bs_spacing_m);
  EXPECT_NEAR(v.at(metrics::kTranslationMaxPerSpacing), 16.0 / slot_m, kRoundoff);
  // Negative control: a collocated swarm has rank-1 H = 1 h^T, one mode of gain Nr Nt, so
  // C = log2(1 + SNR Nr Nt) against C_max = 16 log2(1 + 16 SNR) (SNR = 10).
  const Eigen::Matrix3Xd collocated_m = ura_m.col(0).replicate(1, ura_m.cols());
  const MetricValues r =
      capacity_claim_values(sc, placement::CapPower::kEqual, model.matrix(collocated_m), collocated_m, collocated_m);
  EXPECT_NEAR(r.at(metrics::kCapacityFraction), std::log2(1.0 + 10.0 * 256) / (16 * std::log2(161.0)), kRoundoff);
  EXPECT_EQ(r.at(metrics::kTranslationMaxM), 0.0);
}

}  // namespace
}  // namespace losmimo::experiment
