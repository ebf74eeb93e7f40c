#pragma once
// The layout of a losmimo rawlog (docs/rawlog-format.md has the full description).
//
// An MRPT rawlog in the observations-only format, gzip-compressed (CFileGZOutputStream): a
// sequence of serialized CObservation objects. Streams are told apart by sensorLabel:
//   CONFIG             CObservationComment   first object: "losmimo-rawlog <version>" line,
//                                            then the complete mission INI (mission.h)
//                                            with a [rawlog] section (filter seeds per UAV)
//   UAVnn_TRUTH        CObservationRobotPose true position at the epoch (cov 0)
//   UAVnn_DR           CObservationRobotPose measured displacement since the previous epoch
//                                            (x, y, z; cov = the filter's sigma_d^2 per axis)
//   UAVnn_BEACON       CObservationBearingRange  range, yaw = azimuth, pitch = -elevation (float)
//   UAVnn_BEACON64     CObservationRawDAQ    AIN_double = {range_m, azimuth_rad, elevation_rad}:
//                                            the same beacon in double, as the filter used it
//   UAVnn_CSI          CObservationRawDAQ    AIN_double = {Re y_0, Im y_0, ..., Re y_Nt-1,
//                                            Im y_Nt-1}, AIN_channel_count = 2 Nt
//   UAVnn_BELIEF       CObservationRobotPose the filter's belief (mean, 3x3 block of cov)
//   UAVnn_REFINED      CObservationRobotPose the refined belief placement used (refine only)
//   UAVnn_MOVE         CObservationRawDAQ    AIN_double = {iteration, mode (0 GD, 1 BF,
//                                            2 escape), commanded x y z, actual x y z}
// Since version 2, the same dead reckoning and beacon range as the standard MRPT types that
// stock pf-localization localizes on (one UAV's two streams, extracted, docs/replay.md):
//   UAVnn_ODOMETRY     CObservationOdometry  cumulative 2-D odometry: (sum of the measured
//                                            displacements' x, y since epoch 0, phi = 0), every
//                                            epoch, right after DR (before TRUTH)
//   UAVnn_BS_RANGES    CObservationBeaconRanges  the beacon's range to the BS (kBsBeaconId at the
//                                            array centre, as in the log's beacons.ini), float,
//                                            stdError = sigma_range_m, maxSensorDistance
//                                            kBsRangesMaxDistance_m; epochs with a beacon only
//   EPOCH_END          CObservationComment   integrity mark closing epoch k (key=value lines)
//   END_OF_LOG         CObservationComment   final mark: counts of everything written, the
//                                            run's status, and for a run ended by a fault
//                                            fault_uav and fault (the reason)
// nn is the UAV index, two digits or more (UAV07, UAV123). Frame: BS array frame (metres).

#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "losmimo/fusion/rawlog/io/reader.h"

namespace losmimo::rawlog {

// Version 1: the streams above up to MOVE. Version 2 adds ODOMETRY and BS_RANGES. A reader
// takes every version from kOldestRawlogFormatVersion to kRawlogFormatVersion, and refuses a
// newer one, naming it.
inline constexpr int kRawlogFormatVersion = 2;
inline constexpr int kOldestRawlogFormatVersion = 1;
using rawlog_io::kRawlogMagic;  // "losmimo-rawlog": what the reader trusts as ours

inline constexpr const char* kLabelConfig = "CONFIG";
inline constexpr const char* kLabelEpochEnd = "EPOCH_END";
inline constexpr const char* kLabelEndOfLog = "END_OF_LOG";

// The per-UAV streams.
enum class UavStream { kTruth, kDr, kBeacon, kBeacon64, kCsi, kBelief, kRefined, kMove, kOdometry, kBsRanges };
std::string to_string(UavStream stream);  // "TRUTH", "DR", ...

// "UAV07_BEACON" for (7, kBeacon).
std::string uav_label(int uav, UavStream stream);

struct UavLabel {
  int uav = 0;
  std::string suffix;               // what follows "UAVnn_" ("BEACON", or a foreign suffix)
  std::optional<UavStream> stream;  // set when the suffix is one of ours
};
// Parses "UAV<digits>_<suffix>" (uav < 100000, rawlog_io/labels.h); nullopt for anything else.
std::optional<UavLabel> parse_uav_label(const std::string& label);

// BS_RANGES: the BS as one beacon at the array centre (the beacon's range is |q|,
// localization/measurements.h), and a sensor limit far above the ranges of any scenario
// (MRPT's default, 100 m, is below the paper's 1 km).
inline constexpr int kBsBeaconId = 0;
inline constexpr float kBsRangesMaxDistance_m = 1e6f;

// MOVE record modes.
inline constexpr double kMoveGd = 0.0;
inline constexpr double kMoveBf = 1.0;
inline constexpr double kMoveEscape = 2.0;

// The marks' text: "key = value" lines, closed by "text_digest = <hex64 of the text before it>".
std::string with_text_digest(const std::string& text);  // appends the text_digest line
bool text_digest_matches(const std::string& text);
std::map<std::string, std::string> parse_mark_keys(const std::string& text);

// How the run ended, from END_OF_LOG: status (placement::to_string(RunStatus)), and for a run
// ended by a fault (uav_unresponsive, numerical_fault) fault_uav and fault, the reason (absent
// in logs written before the reason was logged).
struct RunEnd {
  std::string status;
  int fault_uav = -1;  // -1: none named
  std::string fault;
};
bool is_fault_status(const std::string& status);
// Reads `keys` into `out`; returns "" or what is wrong, naming the field and its value.
std::string read_run_end(const std::map<std::string, std::string>& keys, int num_uavs, RunEnd& out);

}  // namespace losmimo::rawlog
