// losmimo-replay's range-only mode on bad input: exit 2 with a message naming what is wrong.
#include <gtest/gtest.h>

#include <sstream>

#include "losmimo/apps/lib/replay_app.h"
#include "losmimo/fusion/rawlog/mission/format.h"
#include "losmimo/fusion/rawlog/mission/recorder.h"
#include "rawlog_test_util.h"

namespace losmimo::mrpt_logs {
namespace {

apps::ReplayAppOptions options(const std::string& log, const std::string& beacons_text) {
  const std::string beacons = test_support::temp_path("input_beacons.txt");
  test_support::write_file_bytes(beacons, beacons_text);
  apps::ReplayAppOptions o;
  o.rawlog_path = log;
  o.beacons_path = beacons;
  return o;
}

TEST(RangeReplayInput, LogWithoutBeaconRanges_ExitsTwoListingWhatItHolds) {
  // GIVEN: a version-1 losmimo mission log (its BS ranging is not CObservationBeaconRanges).
  const apps::ReplayAppOptions o =
      options(test_support::source_path("datasets/missions/nominal/mission.rawlog"), "0 0 0 0\n");
  std::ostringstream out, err;
  EXPECT_EQ(apps::run_replay_app(o, out, err), 2);
  EXPECT_NE(err.str().find("no CObservationBeaconRanges in the log"), std::string::npos) << err.str();
  EXPECT_NE(err.str().find("CObservationComment"), std::string::npos) << err.str();
}

TEST(RangeReplayInput, SeveralUavsRanges_ExitsTwoNamingTheCommandThatKeepsOne) {
  // GIVEN: a losmimo log (4 UAVs) with its written beacons.ini.
  const std::string log = test_support::temp_path("several_uavs.rawlog");
  const rawlog::MissionConfig config = test_support::small_mission("ekf", false);
  rawlog::record_mission(config, {log, 6, {}});
  const std::string ini = test_support::temp_path("several_uavs.beacons.ini");
  test_support::write_file_bytes(ini, rawlog::mission_beacons_ini_text(config));
  apps::ReplayAppOptions o;
  o.rawlog_path = log;
  o.mrpt_config = ini;
  // THEN: refused, not one track over four vehicles' ranges.
  std::ostringstream out, err;
  EXPECT_EQ(apps::run_replay_app(o, out, err), 2);
  EXPECT_NE(err.str().find("CObservationBeaconRanges of 4 UAVs"), std::string::npos) << err.str();
  // The labels the recorder writes (rawlog/format.h), e.g. UAV00_ODOMETRY,UAV00_BS_RANGES.
  const std::string keep = "--keep-label " + rawlog::uav_label(0, rawlog::UavStream::kOdometry) + "," +
                           rawlog::uav_label(0, rawlog::UavStream::kBsRanges);
  EXPECT_EQ(keep, "--keep-label UAV00_ODOMETRY,UAV00_BS_RANGES");
  EXPECT_NE(err.str().find(keep), std::string::npos) << err.str();
}

TEST(RangeReplayInput, BadOptions_ExitTwoNamingTheOptionAndValue) {
  const std::string log = test_support::source_path("datasets/missions/nominal/mission.rawlog");
  {
    apps::ReplayAppOptions o = options(log, "0 0 0 0\n");
    o.initial_pose = "1,2";
    std::ostringstream out, err;
    EXPECT_EQ(apps::run_replay_app(o, out, err), 2);
    EXPECT_NE(err.str().find("--initial-pose '1,2'"), std::string::npos) << err.str();
  }
  {
    apps::ReplayAppOptions o = options(log, "0 0 0 0\n");
    o.initial_pose = "1,2,3";
    o.initial_sigma = "0,1";
    std::ostringstream out, err;
    EXPECT_EQ(apps::run_replay_app(o, out, err), 2);
    EXPECT_NE(err.str().find("--initial-sigma '0,1'"), std::string::npos) << err.str();
  }
  {
    apps::ReplayAppOptions o = options(log, "0 0 zero 0\n");
    std::ostringstream out, err;
    EXPECT_EQ(apps::run_replay_app(o, out, err), 2);
    EXPECT_NE(err.str().find("zero"), std::string::npos) << err.str();
  }
  {
    apps::ReplayAppOptions o = options(log, "0 0 0 0\n");
    o.mrpt_config = "/nonexistent/app.ini";
    std::ostringstream out, err;
    EXPECT_EQ(apps::run_replay_app(o, out, err), 2);
    EXPECT_NE(err.str().find("/nonexistent/app.ini"), std::string::npos) << err.str();
  }
  {
    apps::ReplayAppOptions o = options(log, "0 0 0 0\n");
    o.estimator = "ukf";
    std::ostringstream out, err;
    EXPECT_EQ(apps::run_replay_app(o, out, err), 2);
    EXPECT_NE(err.str().find("--estimator 'ukf'"), std::string::npos) << err.str();
  }
}

}  // namespace
}  // namespace losmimo::mrpt_logs
