#pragma once
// A rawlog read into per-epoch, per-UAV records (what losmimo-replay consumes).
//
// losmimo's own logs (first object CONFIG with the "losmimo-rawlog" magic, format.h):
// objects are grouped by the EPOCH_END marks. A mark is accepted only if the number of objects
// before it and the FNV-1a digest of the bytes since the previous mark match; the epochs up to
// the last accepted mark are used, anything after it (a partial epoch, a corrupted one) is not,
// and the log says where and why. END_OF_LOG, checked the same way, makes the log complete.
// Other rawlogs ("foreign"): observations are assigned to UAVs by a "UAVnn_" label prefix (UAV 0
// otherwise; labels above UAV255_ are skipped). Usable: CObservationBearingRange (the first measurement; yaw = azimuth,
// pitch = -elevation), dead reckoning as CObservationOdometry (2-D, cumulative: the displacement
// is the difference of consecutive readings, z = 0), a "UAVnn_DR" CObservationRobotPose
// (displacement), or CActionRobotMovement2D/3D inside a CActionCollection (pose change taken
// as the displacement in the BS frame), and ground truth as a CObservationRobotPose labelled
// "UAVnn_TRUTH" or "GROUND_TRUTH". Each displacement opens the UAV's next epoch; beacons and
// truth attach to the current epoch. CSensoryFrame contents are handled one by one. Anything
// else is counted in `skipped` by class and label, and ignored.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "losmimo/placement/common/input_error.h"
#include "losmimo/fusion/csi.h"
#include "losmimo/fusion/rawlog/mission/format.h"
#include "losmimo/fusion/rawlog/mission/mission.h"
#include "losmimo/fusion/rawlog/io/reader.h"
#include "losmimo/localization/position/measurements.h"

namespace losmimo::rawlog {

// One UAV at one epoch.
struct LoggedUavEpoch {
  // Ours: any record of this UAV in this epoch. false: nothing arrived from it (an unresponsive
  // UAV, closed_loop.h, or the UAVs after the one whose fault stopped the epoch): the loop kept
  // its belief as it was, and so does the replay.
  bool reported = false;
  std::optional<Eigen::Vector3d> truth_m;
  std::optional<Eigen::Vector3d> displacement_m;  // dead reckoning since the previous epoch
  std::optional<localization::BeaconMeasurement> beacon;
  bool beacon_exact = false;  // from BEACON64 (double), else from the float bearing-range
  std::optional<fusion::CsiMeasurement> csi;
  std::optional<localization::Belief> filter_belief;   // logged (mean, cov only)
  std::optional<localization::Belief> refined_belief;  // logged (refine only)
};

struct MissionLog {
  bool ours = false;                    // written by losmimo-record
  int format_version = 0;               // ours: the CONFIG header's (format.h)
  std::optional<MissionConfig> config;  // from CONFIG (ours)
  std::string config_text;              // the INI as logged
  std::vector<std::uint64_t> filter_seeds;
  int num_uavs = 0;
  // [epoch][uav]; ours: num_uavs per row; foreign: a row may be shorter (UAVs not seen in it).
  std::vector<std::vector<LoggedUavEpoch>> epochs;
  std::vector<std::string> modes;        // [epoch]: 'G', 'B', '-' per UAV (ours)
  std::optional<int> final_truth_epoch;  // epoch index of the final positions
  std::optional<Eigen::Matrix3Xd> final_truth_m;
  bool complete = false;  // END_OF_LOG present and verified
  RunEnd run_end;         // from END_OF_LOG (ours, complete); status empty otherwise
  bool run_faulted() const { return is_fault_status(run_end.status); }
  std::map<std::string, std::int64_t> used;     // "class label" -> count
  std::map<std::string, std::int64_t> skipped;  // "class label" -> count
  rawlog_io::RawlogReadStatus read_status;
  std::string integrity_error;               // first failed check of a mark (empty: none)
  std::int64_t objects_after_last_mark = 0;  // read but not used (ours)
  std::string stop_description() const;      // where and why the usable data ended
};

// Ours: an epoch may hold fewer records than UAVs (silent UAVs, or the last epoch of a run a
// fault stopped part-way through it), as long as the log so far has a record per UAV-epoch.
// Reads the whole rawlog. Throws common::InputError (and nothing else) if the log is ours
// but its CONFIG is not a valid mission config or names a format version this reader does not
// know (a newer one: the message names it), or if no object at all could be read.
// Non-finite BEACON64 and CSI values are refused (skipped), as are records of the wrong size.
MissionLog load_mission_log(rawlog_io::RawlogReader& reader);

}  // namespace losmimo::rawlog
