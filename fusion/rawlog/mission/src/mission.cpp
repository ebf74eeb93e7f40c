#include "losmimo/fusion/rawlog/mission/mission.h"

#include <limits>
#include <random>

#include "losmimo/placement/common/format.h"
#include "losmimo/fusion/closed_loop_settings.h"

namespace losmimo::rawlog {

namespace {}  // namespace

const common::KeyTable<MissionConfig>& mission_keys() {
  using K = common::Key<MissionConfig>;
  constexpr long long kSeedMax = std::numeric_limits<long long>::max();
  static const common::KeyTable<MissionConfig> table(
      {
          K::integer("mission", "seed", &MissionConfig::seed, 0, kSeedMax, "run seed: sensors, filters, CSI, actuation",
                     "11"),
          K::integer("mission", "start_seed", &MissionConfig::start_seed, 0, kSeedMax,
                     "draws the start positions in the start cube", "5"),
          K::real("mission", "epoch_period_s", &MissionConfig::epoch_period_s, common::Range::above_up_to(0.0, 86400.0),
                  "time between epochs in the rawlog's timestamps [s]", "0.5"),
      },
      &common::format_exact);
  return table;
}

std::map<std::string, std::set<std::string>> mission_config_keys(
    std::map<std::string, std::set<std::string>> also_known) {
  auto keys = std::move(also_known);
  for (const auto& known :
       {placement::placement_config_keys(), fusion::closed_loop_keys().known_keys(), mission_keys().known_keys()}) {
    for (const auto& [section, names] : known) keys[section].insert(names.begin(), names.end());
  }
  return keys;
}

MissionConfig load_mission_config(const common::IniConfig& ini,
                                  const std::map<std::string, std::set<std::string>>& also_known) {
  ini.require_known(mission_config_keys(also_known));
  MissionConfig c;
  c.ini = ini;
  c.placement = placement::load_placement_settings(ini);
  placement::require_los_channel(c.placement.channel, ini, "the closed-loop mission");
  c.closed_loop = fusion::load_closed_loop_config(ini, c.placement);
  mission_keys().load(ini, c);
  return c;
}

std::string mission_to_ini(const MissionConfig& c) {
  return placement::to_ini(c.placement) + "\n" + fusion::closed_loop_to_ini(c.closed_loop) + "\n" +
         mission_keys().to_ini(c);
}

Eigen::Matrix3Xd mission_start_positions_m(const MissionConfig& config) {
  std::mt19937_64 rng(config.start_seed);
  return placement::random_start_positions_m(config.placement.scenario, rng);
}

}  // namespace losmimo::rawlog
