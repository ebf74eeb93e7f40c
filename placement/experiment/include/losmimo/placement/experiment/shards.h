#pragma once
// Splitting one experiment over processes: `--shard i/N` runs the jobs j with j % N == i
// (engine.h) into its own folder (config.ini, records.csv, and losmimo-run.ini saying kind =
// shard with its [shard] index, count, threads, wall_s); a merge orders the verified records
// of shards 0..N-1 exactly as one process would have, so the merged files are byte-identical to
// a single run's.

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/experiment/engine.h"
#include "losmimo/placement/experiment/records.h"
#include "losmimo/placement/experiment/report.h"

namespace losmimo::experiment {

// Parses "i/N" (0 <= i < N, decimal); throws common::InputError naming the text otherwise.
std::pair<int, int> parse_shard(const std::string& text);

// The records of complete shards (read_records, kComplete) in single-run order; common::InputError
// naming the origin, point, trial and algorithm if a record is missing, duplicated, in the wrong
// shard or outside the configuration.
ExperimentResults merge_shard_records(const ExperimentSettings& settings, const std::vector<RecordLines>& shards,
                                      const std::vector<std::string>& origins);

// Adds a shard's own run (its manifest's [shard] `threads` and `wall_s`, and the kernels'
// instruction set `isa`) to the merge's timing, if the shard recorded them; common::InputError
// naming the key and value on a bad one.
void add_shard_timing(const common::IniConfig& shard_ini, RunTiming& timing);

// Which instruction set ran how many parts, in name order: "sse2 in 1 shard, avx512 in 3 shards".
std::string isa_counts(const std::map<std::string, int>& parts_per_isa, const std::string& part);
// "" when every part of a run (`part`: "shard", or "rank" under MPI) ran the kernels on the same
// instruction set (`parts_per_isa`: name -> parts); else what the user should know: the kernels
// give the same bits on each (kernels.h), the C library's math may not, so the merged results
// agree with a one-machine run to 1e-9 relative rather than to the bit.
std::string mixed_isa_note(const std::map<std::string, int>& parts_per_isa, const std::string& part);

}  // namespace losmimo::experiment
