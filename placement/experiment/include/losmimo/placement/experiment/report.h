#pragma once
// Figures (gnuplot) and report.md of an experiment run.
//   fig1a.png  ICN vs iteration (GD, BF; Fig 1 traced runs)
//   fig1b.png  SINR NV / ZF / MF vs iteration
//   fig2a.png  mean distance per UAV to ICN 0.5 (solid) and 0.95 (dotted) vs sigma_loc
//   fig2b.png  final SINR (NV solid, ZF dotted, MF dash-dot) vs sigma_loc, random start too
//   fig3.png   final SINR vs sigma_act
// Each figure's data (.dat) and script (.gp) sit beside it; gnuplot (Debian gnuplot-nox) is run
// when it is on PATH, else the scripts are left for the user and a warning says so.
//   paths.png  the UAVs' paths of the Fig 1 runs (trial 0) and of GD and BF under the largest
//              sigma_act, lateral and side views ([experiment] paths; data in paths.csv)
// report.md puts every value read from the paper's figures beside the measured mean and its
// 95% confidence interval; a value agrees when |measured - paper| <= CI + the resolution at
// which it can be read off the paper's plot. Every other difference gets a "Why" line from
// measurement: the readings (readings.h) that move it, by how much, from paired runs made here,
// or "cause unknown" when none does (or none was run). readings.csv holds every reading's
// numbers.

#include <map>
#include <string>
#include <vector>

#include "losmimo/placement/experiment/engine.h"
#include "losmimo/placement/experiment/metrics.h"
#include "losmimo/placement/experiment/summary.h"

namespace losmimo::experiment {

// How the results were computed, for report.md's first line and the app's last line.
// A merge of shard folders reports the shards' own timing (from their shard.ini), not just
// the seconds the merge took.
struct RunTiming {
  double wall_s = 0.0;  // this process: the whole run, or for a merge the merge itself
  int threads = 1;      // this process's threads (all ranks' threads under MPI)
  int shards = 0;       // > 0: merged from this many shard folders
  // Over the shards that recorded their own run in shard.ini (older folders did not):
  int timed_shards = 0;
  double slowest_shard_wall_s = 0.0;
  double shards_wall_s = 0.0;  // sum over those shards
  int min_shard_threads = 0;
  int max_shard_threads = 0;
  // The instruction set the placement kernels ran on (isa.h: "avx512"); for a merge, the shards'
  // (their shard.ini `isa`; older shards did not record it) with how many shards ran on each.
  std::string isa{};
  std::map<std::string, int> shard_isas{};
};
// "2 threads, 500.4 s wall, avx512 kernels", or "merged from 20 shards of 1 thread: slowest
// 71.4 s wall, 1276.3 s wall summed over shards; merge 3.8 s; avx512 kernels" (with shards on
// several instruction sets: "; kernels avx2 in 5 shards, avx512 in 15 shards").
std::string describe(const RunTiming& timing);

// The line colour of an algorithm in every figure (gnuplot "#rrggbb").
const char* algorithm_color(const Algorithm& algorithm);

struct ReportOutcome {
  std::vector<std::string> warnings;
};

// Figures of sweeps that did not run are skipped; extensions add their figures and sections.
ReportOutcome write_figures_and_report(const ExperimentSettings& settings, const ExperimentExtensions& extensions,
                                       const ExperimentResults& results, const std::vector<SummaryRow>& summary,
                                       const std::string& out_dir, const RunTiming& timing);

// One paper-vs-measured comparison line of report.md.
struct PaperValue {
  std::string figure;    // "Fig 2a"
  std::string quantity;  // human label
  std::string sweep;
  double value;  // sweep point
  std::string algorithm;
  MetricId metric;  // a summarised metric or a milestone (metrics.h)
  double paper;
  double resolution;  // how precisely the value can be read off the paper's figure
};
// The 27 values, numbered 1..27 in this order. Fig 1's iteration counts use the metric
// metrics::kIterationsToIcn095 (the report falls back to `iterations` without milestone columns: the
// same number for runs that stop at ICN 0.95).
std::vector<PaperValue> paper_values();

}  // namespace losmimo::experiment
