#pragma once
// Exact records, and the proof they carry. Every field of a TrialRecord at full precision
// (doubles as %.17g, positions included) reads back to the same bits. They are the checkpoint of
// a run (records.partial), a finished shard's output (records.csv) and what MPI ranks send to
// rank 0. A file, line by line:
//
//   # losmimo-experiment records v2
//   h,<kind>,<shard index>,<shard count>,<config digest>
//   r,<point>,<sweep>,<value>,<algorithm>,<trial>,<seed>,<start_seed>,<status>,<metrics in
//     kMetrics order (metrics.h)>,<number of extra>,<extra...>,<start positions>,<final
//     positions>,<line digest>
//   d,<point>,<records of the point>,<digest>
//   e,<points>,<records>,<digest>
//
// kind is "run" (one process, or a resumed run) or "shard" (shard i of N, or an MPI rank);
// config digest: FNV-1a 64 of the results-relevant config (run_folder.h, results_config). A
// point's r lines are followed by its d line once the point is complete (points in order
// 0, 1, ...); the e line closes a finished shard's file. Digests (16 hex digits, FNV-1a 64,
// common/hash.h): an r line's covers its own text before ",<line digest>"; a d or e line's covers
// every byte of the file before that line. So one record missing, duplicated or altered is
// found and named (the file, line, point, trial and algorithm). The digests guard against
// accidents (a truncated copy, an edit, a mixed folder), not against forgery.

#include <cstdint>
#include <iosfwd>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "losmimo/placement/common/bounded_read.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/experiment/trial.h"

namespace losmimo::experiment {

inline constexpr const char* kRecordsMagic = "# losmimo-experiment records v";
inline constexpr const char* kRecordsHeader = "# losmimo-experiment records v2";
inline constexpr const char* kRecordsKindRun = "run";
inline constexpr const char* kRecordsKindShard = "shard";

struct RecordsHeader {
  std::string kind = kRecordsKindRun;
  int shard_index = 0;
  int shard_count = 1;
  std::uint64_t config_digest = 0;
};

// Makes the text of a records file piece by piece, keeping the running digest: the caller
// writes each piece where it likes (a checkpoint file, a shard's file, a rank's message).
// Resuming re-makes the verified prefix with a fresh writer: the digest depends only on the
// bytes.
class RecordsWriter {
 public:
  std::string header(const RecordsHeader& h);  // the magic line and the h line
  // The point's r lines, then its d line.
  std::string point(int point, const std::vector<TrialRecord>& records);
  std::string end();  // the e line (a finished shard)

 private:
  std::string emit(std::string text);
  std::uint64_t digest_ = 0;
  int points_ = 0;
  std::int64_t records_ = 0;
};

enum class RecordsMode {
  kCheckpoint,  // records.partial: the verified points up to the last d line; the rest (an
                // interrupted point, a cut line) is ignored
  kComplete,    // records.csv, a rank's records: every line verified, closed by the e line
};

struct RecordLines {
  RecordsHeader header;
  std::map<int, std::vector<TrialRecord>> points;  // finished point -> records, in file order
  std::int64_t records = 0;                        // in the finished points
  std::uint64_t verified_bytes = 0;                // up to the last verified h, d or e line
  int unverified_lines = 0;                        // checkpoint: the interrupted point's lines, ignored
};

// Reads and verifies a records file (line by line, each line at most max_line_bytes). Throws
// common::InputError naming `origin`, the line, and the point, trial and algorithm concerned:
// another format version, a malformed line, an r line whose digest differs (altered), a
// (trial, algorithm) twice in a point (duplicated), a d line whose count or digest differs (a
// record missing or added), points out of order, a missing or wrong e line (kComplete).
RecordLines read_records(std::istream& in, const std::string& origin, RecordsMode mode,
                         std::size_t max_line_bytes = common::kMaxRecordLineBytes);

// A finished point's records against the jobs that should have made them: every trial in
// `trials` holds each algorithm of the point exactly once, and no other trial is there.
// Throws common::InputError ("<origin>: point 3, trial 2: no record of algorithm gd").
void check_point_jobs(const std::string& origin, int point, const std::vector<TrialRecord>& records,
                      const std::set<int>& trials);

}  // namespace losmimo::experiment
