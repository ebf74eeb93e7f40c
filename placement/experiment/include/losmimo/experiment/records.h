#pragma once
// Exact records: every field of a TrialRecord at full precision (doubles as %.17g, positions
// included), one line each, `r,<point>,<sweep>,<value>,<algorithm>,<trial>,<seed>,<start_seed>,
// <status>,<metrics in kMetrics order>,<number of extra>,<extra...>,<start positions>,<final
// positions>`, and `d,<point>` once a point is complete. They are
// the checkpoint of a run (records.partial), a shard's output (records.csv) and what MPI ranks
// send to rank 0, and they read back to the same bits.

#include <iosfwd>
#include <map>
#include <string>
#include <vector>

#include "losmimo/common/input_error.h"
#include "losmimo/experiment/trial.h"

namespace losmimo::experiment {

// The first line of a records file. v2: the metrics in kMetrics order (metrics.h). A file of
// another version is refused, naming it.
inline constexpr const char* kRecordsMagic = "# losmimo-experiment records v";
inline constexpr const char* kRecordsHeader = "# losmimo-experiment records v2";

void write_record_lines(std::ostream& out, int point, const std::vector<TrialRecord>& records);
void write_point_done(std::ostream& out, int point);

struct RecordLines {
  std::map<int, std::vector<TrialRecord>> points;  // point -> records in file order
  std::vector<int> done;                           // `d` markers, in order
};
// Throws common::InputError naming `origin` and the line on a malformed line; a truncated last line
// (an interrupted write) is ignored when `allow_truncated_tail`.
RecordLines parse_record_lines(std::istream& in, const std::string& origin, bool allow_truncated_tail);

}  // namespace losmimo::experiment
