#pragma once
// One recorded mission's configuration (losmimo-record, losmimo-replay): the placement settings
// (settings.h), the closed loop (closed_loop.h) and the mission's seeds, read from one INI file.
//
//   [scenario] [errors] [placement] [gd] [bf]   as in settings.h (errors.sigma_loc_m unused)
//   [closed_loop]
//     filter                 ekf | pf                       (ekf)
//     num_particles          particle filter size            (1000)
//     refine                 Ceres sliding-window refinement (false)
//     use_csi                CSI rows in the refinement       (true)
//     window_epochs          refinement window W              (5)
//     fallback               BF on degraded beliefs           (true)
//     gd_mode                mean | sigma_points              (mean)
//     beacon_sigma_range_m   true beacon range 1-sigma [m]    (0.1)
//     beacon_sigma_angle_rad true beacon angle 1-sigma [rad]  (1e-4)
//     beacon_period_epochs   a beacon every N epochs          (1)
//     outlier_fraction       gross beacon errors, in [0, 1]   (0)
//     dr_sigma_floor_m       dead reckoning 1-sigma at rest   (0.01)
//     dr_sigma_fraction      ... plus this fraction of |d|    (0.02)
//     filter_sigma_range_m   what the filter assumes          (= beacon_sigma_range_m)
//     filter_sigma_angle_rad                                  (= beacon_sigma_angle_rad)
//     degraded_after_epochs  belief degraded after N epochs without beacon (10)
//     outages                per-UAV beacon outages "uav:first_epoch:num_epochs, ..." (none)
//     faults                 injected faults (closed_loop.h fusion::UavFault), "kind:uav:from_iteration
//                            [:num_iterations], ..."; kind unresponsive | nan_beacon |
//                            nan_displacement | nan_csi; num_iterations 0 = to the end (none)
//     unresponsive_after_iterations  the master ends the run after a UAV is silent (no
//                            measurement, no motion) this many iterations, in [1, 1000] (3)
//   [mission]
//     seed                   run seed: sensors, filters, CSI, actuation (1)
//     start_seed             draws the start positions in the start cube (1)
//     epoch_period_s         time between epochs in the rawlog's timestamps (1.0)
// losmimo-experiment's INI files load too (datasets/configs/paper.ini): their [experiment] and
// sweep sections ([coevaluation]) are accepted and ignored.
// Filter noise defaults to the true sensor noise (matched_closed_loop_config); the refinement
// takes the filter's noise model and the scenario's CSI noise (refinement_config_from).

#include <cstdint>
#include <map>
#include <set>
#include <string>

#include <Eigen/Core>

#include "losmimo/fusion/closed_loop.h"
#include "losmimo/common/ini_config.h"
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

// Sections and keys load_mission_config accepts: placement's, [closed_loop], [mission] and
// `also_known` (e.g. the experiment's, so that its INI files load too).
std::map<std::string, std::set<std::string>> mission_config_keys(
    std::map<std::string, std::set<std::string>> also_known = {});

// Reads and validates every key (unknown ones are errors); a bad value throws
// common::InputError naming the file, line, key and value.
MissionConfig load_mission_config(const common::IniConfig& ini,
                                  const std::map<std::string, std::set<std::string>>& also_known = {});

// The complete configuration as INI text: every key with its effective value (faults and
// unresponsive_after_iterations only when not the defaults), so that
// load_mission_config(from_string(mission_to_ini(c))) gives the same mission.
std::string mission_to_ini(const MissionConfig& config);

// The start positions: placement::random_start_positions_m with std::mt19937_64(start_seed).
Eigen::Matrix3Xd mission_start_positions_m(const MissionConfig& config);

}  // namespace losmimo::rawlog
