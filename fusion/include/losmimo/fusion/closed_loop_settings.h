#pragma once
// The [closed_loop] INI section: the closed loop's settings (closed_loop.h ClosedLoopConfig) as
// losmimo-record reads them and writes them into a rawlog's CONFIG, and as the co-evaluation
// reads the ones it shares (its sensor noise, particles and refinement window). Each key is
// declared once in the key table in closed_loop_settings.cpp (closed_loop_keys();
// common/key_table.h), with the ClosedLoopConfig fields it sets.
//
// Matching: the beacon_* keys and outlier_fraction set the true sensor (SimulatorConfig); the
// filter assumes the true beacon noise unless filter_sigma_range_m / filter_sigma_angle_rad are
// given; the dead-reckoning keys set the truth and what the filter and the refinement assume;
// the refinement assumes the filter's beacon noise and the scenario's CSI noise
// (matched_closed_loop_config, refinement_config_from).

#include <string>

#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/common/key_table.h"
#include "losmimo/fusion/closed_loop.h"
#include "losmimo/placement/settings.h"

namespace losmimo::fusion {

// The [closed_loop] keys. to_ini writes doubles with 17 significant digits (the text recorded
// rawlogs hold).
const common::KeyTable<ClosedLoopConfig>& closed_loop_keys();

// Reads [closed_loop] over the matched defaults of `placement` (its scenario's CSI noise, its
// [errors] sigma_act_m as the simulator's actuation error) and validates: a bad value, a broken
// rule (validate(ClosedLoopConfig)) or a UAV index beyond the swarm throws common::InputError
// naming the key.
ClosedLoopConfig load_closed_loop_config(const common::IniConfig& ini, const placement::PlacementSettings& placement);

// The [closed_loop] section of `config`: every key with its value (faults,
// unresponsive_after_iterations and filter_max_beacon_range_m only when set).
std::string closed_loop_to_ini(const ClosedLoopConfig& config);

}  // namespace losmimo::fusion
