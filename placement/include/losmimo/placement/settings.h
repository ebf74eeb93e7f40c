#pragma once
// The placement settings an INI config holds, with the paper's values as defaults: sections
// [scenario] (Scenario), [errors] (ErrorModel), [placement] (RunOptions), [gd] (GdOptions),
// [bf] (BfOptions), [ura] (UraOptions), [cap] (CapOptions) and [channel] (ChannelSettings:
// Rician fading, CSI estimation noise), plus per-algorithm stop rules in [gd], [bf], [ura] and
// [cap] (RunOverride). Every
// key, with its field, accepted values and meaning, is declared once in the key table in
// settings.cpp (placement_keys(); common/key_table.h). Keys beyond the paper setup are written
// only when not at their default: the text of the defaults (paper.ini, every recorded rawlog's
// CONFIG) holds the paper setup's keys only.

#include <map>
#include <set>
#include <string>

#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/common/key_table.h"
#include "losmimo/placement/bf.h"
#include "losmimo/placement/capacity.h"
#include "losmimo/placement/channel_conditions.h"
#include "losmimo/placement/gd.h"
#include "losmimo/placement/ura.h"

namespace losmimo::placement {

// One algorithm's own stop rule in the experiment's runs; unset fields take [placement]'s.
struct RunOverride {
  double target_icn = 0.0;  // 0: unset
  int max_iterations = -1;  // -1: unset
};
// `run` with the override's set fields.
RunOptions with_override(RunOptions run, const RunOverride& override_);

struct PlacementSettings {
  Scenario scenario;
  ErrorModel errors;
  RunOptions run;
  GdOptions gd;
  BfOptions bf;
  UraOptions ura;
  RunOverride gd_run;
  RunOverride bf_run;
  RunOverride ura_run;
  ChannelSettings channel;
  CapOptions cap;
  RunOverride cap_run;
};

// The key table: one entry per key (section, key, field, accepted values, meaning).
const common::KeyTable<PlacementSettings>& placement_keys();

// Sections and keys read by load_placement_settings (placement_keys().known_keys()).
std::map<std::string, std::set<std::string>> placement_config_keys();

// Reads the keys present (others keep their defaults) and validates everything; a bad value
// throws common::InputError naming the file, line, key and value. Unknown keys are not checked here:
// call common::IniConfig::require_known with the keys of every reader of the file.
PlacementSettings load_placement_settings(const common::IniConfig& config);

// For tools that evaluate the LoS channel only (losmimo-eval, the closed loop's record/replay and
// co-evaluation): [channel] conditions are refused, common::InputError naming key and value.
void require_los_channel(const ChannelSettings& channel, const common::IniConfig& config, const std::string& tool);

// The settings as INI text, in table order (what datasets/configs/paper.ini holds, sorted).
std::string to_ini(const PlacementSettings& settings);

}  // namespace losmimo::placement
