#pragma once
// The placement settings an INI config holds, with the paper's values as defaults.
//
//   [scenario]  bs_rows bs_cols bs_spacing_m carrier_hz num_uavs cube_side_m cube_center_x_m
//               cube_center_y_m cube_center_z_m snr_db gain_model (far_field | exact)
//   [errors]    sigma_loc_m sigma_act_m
//   [placement] target_icn max_iterations
//   [gd]        step decay max_move_m backtracking max_halvings escape stall_window
//               stall_min_decrease escape_half_grid escape_uavs depth_step_gain
//   [bf]        step decay contraction min_step_m escape stall_window stall_min_decrease

#include <map>
#include <set>
#include <string>

#include "losmimo/placement/bf.h"
#include "losmimo/placement/gd.h"
#include "losmimo/common/ini_config.h"

namespace losmimo::placement {

struct PlacementSettings {
  Scenario scenario;
  ErrorModel errors;
  RunOptions run;
  GdOptions gd;
  BfOptions bf;
};

// Sections and keys read by load_placement_settings.
std::map<std::string, std::set<std::string>> placement_config_keys();

// Reads the keys present (others keep their defaults) and validates everything; a bad value
// throws common::InputError naming the file, line, key and value. Unknown keys are not checked here:
// call common::IniConfig::require_known with the keys of every reader of the file.
PlacementSettings load_placement_settings(const common::IniConfig& config);

// The settings as INI text (what datasets/configs/paper.ini holds).
std::string to_ini(const PlacementSettings& settings);

}  // namespace losmimo::placement
