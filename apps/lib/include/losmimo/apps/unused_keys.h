#pragma once
// The keys each app or sweep leaves unused, declared once (unused_keys.cpp), with the reason.
//
// A run's users are what consumes its settings: "losmimo-eval", "losmimo-record", or for
// losmimo-experiment each sweep it runs ("sigma_loc_m", "beacon_noise_m", ...). An entry says
// that its keys are unused by its users. A key given with --set that every user of the run
// leaves unused is refused before any work (exit 2):
//   "--set: [errors] sigma_loc_m: not used by beacon_noise_m: <reason>"
// Keys in a --config file are not refused: one file serves every app and sweep
// (datasets/configs/paper.ini), so a file may hold keys for the others.
// tests/apps/every_setting_acts_test.cpp runs every key in every app and sweep: each either
// changes the results or is refused.

#include <string>
#include <vector>

#include "losmimo/common/ini_config.h"

namespace losmimo::apps {

struct UnusedKeys {
  std::vector<std::string> keys;   // "section.key", or "section.*" for every key of the section
  std::vector<std::string> users;  // apps and sweeps that leave them unused
  std::string reason;              // why, for the message
};

// The declarations, every app's and sweep's.
const std::vector<UnusedKeys>& unused_keys();

// The declarations as a markdown table (docs/configuration.md): keys, not used by, why.
std::string unused_keys_markdown();

// Throws common::InputError naming the first assignment of `overrides` ("section.key=value", as
// given to --set, already applied to `config`) whose key every one of `users` leaves unused.
void refuse_unused_overrides(const common::IniConfig& config, const std::vector<std::string>& overrides,
                             const std::vector<std::string>& users);

}  // namespace losmimo::apps
