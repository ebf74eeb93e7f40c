#pragma once
// The golden missions' invariants (datasets/missions/<mission>/invariants.ini): the file's reader,
// the figures of a fresh replay and the checker (golden_invariants.cpp). The tests
// (golden_invariants_test.cpp, golden_bounds_test.cpp, golden_negative_controls_test.cpp) check
// each mission.rawlog replayed with each golden estimator, without reading golden/: what the
// golden outputs must mean, not what they were. Format and the reason of every bound:
// docs/rawlog-format.md#golden-missions.
//
// invariants.ini: INI sections [mission] (bounds of every variant) and optionally [<variant>]
// (e.g. [ekf+ceres]: overrides for that variant); every `key = value` line has its reason on the
// comment line(s) right above it. [mission] variants lists the golden/ folders. Keys (all
// required; an unknown key is an error, so that a typo cannot switch a check off):
//   status                    END_OF_LOG status of the recorded run (converged, iteration_cap)
//   epochs                    epochs of the recorded trajectory (the counts below are for it)
//   final_icn_min, _max       ICN at the final true positions
//   nees_epoch_low, _high     band of each epoch's average NEES over the swarm's UAVs
//   nees_epoch_min_fraction   fraction of the epochs whose average must be inside that band
//   nees_mean_low, _high      band of the average NEES over every UAV-epoch
//   shape_nees_mean_low, _high  band of the swarm shape's NEES per degree of freedom
//                             (placement/swarm_shape.h), averaged over the epochs with every truth
//   range_rmse_min_m          RMSE along the line of sight (x) over the UAV-epochs with a beacon
//   rmse_max_m                3-D RMSE over the UAV-epochs with a beacon
//   beacons                   beacons the estimator consumed, exactly
//   fallback_fraction_min, _max   BF fallback UAV-epochs / (epochs x UAVs)

#include <map>
#include <string>
#include <vector>

#include "losmimo/fusion/rawlog/mission/replay.h"

namespace losmimo::rawlog::golden {

// ---------------------------------------------------------------------------------------------
// invariants.ini

struct Bound {
  std::string value;
  std::string reason;
  int line = 0;
};
using Bounds = std::map<std::string, Bound>;  // key -> bound

struct InvariantsFile {
  std::string path;
  std::map<std::string, Bounds> sections;
  std::vector<std::string> problems;  // malformed lines, keys without a reason, duplicates
};

// The keys every variant must have.
const std::vector<std::string>& variant_keys();
InvariantsFile read_invariants(const std::string& path);
// [mission] variants.
std::vector<std::string> listed_variants(const InvariantsFile& f);
// [mission]'s bounds with [variant]'s on top.
Bounds bounds_of(const InvariantsFile& f, const std::string& variant);

// ---------------------------------------------------------------------------------------------
// What a replay shows, computed from its per-UAV estimates (never from golden/ or summary rows).

struct ReplayFigures {
  std::string status;  // END_OF_LOG
  int epochs = 0;
  int uavs = 0;
  double final_icn = 0.0;
  std::vector<double> epoch_average_nees;  // per epoch, over the UAVs with truth
  std::vector<int> epoch_nees_samples;
  double average_nees = 0.0;  // over every UAV-epoch with truth
  double shape_nees = 0.0;    // shape NEES / dof, mean over the epochs with every UAV's truth
  double range_rmse_m = 0.0;  // x error, UAV-epochs with a beacon
  double rmse_m = 0.0;        // 3-D, UAV-epochs with a beacon
  int beacons = 0;
  double fallback_fraction = 0.0;
};

ReplayFigures figures_of(const MissionLog& log, const ReplayResult& r);

// The checker: one message per violated (or missing, unknown, malformed) invariant, each
// starting with the key.
std::vector<std::string> violations(const Bounds& bounds, const ReplayFigures& f);

// The lines, each on its own indented line (for failure messages).
std::string joined(const std::vector<std::string>& lines);

// A golden variant's replay options: "ekf", "pf", "ekf+ceres".
ReplayOptions options_of(const std::string& variant);

// The missions datasets/missions ships.
const std::vector<std::string>& shipped_missions();

}  // namespace losmimo::rawlog::golden
