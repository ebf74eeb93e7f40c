// The mission config's fault keys and losmimo-record's exit code 3 (faults in the closed loop:
// tests/fusion/closed_loop_faults_test.cpp).
#include <gtest/gtest.h>

#include <cstdio>
#include <sstream>
#include <string>

#include "losmimo/apps/lib/record_app.h"
#include "losmimo/placement/common/ini_config.h"
#include "losmimo/localization/position/filter.h"
#include "losmimo/fusion/rawlog/mission/mission.h"
#include "fusion/closed_loop_fixtures.h"

namespace losmimo::rawlog {
namespace {

using fusion::UavFaultKind;
using test_support::contains;

TEST(MissionConfigFaults, FaultKeys_ParseRoundTripAndRejectBadValues) {
  // GIVEN / WHEN: the INI keys of losmimo-record.
  const MissionConfig c = load_mission_config(
      common::IniConfig::from_string("[closed_loop]\nfaults = unresponsive:3:12, nan_beacon:0:5:10\n"
                                     "unresponsive_after_iterations = 4\n",
                                     "mission.ini"));
  // THEN
  ASSERT_EQ(c.closed_loop.faults.size(), 2u);
  EXPECT_EQ(c.closed_loop.faults[0].kind, UavFaultKind::kUnresponsive);
  EXPECT_EQ(c.closed_loop.faults[0].uav, 3);
  EXPECT_EQ(c.closed_loop.faults[0].from_iteration, 12);
  EXPECT_EQ(c.closed_loop.faults[0].num_iterations, 0);
  EXPECT_EQ(c.closed_loop.faults[1].kind, UavFaultKind::kNanBeacon);
  EXPECT_EQ(c.closed_loop.faults[1].num_iterations, 10);
  EXPECT_EQ(c.closed_loop.unresponsive_after_iterations, 4);
  // to_ini keeps them; without them the INI has no fault keys at all.
  const MissionConfig again = load_mission_config(common::IniConfig::from_string(mission_to_ini(c), "again"));
  EXPECT_EQ(mission_to_ini(again), mission_to_ini(c));
  EXPECT_FALSE(contains(mission_to_ini(load_mission_config(common::IniConfig())), "faults"));

  const auto error = [](const std::string& text) {
    try {
      load_mission_config(common::IniConfig::from_string(text, "m.ini"));
    } catch (const common::InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_TRUE(contains(error("[closed_loop]\nfaults = dead:1:2\n"), "faults"))
      << error("[closed_loop]\nfaults = dead:1:2\n");
  EXPECT_TRUE(contains(error("[closed_loop]\nfaults = dead:1:2\n"), "'dead'"));
  EXPECT_TRUE(contains(error("[closed_loop]\nfaults = unresponsive:16:2\n"), "uav"));
  EXPECT_TRUE(contains(error("[closed_loop]\nfaults = unresponsive:1:0\n"), "from_iteration"));
  EXPECT_TRUE(
      contains(error("[closed_loop]\nfaults = unresponsive:1\n"), "expected kind:uav:from_iteration[:num_iterations]"));
  EXPECT_TRUE(contains(error("[closed_loop]\nfaults = nan_csi:1:2\n"), "nan_csi needs refine"));
  EXPECT_TRUE(contains(error("[closed_loop]\nunresponsive_after_iterations = 0\n"), "unresponsive_after_iterations"));
  EXPECT_TRUE(contains(error("[closed_loop]\nfaults = unresponsive:1:2\n"), "accepted"));
  // The closed loop models the LoS channel with perfect CSI: channel conditions are refused.
  EXPECT_EQ(error("[channel]\nrician_k_db = 10\n"),
            "m.ini:2: [channel] rician_k_db: 10 is not supported by the closed-loop mission, which models the LoS "
            "channel with perfect CSI (use losmimo-experiment)");
  EXPECT_TRUE(contains(error("\n[channel]\ncsi_snr_db = 20\n"), "m.ini:3: [channel] csi_snr_db: 20"));
  EXPECT_EQ(error("[channel]\nrician_k_db = inf\ncoherence_iterations = 4\n"), "accepted");
}

TEST(MissionConfigFaults, BeaconRangeLimitKey_ParsesRoundTripsAndRejectsBadValues) {
  const MissionConfig defaults = load_mission_config(common::IniConfig());
  EXPECT_EQ(defaults.closed_loop.filter.max_beacon_range_m, localization::FilterConfig{}.max_beacon_range_m);
  // Not written when it is the default: the CONFIG of existing missions does not change.
  EXPECT_FALSE(contains(mission_to_ini(defaults), "max_beacon_range_m"));
  const MissionConfig c =
      load_mission_config(common::IniConfig::from_string("[closed_loop]\nfilter_max_beacon_range_m = 2500\n", "m.ini"));
  EXPECT_EQ(c.closed_loop.filter.max_beacon_range_m, 2500.0);
  const MissionConfig again = load_mission_config(common::IniConfig::from_string(mission_to_ini(c), "again"));
  EXPECT_EQ(again.closed_loop.filter.max_beacon_range_m, 2500.0);
  for (const char* bad : {"0", "-1", "inf", "nan", "far"}) {
    std::string message = "accepted";
    try {
      load_mission_config(common::IniConfig::from_string(
          std::string("[closed_loop]\nfilter_max_beacon_range_m = ") + bad + "\n", "m.ini"));
    } catch (const common::InputError& e) {
      message = e.what();
    }
    EXPECT_TRUE(contains(message, "filter_max_beacon_range_m")) << bad << ": " << message;
  }
}

TEST(RecordAppFaults, UnresponsiveUav_ExitCode3WithTheReasonAndAClosedLog) {
  // GIVEN: losmimo-record with a UAV that dies at iteration 3.
  const std::string out_path = ::testing::TempDir() + "losmimo_record_fault.rawlog";
  apps::RecordAppOptions options;
  options.overrides = {"closed_loop.faults=unresponsive:5:3", "placement.max_iterations=50"};
  options.out_path = out_path;
  options.replace = true;  // the test's file from an earlier run
  std::ostringstream out, err;
  // WHEN
  const int code = apps::run_record_app(options, out, err);
  // THEN
  EXPECT_EQ(code, 3) << out.str() << err.str();
  EXPECT_TRUE(contains(out.str(), "uav_unresponsive")) << out.str();
  EXPECT_TRUE(contains(err.str(), "run ended by a fault: UAV 5: no measurement and no motion")) << err.str();
  std::FILE* f = std::fopen(out_path.c_str(), "rb");
  ASSERT_NE(f, nullptr);
  std::fseek(f, 0, SEEK_END);
  EXPECT_GT(std::ftell(f), 1000);
  std::fclose(f);
  std::remove(out_path.c_str());
}

}  // namespace
}  // namespace losmimo::rawlog
