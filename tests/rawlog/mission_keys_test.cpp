// The mission config's key tables ([closed_loop]: fusion/closed_loop_settings.h; [mission]:
// rawlog/mission.h): the CONFIG text of a default mission, every key round-tripping through
// mission_to_ini, every refused value and every rule naming its key, generated from the tables.
#include <gtest/gtest.h>

#include <string>

#include "losmimo/placement/common/ini_config.h"
#include "losmimo/fusion/closed_loop_settings.h"
#include "losmimo/fusion/rawlog/mission/mission.h"

namespace losmimo::rawlog {
namespace {

MissionConfig load(const std::string& text) {
  return load_mission_config(common::IniConfig::from_string(text, "m.ini"));
}

std::string error_of(const std::string& text) {
  try {
    load(text);
  } catch (const common::InputError& e) {
    return e.what();
  }
  return "accepted";
}

// Every key of the two tables, as (section, key, example, refused values).
template <typename Fn>
void for_each_key(Fn&& fn) {
  for (const auto& k : fusion::closed_loop_keys().keys()) fn(k.section, k.key, k.example, k.refused);
  for (const auto& k : mission_keys().keys()) fn(k.section, k.key, k.example, k.refused);
}

TEST(MissionKeys, DefaultMission_WritesTheRecordedConfigText) {
  // The CONFIG block of every rawlog recorded with the defaults (datasets/missions): unchanged.
  EXPECT_EQ(mission_to_ini(load("")),
            placement::to_ini(placement::PlacementSettings{}) +
                "\n[closed_loop]\nfilter = ekf\nnum_particles = 1000\nrefine = false\nuse_csi = true\n"
                "window_epochs = 5\nfallback = true\ngd_mode = mean\nbeacon_sigma_range_m = 0.10000000000000001\n"
                "beacon_sigma_angle_rad = 0.0001\nbeacon_period_epochs = 1\noutlier_fraction = 0\n"
                "dr_sigma_floor_m = 0.01\ndr_sigma_fraction = 0.02\nfilter_sigma_range_m = 0.10000000000000001\n"
                "filter_sigma_angle_rad = 0.0001\ndegraded_after_epochs = 10\noutages = \n\n"
                "[mission]\nseed = 1\nstart_seed = 1\nepoch_period_s = 1\n");
}

TEST(MissionKeys, EveryKeysExample_RoundTripsThroughMissionToIni) {
  const std::string defaults = mission_to_ini(load(""));
  for_each_key([&](const std::string& section, const std::string& key, const std::string& example,
                   const std::vector<std::string>&) {
    ASSERT_FALSE(example.empty()) << key;
    const std::string text = mission_to_ini(load("[" + section + "]\n" + key + " = " + example + "\n"));
    EXPECT_NE(text, defaults) << key;
    EXPECT_EQ(common::IniConfig::from_string(text).get_string(section, key, "?"), example) << key;
    EXPECT_EQ(mission_to_ini(load(text)), text) << key;
  });
}

TEST(MissionKeys, EveryRefusedValue_NamesFileLineAndKey) {
  for_each_key([&](const std::string& section, const std::string& key, const std::string&,
                   const std::vector<std::string>& refused) {
    ASSERT_FALSE(refused.empty()) << key;
    for (const std::string& bad : refused) {
      const std::string msg = error_of("\n[" + section + "]\n" + key + " = " + bad + "\n");
      EXPECT_EQ(msg.rfind("m.ini:3: [" + section + "] " + key + ": ", 0), 0u) << bad << " -> " << msg;
    }
  });
}

TEST(MissionKeys, RuleFailures_NameTheKeyThatSetTheField) {
  // The ranges of SimulatorConfig, FilterConfig, RefinementConfig and ClosedLoopConfig, read
  // with the key; a key that sets several fields takes the strictest field's range.
  EXPECT_EQ(error_of("[closed_loop]\nbeacon_sigma_range_m = -1\n"),
            "m.ini:2: [closed_loop] beacon_sigma_range_m: -1: must be >= 0");
  EXPECT_EQ(error_of("[closed_loop]\noutlier_fraction = 2\n"),
            "m.ini:2: [closed_loop] outlier_fraction: 2: must be in [0, 1]");
  EXPECT_EQ(error_of("[closed_loop]\ndr_sigma_floor_m = 0\n"),
            "m.ini:2: [closed_loop] dr_sigma_floor_m: 0: must be > 0");
  EXPECT_EQ(error_of("[closed_loop]\nbeacon_sigma_range_m = 0.5\nfilter_sigma_range_m = -0.5\n"),
            "m.ini:3: [closed_loop] filter_sigma_range_m: -0.5: must be > 0");
  EXPECT_EQ(error_of("[closed_loop]\nfilter_sigma_angle_rad = 0\n"),
            "m.ini:2: [closed_loop] filter_sigma_angle_rad: 0: must be > 0");
  EXPECT_EQ(error_of("[closed_loop]\nfilter_max_beacon_range_m = 0\n"),
            "m.ini:2: [closed_loop] filter_max_beacon_range_m: 0: must be > 0");
  // A filter assuming the true noise: the beacon key is named though the filter's copy is bad too.
  EXPECT_EQ(error_of("[closed_loop]\nbeacon_sigma_angle_rad = -1\n")
                .rfind("m.ini:2: [closed_loop] beacon_sigma_angle_rad: ", 0),
            0u);
  // A matched zero noise breaks the refinement's rule on a key not given: named without a line.
  EXPECT_EQ(error_of("[closed_loop]\nbeacon_sigma_angle_rad = 0\n"),
            "[closed_loop] filter_sigma_angle_rad: refinement.beacon_sigma_angle_rad = 0: must be > 0");
  // UAV indices beyond the swarm (16 UAVs), and the rule across faults, refine and use_csi.
  EXPECT_EQ(error_of("[closed_loop]\noutages = 1:0:4, 16:0:4\n"),
            "m.ini:2: [closed_loop] outages: closed_loop.outages[1].uav = 16: must be < the number of UAVs (16)");
  EXPECT_EQ(error_of("[scenario]\nnum_uavs = 4\n[closed_loop]\nfaults = unresponsive:4:2\n"),
            "m.ini:4: [closed_loop] faults: closed_loop.faults[0].uav = 4: must be < the number of UAVs (4)");
  EXPECT_EQ(error_of("[closed_loop]\nrefine = true\nfaults = nan_csi:1:2\nuse_csi = false\n"),
            "m.ini:3: [closed_loop] faults: nan_csi needs refine = true and use_csi = true");
  EXPECT_EQ(error_of("[closed_loop]\nrefine = true\nfaults = nan_csi:1:2\n"), "accepted");
  EXPECT_EQ(error_of("[mission]\nepoch_period_s = 0\n"), "m.ini:2: [mission] epoch_period_s: 0: must be in (0, 86400]");
}

}  // namespace
}  // namespace losmimo::rawlog
