#pragma once
// The experiment's CSV files (columns in docs/experiment.md):
//   trials.csv     one row per record; `extra` names an extension's columns, appended after the
//                  built-in ones (missing cells as nan)
//   positions.csv  start and final UAV positions of every record, at full precision
//   traces.csv     per-iteration ICN, f, SINR and distances of the Fig 1 runs
// Numbers are written with common::kCsvDigits significant digits, positions exactly.

#include <cstddef>
#include <iosfwd>
#include <string>
#include <vector>

#include "losmimo/placement/common/format.h"
#include "losmimo/placement/experiment/engine.h"

namespace losmimo::experiment {

void write_trials_header(std::ostream& out, const std::vector<std::string>& extra = {});
void write_trials_rows(std::ostream& out, const std::vector<TrialRecord>& records, std::size_t num_extra = 0);
void write_positions_header(std::ostream& out);
void write_positions_rows(std::ostream& out, const std::vector<TrialRecord>& records);
void write_traces_csv(std::ostream& out, const std::vector<TracedRun>& traces);

}  // namespace losmimo::experiment
