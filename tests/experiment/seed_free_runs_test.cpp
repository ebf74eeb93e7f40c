// SeedFreeRuns (trial.h): a run that takes nothing from its seed is computed once per
// experiment and its record reused at the other sweep points. Checked against records computed
// afresh at every point, field by field, and against the rule's limits.
#include <gtest/gtest.h>

#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/experiment/extension.h"
#include "losmimo/placement/experiment/trial.h"

namespace le = losmimo::experiment;

namespace {
le::ExperimentSettings small() {
  return le::load_experiment_settings(losmimo::common::IniConfig::from_string(
      "[experiment]\ntrials = 2\nsigma_loc_values_m = 0, 0.1\nsigma_act_values_m = 0, 0.1\n"
      "algorithms = random, gd, bf, ura\n[placement]\nmax_iterations = 40\n"));
}

void expect_same_record(const le::TrialRecord& a, const le::TrialRecord& b) {
  EXPECT_EQ(a.sweep, b.sweep);
  EXPECT_EQ(a.value, b.value);
  EXPECT_EQ(a.algorithm, b.algorithm);
  EXPECT_EQ(a.seed, b.seed);
  EXPECT_EQ(a.start_seed, b.start_seed);
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.status, b.status);
  EXPECT_EQ(a.final_icn, b.final_icn);
  EXPECT_EQ(a.dist_total_m, b.dist_total_m);
  EXPECT_EQ(a.probe_dist_m, b.probe_dist_m);
  EXPECT_EQ(a.sinr_nv_db, b.sinr_nv_db);
  EXPECT_EQ(a.sum_rate_zf_bps_hz, b.sum_rate_zf_bps_hz);
  EXPECT_EQ(a.icn095_iteration, b.icn095_iteration);
  EXPECT_EQ(a.final_m, b.final_m);
}
}  // namespace

TEST(SeedFreeRuns, ReusedRecords_AreTheRecordsComputedAtEveryPoint) {
  const le::ExperimentSettings s = small();
  le::SeedFreeRuns reuse;
  for (const std::string& sweep : {le::kSweepSigmaLoc, le::kSweepSigmaAct}) {
    for (int point = 0; point < 2; ++point) {
      for (int trial = 0; trial < 2; ++trial) {
        const auto fresh = le::run_trial(s, sweep, point, trial);
        const auto shared = le::run_trial(s, sweep, point, trial, &reuse);
        ASSERT_EQ(fresh.size(), shared.size());
        for (std::size_t i = 0; i < fresh.size(); ++i) expect_same_record(fresh[i], shared[i]);
      }
    }
  }
  // BF never estimates a position: sigma_loc 0.1 is seed-free for it, not for GD.
  EXPECT_TRUE(reuse.find(le::Algorithm::kBf, 1).has_value());
  EXPECT_TRUE(reuse.find(le::Algorithm::kGd, 1).has_value());  // from sigma_loc 0 = sigma_act 0
}

TEST(SeedFreeRuns, OnlyRunsThatDrawNothing_AreSeedFree) {
  losmimo::placement::PlacementSettings p = small().placement;
  EXPECT_TRUE(le::SeedFreeRuns::applies(p, le::Algorithm::kGd));
  p.errors.sigma_loc_m = 0.1;
  EXPECT_FALSE(le::SeedFreeRuns::applies(p, le::Algorithm::kGd));
  EXPECT_FALSE(le::SeedFreeRuns::applies(p, le::Algorithm::kUra));
  EXPECT_TRUE(le::SeedFreeRuns::applies(p, le::Algorithm::kBf));
  EXPECT_TRUE(le::SeedFreeRuns::applies(p, le::Algorithm::kRandom));
  p.errors.sigma_act_m = 0.02;
  EXPECT_FALSE(le::SeedFreeRuns::applies(p, le::Algorithm::kBf));
  EXPECT_FALSE(le::SeedFreeRuns::applies(p, le::Algorithm::kRandom));
}

TEST(SeedFreeRuns, AnEmptyStore_FindsNothing) {
  const le::SeedFreeRuns reuse;
  EXPECT_FALSE(reuse.find(le::Algorithm::kBf, 0).has_value());
}
