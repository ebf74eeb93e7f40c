#pragma once
// The keys each app or sweep leaves unused, declared once (unused_keys.cpp), with the reason.
//
// A run's users are what consumes its settings: the app ("losmimo-eval", "losmimo-record"), or
// for losmimo-experiment each sweep it runs ("sigma_loc_m", "beacon_noise_m", ...), each with
// the conditions of the run that switch parts of it off (e.g. "no URA in [experiment]
// algorithms"). An entry says that its keys are unused by the users or conditions it lists. A
// key given with --set that every user of the run leaves unused (by its name or by one of its
// conditions) is refused before any work (kExitBadInput):
//   "--set: [errors] sigma_loc_m: not used by the sweep beacon_noise_m: <reason>"
// Keys in a --config file are not refused: one file serves every app and sweep
// (datasets/configs/paper.ini), so a file may hold keys for the others.
// tests/apps/every_setting_acts_test.cpp runs every key in every app and sweep: each either
// changes the results or is refused.

#include <map>
#include <string>
#include <vector>

#include "losmimo/placement/common/ini_config.h"

namespace losmimo::apps {

struct UnusedKeys {
  std::vector<std::string> keys;   // "section.key", or "section.*" for every key of the section
  std::vector<std::string> users;  // apps, sweeps and conditions that leave them unused
  std::string reason;              // why, for the message
};

// One user of a run: its name and the conditions it runs under (the kCondition* names).
struct KeyUser {
  std::string name;
  std::vector<std::string> conditions;
};

// The conditions, as entries and KeyUser::conditions name them. A planner's own sections
// (placement::PlannerEntry::sections) are unused under no_planner_condition(section): "no gd in
// [experiment] algorithms", "no ura, ura_lattice or ura_lattice_exact in [experiment] algorithms".
std::string no_planner_condition(const std::string& section);
// The sections the registered planners own, in registration order of their first owner.
std::vector<std::string> planner_sections();
inline const std::string kLosChannel = "[channel] rician_k_db = inf";
inline const std::string kNoReadings = "no [experiment] readings";
inline const std::string kEkfFilter = "[closed_loop] filter = ekf";
inline const std::string kNoRefinement = "[closed_loop] refine = false";

// The users of a losmimo-experiment run: its sweeps with their conditions.
struct ExperimentUse {
  std::vector<std::string> sweeps;
  std::vector<std::string> algorithms;  // [experiment] algorithms
  bool fading = false;                  // [channel] rician_k_db finite
  bool readings = false;
  // Per sweep, the conditions its extension reports (ExperimentExtension::unused_conditions).
  std::map<std::string, std::vector<std::string>> sweep_conditions;
};
std::vector<KeyUser> experiment_users(const ExperimentUse& use);

// The declarations, every app's and sweep's.
const std::vector<UnusedKeys>& unused_keys();

// The declarations as a markdown table (docs/configuration.md): keys, not used by, why.
std::string unused_keys_markdown();

// Throws common::InputError naming the first assignment of `overrides` ("section.key=value", as
// given to --set, already applied to `config`) whose key every one of `users` leaves unused.
void refuse_unused_overrides(const common::IniConfig& config, const std::vector<std::string>& overrides,
                             const std::vector<KeyUser>& users);

}  // namespace losmimo::apps
