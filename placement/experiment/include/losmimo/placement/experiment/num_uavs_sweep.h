#pragma once
// The swarm-size sweep `num_uavs`, an extension (extension.h) like the channel sweeps, off unless
// listed in [experiment] sweeps. At each point Nr of [experiment] num_uavs_values the scenario
// has Nr UAVs and a BS array chosen by [experiment] num_uavs_array:
//   square  n x n with n = ceil(sqrt(Nr)), the smallest square array with n^2 >= Nr;
//   fixed   the configured bs_rows x bs_cols (Nt); a point with Nr > Nt is refused at load.
// Every algorithm of [experiment] algorithms runs from trial t's start for Nr UAVs (drawn in the
// start cube from trial t's start seed), errors drawn from the point's trial seed (trial.h).
// The capacity planner costs O(Nr^4) per iteration (capacity.h): it runs only at points with
// Nr <= [experiment] num_uavs_cap_max (default 64); above, its rows are absent and the report
// says so.
//
// Extra column: bs_antennas (Nt at the point). With [experiment] capacity_columns the capacity
// and translation columns (capacity_claims.h) come too.
// Timing (time per iteration) is not reproducible, so it stays out of trials.csv and
// summary.csv: the extension's runs log their wall time (per point and algorithm, summed over
// the trials this process ran) and the figures step plots it (num_uavs_timing.png, .dat: not a .csv); the
// report.md section quotes it (report.md's first line holds the wall time already). A merged
// or resumed run lacks (some of) it and says so.
// Figures: num_uavs.png (.dat, .gp): final ICN, ZF and NV sum rates, distance flown per UAV and
// iterations against Nr, one line per algorithm.

#include <memory>
#include <string>
#include <vector>

#include "losmimo/placement/common/key_table.h"
#include "losmimo/placement/experiment/extension.h"
#include "losmimo/placement/experiment/summary.h"

namespace losmimo::experiment {

inline const std::string kSweepNumUavs = "num_uavs";

enum class NumUavsArray { kSquare, kFixed };
std::string to_string(NumUavsArray array);  // "square", "fixed"

struct NumUavsSweepSettings {
  std::vector<int> num_uavs_values = {16, 64, 256};
  NumUavsArray array = NumUavsArray::kSquare;
  int cap_max_uavs = 64;
};

// The keys ([experiment] num_uavs_values, num_uavs_array, num_uavs_cap_max).
const common::KeyTable<NumUavsSweepSettings>& num_uavs_sweep_keys();
// Reads and checks them (common::InputError naming the key; with `fixed`, a point Nr > Nt is
// refused naming the point).
NumUavsSweepSettings load_num_uavs_sweep_settings(const ExperimentSettings& settings);

// The side n of the smallest square array with n^2 >= num_uavs.
int square_array_side(int num_uavs);
// The scenario at a point: the configured one with num_uavs UAVs and the array above.
placement::Scenario num_uavs_scenario(const placement::Scenario& base, NumUavsArray array, int num_uavs);
// Whether algorithm a runs at a point of num_uavs UAVs (cap only up to cap_max_uavs).
bool runs_at(const NumUavsSweepSettings& sweep, const Algorithm& a, int num_uavs);

inline constexpr ExtensionMetric kBsAntennas{{"bs_antennas"}, "", "BS antennas Nt = bs_rows x bs_cols at the point"};
const ExtensionMetrics& num_uavs_sweep_metrics();

// Wall time of the runs, per point and algorithm (thread-safe; summed over trials).
class NumUavsTiming {
 public:
  struct Entry {
    int runs = 0;
    long long iterations = 0;
    double wall_s = 0.0;
  };
  NumUavsTiming();
  void add(int point, const std::string& algorithm, int iterations, double wall_s);
  // nullptr when no run of (point, algorithm) was timed by this process.
  std::unique_ptr<Entry> find(int point, const std::string& algorithm) const;
  // Forgets every entry (the extension's report section does, once it has quoted them, so that
  // another run in the same process starts afresh).
  void clear();

 private:
  struct Impl;
  std::shared_ptr<Impl> impl_;  // shared by copies: one log
};

// Trial `trial` at point `point`: the settings' algorithms that run there; `timing` (optional)
// receives each run's wall time.
std::vector<TrialRecord> run_num_uavs_trial(const ExperimentSettings& settings, const NumUavsSweepSettings& sweep,
                                            int point, int trial, NumUavsTiming* timing = nullptr);

// num_uavs.png (.dat, .gp) and num_uavs_timing.png (.dat, .gp) (warnings if gnuplot is missing), and the
// report section.
std::vector<std::string> write_num_uavs_figure(const ExperimentSettings& settings, const std::vector<SummaryRow>& rows,
                                               const NumUavsTiming& timing, const std::string& out_dir);
std::string num_uavs_report_section(const ExperimentSettings& settings, const std::vector<SummaryRow>& rows,
                                    const NumUavsTiming& timing);

// Its conditions under which keys do not act (ExperimentExtension::unused_conditions).
inline const std::string kNumUavsSquareArray = "num_uavs_array = square";
inline const std::string kNumUavsNoneAboveCapMax = "no num_uavs point above num_uavs_cap_max";

// The sweep as an extension, for run_experiment_app next to the channel sweeps; its runs time
// themselves into one log shared by its figures and report section.
ExperimentExtension num_uavs_extension();

}  // namespace losmimo::experiment
