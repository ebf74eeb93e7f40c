#pragma once
// One recorded mission's configuration (losmimo-record, losmimo-replay), read from one INI file:
//   [scenario] [errors] [placement] [gd] [bf]   the placement settings (settings.h; errors.sigma_loc_m
//                                               unused)
//   [closed_loop]                               the closed loop (fusion/closed_loop_settings.h)
//   [mission]                                   the seeds and the epoch period (mission_keys())
// Each key is declared once, in its section's key table (common/key_table.h).
// losmimo-experiment's INI files load too (datasets/configs/paper.ini) when their keys are
// passed as also_known: their [experiment] and sweep sections ([coevaluation]) are then accepted
// and ignored.

#include <cstdint>
#include <map>
#include <set>
#include <string>

#include <Eigen/Core>

#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/common/key_table.h"
#include "losmimo/fusion/closed_loop.h"
#include "losmimo/placement/settings.h"

namespace losmimo::rawlog {

struct MissionConfig {
  placement::PlacementSettings placement;
  fusion::ClosedLoopConfig closed_loop;
  std::uint64_t seed = 1;
  std::uint64_t start_seed = 1;
  double epoch_period_s = 1.0;
  common::IniConfig ini;  // the validated INI as given (overrides applied)
};

// The [mission] keys: the run seeds and the epoch period of the timestamps.
const common::KeyTable<MissionConfig>& mission_keys();

// Sections and keys load_mission_config accepts: placement's, [closed_loop], [mission] and
// `also_known` (e.g. the experiment's, so that its INI files load too).
std::map<std::string, std::set<std::string>> mission_config_keys(
    std::map<std::string, std::set<std::string>> also_known = {});

// Reads and validates every key (unknown ones are errors); a bad value throws
// common::InputError naming the file, line, key and value.
MissionConfig load_mission_config(const common::IniConfig& ini,
                                  const std::map<std::string, std::set<std::string>>& also_known = {});

// The complete configuration as INI text, the three tables' in turn: every key with its
// effective value (a few only when set, see the tables), so that
// load_mission_config(from_string(mission_to_ini(c))) gives the same mission.
std::string mission_to_ini(const MissionConfig& config);

// The start positions: placement::random_start_positions_m with std::mt19937_64(start_seed).
Eigen::Matrix3Xd mission_start_positions_m(const MissionConfig& config);

}  // namespace losmimo::rawlog
