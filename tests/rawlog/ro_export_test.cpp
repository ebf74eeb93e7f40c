// One UAV's stream of a recorded mission exported for stock ro-localization (rawlog/ro_export.h),
// read back with MRPT's own CRawlog and losmimo's stock-config reader, and checked against the
// mission log it came from; and losmimo-record's --ro-export refusing a UAV it cannot export.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationBeaconRanges.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/poses/CPosePDFGaussian.h>

#include "losmimo/apps/lib/record_app.h"
#include "losmimo/fusion/rawlog/mrpt_logs/mrpt_app_config.h"
#include "losmimo/fusion/rawlog/mission/recorder.h"
#include "losmimo/fusion/rawlog/mission/ro_export.h"
#include "rawlog_test_util.h"
#include "support/input_error.h"

namespace losmimo::rawlog {
namespace {

constexpr int kUavWithOutage = 1;  // small_mission's outages = 1:3:4: UAV 1 has no beacon at epochs 3 .. 6

struct Recorded {
  std::string dir;
  MissionLog log;
};

const Recorded& recorded() {
  static const Recorded r = [] {
    Recorded out;
    out.dir = test_support::temp_path("ro_export");
    std::filesystem::create_directories(out.dir);
    record_mission(test_support::small_mission("ekf", false), {out.dir + "/run.rawlog", 6, {}});
    out.log = test_support::load_log(out.dir + "/run.rawlog");
    return out;
  }();
  return r;
}

TEST(RoExport, RecordedMission_TheWrittenSensoryFramesCarryTheLogsDisplacementsAndRanges) {
  // GIVEN: UAV 1's export of a recorded mission (a beacon outage in it), written to a rawlog.
  const MissionLog& log = recorded().log;
  ASSERT_TRUE(log.complete);
  const RoExport ro = build_ro_export(log, kUavWithOutage);
  const std::string path = recorded().dir + "/uav1.ro.rawlog";
  write_ro_rawlog(ro, path);

  // WHEN: MRPT reads it back.
  mrpt::obs::CRawlog rawlog;
  ASSERT_TRUE(rawlog.loadFromRawLogFile(path));

  // THEN: one (action, sensory frame) pair per epoch of the log, in order: the action is the
  // log's displacement (none before the first frame) with the DR stream's sigma, the frame
  // holds the epoch's range to the BS beacon, or nothing in the outage.
  ASSERT_EQ(ro.frames.size(), log.epochs.size());
  ASSERT_EQ(rawlog.size(), 2 * log.epochs.size());
  const auto& noise = log.config->closed_loop.filter.noise;
  std::size_t entry = 0;
  mrpt::poses::CPose2D composed;
  Eigen::Vector2d displacement_sum = Eigen::Vector2d::Zero();
  int empty_frames = 0;
  for (std::size_t k = 0; k < log.epochs.size(); ++k) {
    const LoggedUavEpoch& e = log.epochs[k][kUavWithOutage];
    mrpt::obs::CActionCollection::Ptr action;
    mrpt::obs::CSensoryFrame::Ptr frame;
    ASSERT_TRUE(rawlog.getActionObservationPair(action, frame, entry)) << "epoch " << k;
    const auto move = action->getBestMovementEstimation();
    ASSERT_TRUE(move) << "epoch " << k;
    const auto* change = dynamic_cast<const mrpt::poses::CPosePDFGaussian*>(move->poseChange.get());
    ASSERT_NE(change, nullptr) << "epoch " << k;
    const Eigen::Vector3d d = (k == 0 || !e.displacement_m) ? Eigen::Vector3d::Zero() : *e.displacement_m;
    EXPECT_DOUBLE_EQ(change->mean.x(), d.x()) << "epoch " << k;
    EXPECT_DOUBLE_EQ(change->mean.y(), d.y()) << "epoch " << k;
    EXPECT_EQ(change->mean.phi(), 0.0);
    const double sigma_m = noise.dr_sigma_floor_m + noise.dr_sigma_fraction * d.norm();
    EXPECT_NEAR(change->cov(0, 0), sigma_m * sigma_m, 1e-15) << "epoch " << k;
    EXPECT_NEAR(change->cov(1, 1), sigma_m * sigma_m, 1e-15) << "epoch " << k;
    composed = composed + change->mean;
    displacement_sum += d.head<2>();
    const auto ranges = frame->getObservationByClass<mrpt::obs::CObservationBeaconRanges>();
    ASSERT_EQ(static_cast<bool>(ranges), e.beacon.has_value()) << "epoch " << k;
    if (!ranges) {
      EXPECT_EQ(frame->size(), 0u);
      ++empty_frames;
      continue;
    }
    ASSERT_EQ(ranges->sensedData.size(), 1u);
    EXPECT_EQ(ranges->sensedData[0].beaconID, kBsBeaconId);
    EXPECT_EQ(ranges->sensedData[0].sensedDistance, static_cast<float>(e.beacon->range_m)) << "epoch " << k;
    EXPECT_EQ(ranges->stdError, static_cast<float>(log.config->closed_loop.simulator.sigma_range_m));
    EXPECT_EQ(ranges->sensorLabel, uav_label(kUavWithOutage, UavStream::kBsRanges));
  }
  EXPECT_EQ(empty_frames, 4);
  // Robot-frame increments composed with heading 0 are the BS-frame displacements' sum.
  EXPECT_NEAR(composed.x(), displacement_sum.x(), 1e-12);
  EXPECT_NEAR(composed.y(), displacement_sum.y(), 1e-12);
}

TEST(RoExport, RecordedMission_TruthRowsAndConfigPlaceTheTrackWhereTheLogHasIt) {
  // GIVEN: UAV 2's export, its ground-truth text and config.
  const MissionLog& log = recorded().log;
  const RoExport ro = build_ro_export(log, 2);
  const std::string dir = recorded().dir;
  std::ofstream(dir + "/gt.txt") << ro_ground_truth_text(ro);
  std::ofstream(dir + "/ro.ini") << ro_localization_ini_text(ro, {"x.rawlog", "gt.txt", "out"});

  // WHEN: losmimo's reader of stock configs and ground-truth files reads them.
  const mrpt_logs::MrptAppConfig c = mrpt_logs::read_mrpt_app_config(dir + "/ro.ini");
  const std::vector<Eigen::Vector3d> rows = mrpt_logs::read_relative_ground_truth(dir + "/gt.txt");

  // THEN: the start is the UAV's logged belief after epoch 0, start + row k the truth at epoch
  // k; the map is the BS beacon at the origin with the range sigma; the files are the ones named.
  ASSERT_TRUE(c.start_pose.has_value());
  EXPECT_EQ(c.start_pose->x(), log.epochs[0][2].filter_belief->mean_m.x());
  EXPECT_EQ(c.start_pose->y(), log.epochs[0][2].filter_belief->mean_m.y());
  EXPECT_EQ(c.start_pose->z(), 0.0);
  ASSERT_EQ(rows.size(), log.epochs.size());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    EXPECT_NEAR(c.start_pose->x() + rows[k].x(), log.epochs[k][2].truth_m->x(), 1e-9) << "epoch " << k;
    EXPECT_NEAR(c.start_pose->y() + rows[k].y(), log.epochs[k][2].truth_m->y(), 1e-9) << "epoch " << k;
    EXPECT_EQ(rows[k].z(), 0.0);
  }
  ASSERT_EQ(c.beacons.size(), 1u);
  EXPECT_TRUE(c.beacons.find(kBsBeaconId) != nullptr);
  EXPECT_EQ(c.beacons.find(kBsBeaconId)->norm(), 0.0);
  EXPECT_DOUBLE_EQ(*c.range_sigma_m, log.config->closed_loop.simulator.sigma_range_m);
  EXPECT_EQ(c.particles, kRoParticles);
  EXPECT_EQ(std::filesystem::path(c.ground_truth_file).filename(), "gt.txt");
}

TEST(RoExport, UavOutsideTheLog_RefusedNamingIt) {
  const MissionLog& log = recorded().log;
  test_support::expect_input_error([&] { build_ro_export(log, 4); }, {"UAV 4", "4 UAVs", "0 .. 3"});
  test_support::expect_input_error([&] { build_ro_export(log, -1); }, {"UAV -1"});
}

TEST(RoExport, RecordAppUavOutsideTheMissionOrTwice_Exit2NamingItAndNothingWritten) {
  const std::string dir = test_support::temp_path("ro_export_refused");
  std::filesystem::create_directories(dir);
  for (const std::vector<int>& uavs : {std::vector<int>{4}, std::vector<int>{-3}, std::vector<int>{1, 1}}) {
    apps::RecordAppOptions o;
    o.overrides = {"scenario.num_uavs=4", "placement.max_iterations=2"};
    o.out_path = dir + "/run.rawlog";
    o.ro_export_uavs = uavs;
    std::ostringstream out, err;
    EXPECT_EQ(apps::run_record_app(o, out, err), 2);
    EXPECT_NE(err.str().find("--ro-export: UAV " + std::to_string(uavs.back())), std::string::npos) << err.str();
    EXPECT_TRUE(std::filesystem::is_empty(dir)) << "a refused run left files in " << dir;
  }
}

TEST(RoExport, ExportPaths_BesideTheLogNamedForTheUav) {
  const RoExportPaths p = ro_export_paths("/d/run.rawlog", 3);
  EXPECT_EQ(p.rawlog, "/d/run.uav03.ro.rawlog");
  EXPECT_EQ(p.ini, "/d/run.uav03.ro.ini");
  EXPECT_EQ(p.ground_truth, "/d/run.uav03.ro_truth.txt");
  EXPECT_EQ(ro_export_paths("log", 12).rawlog, "log.uav12.ro.rawlog");
}

}  // namespace
}  // namespace losmimo::rawlog
