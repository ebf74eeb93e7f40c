#pragma once
// losmimo-record: runs one closed-loop mission (mission.h) and logs it as an MRPT rawlog
// (layout in format.h and docs/rawlog-format.md).
//
// Writing: every object is serialized with MRPT's CArchive into memory, hashed (FNV-1a 64) and
// written through zlib's gzip writer (the format MRPT's CFileGZOutputStream writes). After each
// epoch an EPOCH_END mark carries the object count and the digest of the epoch's bytes, and the
// gzip stream is flushed (Z_SYNC_FLUSH) to the file: a crash or kill mid-mission leaves a
// readable prefix that ends at the last mark. END_OF_LOG closes a complete log.
// CSI: the row the refinement used when the loop measured one (refine with use_csi); otherwise
// the recorder simulates the row at the true position (simulate_csi, the scenario's noise) with
// its own generator, so every log carries CSI and can be replayed with refinement. The run
// itself is the same with or without the recorder.

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <map>
#include <string>
#include <vector>

#include "losmimo/fusion/closed_loop.h"
#include "losmimo/rawlog/mission.h"

namespace losmimo::rawlog {

struct RecordResult {
  fusion::ClosedLoopRun run;
  std::int64_t objects = 0;            // every object written, marks included
  std::uint64_t uncompressed_bytes = 0;
  int epochs = 0;                      // localization epochs (0 .. epochs - 1)
  std::map<std::string, std::int64_t> label_counts;  // per sensorLabel
};

struct RecordOptions {
  std::string out_path;
  int compression_level = 6;  // zlib, 1..9
  // Test hook: called after each EPOCH_END mark was flushed (e.g. to kill the process there).
  std::function<void(int epoch)> after_epoch_mark;
};

// Runs and records the mission. Throws std::runtime_error if the file cannot be written.
RecordResult record_mission(const MissionConfig& config, const RecordOptions& options);

}  // namespace losmimo::rawlog
