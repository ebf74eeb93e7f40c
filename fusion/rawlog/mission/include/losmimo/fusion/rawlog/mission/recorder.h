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
// its own generator (std::mt19937_64 seeded with recorder_csi_seed), so every log carries CSI
// and can be replayed with refinement. The run itself is the same with or without the recorder.

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <map>
#include <string>
#include <vector>

#include "losmimo/fusion/closed_loop.h"
#include "losmimo/localization/pose/range_model.h"
#include "losmimo/fusion/rawlog/mission/mission.h"

namespace losmimo::rawlog {

struct RecordResult {
  fusion::ClosedLoopRun run;
  std::int64_t objects = 0;  // every object written, marks included
  std::uint64_t uncompressed_bytes = 0;
  int epochs = 0;                                    // localization epochs (0 .. epochs - 1)
  std::map<std::string, std::int64_t> label_counts;  // per sensorLabel
};

struct RecordOptions {
  std::string out_path;
  int compression_level = 6;  // zlib, 1..9
  // Test hook: called after each EPOCH_END mark was flushed (e.g. to kill the process there).
  std::function<void(int epoch)> after_epoch_mark;
};

// The seed of the recorder's CSI generator for a mission seed: common::tagged_seed with
// kRecorderCsiStreamTag. A log's CSI bytes depend on it; the shipped logs were recorded with it.
inline constexpr std::uint64_t kRecorderCsiStreamTag = 0x5EED'C51C'0000'0006ULL;
std::uint64_t recorder_csi_seed(std::uint64_t mission_seed);

// Runs and records the mission. Throws std::runtime_error if the file cannot be written.
RecordResult record_mission(const MissionConfig& config, const RecordOptions& options);

// The beacon map of the BS_RANGES stream (format.h): the BS as beacon kBsBeaconId at the array
// centre (0, 0, 0) of the BS frame.
localization::BeaconMap bs_ranges_beacon_map();
// The beacons.ini for stock MRPT apps that losmimo-record writes beside a log of `config`:
// bs_ranges_beacon_map() with beaconRangesStd = the beacon's range sigma (1 mm at least), as
// beacons_ini_text (mrpt_app_config.h) writes it, and pf-localization's prior box in
// [LocalizationExperiment]: init_PDF_mode = 1, init_PDF_min/max_x/y = the start cube's x-y
// extent, init_PDF_min/max_yaw_deg = 0 (the ODOMETRY readings' heading).
// losmimo-replay --mrpt-config reads the same keys.
std::string mission_beacons_ini_text(const MissionConfig& config);
// Where: "<log path without a .rawlog extension>.beacons.ini" (run.rawlog -> run.beacons.ini).
std::string beacons_ini_path(const std::string& log_path);

}  // namespace losmimo::rawlog
