#pragma once
// One Monte Carlo trial of the experiment: every algorithm from the same start with the same
// error seed (paired comparison), and the Fig 1 traced runs.
//
// Seeds: start_seed = derive_seed(seed, {0, trial}) (the same start at every sweep point);
//        seed       = derive_seed(seed, {1, sweep, point, trial}) drives the error draws.
// Distances are means per UAV in metres; dist_to_icn050_m / dist_to_icn095_m are placement
// distance when the ICN first reached 0.5 / 0.95 (NaN if never); dist_total_m is everything
// flown (placement + probe), probe_dist_m the BF probe flights alone. SINR columns are stream 1
// (as the paper) and the mean of the per-stream dB values, at the final positions.

#include <cstdint>
#include <string>
#include <vector>

#include "losmimo/placement/experiment_settings.h"
#include "losmimo/placement/run.h"

namespace losmimo::placement {

struct TrialRecord {
  Sweep sweep = Sweep::kSigmaLoc;
  double value = 0.0;  // the swept sigma, metres
  Algorithm algorithm = Algorithm::kRandom;
  int trial = 0;
  std::uint64_t seed = 0;
  std::uint64_t start_seed = 0;
  int iterations = 0;
  bool converged = false;
  std::string status;
  double final_icn = 0.0;
  double dist_to_icn050_m = 0.0;
  double dist_to_icn095_m = 0.0;
  double dist_total_m = 0.0;
  double dist_placement_m = 0.0;
  double probe_dist_m = 0.0;
  double sinr_nv_db = 0.0;
  double sinr_zf_db = 0.0;
  double sinr_mf_db = 0.0;
  double mean_sinr_nv_db = 0.0;
  double mean_sinr_zf_db = 0.0;
  double mean_sinr_mf_db = 0.0;
  double sum_rate_nv_bps_hz = 0.0;
  double sum_rate_zf_bps_hz = 0.0;
  Eigen::Matrix3Xd start_m;
  Eigen::Matrix3Xd final_m;
};

// The settings' algorithms on trial `trial` of sweep point `point` (value = its sigma).
std::vector<TrialRecord> run_trial(const ExperimentSettings& settings, Sweep sweep, int point,
                                   int trial);

// A Fig 1 run: `algorithm` without errors from trial `trial`'s start, SINR traced.
RunResult run_traced(const ExperimentSettings& settings, Algorithm algorithm, int trial);

}  // namespace losmimo::placement
