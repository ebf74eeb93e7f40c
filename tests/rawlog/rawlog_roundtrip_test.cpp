// Recorder -> reader round trip: every value the recorder writes reads back equal to
// what the closed loop produced (captured independently by an observer on an identical run),
// the integrity marks verify, and the stock rawlog-edit counts what we wrote.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <regex>
#include <sstream>

#include <mrpt/obs/CObservationBeaconRanges.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationRawDAQ.h>
#include <mrpt/obs/CObservationRobotPose.h>

#include "losmimo/apps/lib/record_app.h"
#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/experiment/extension.h"
#include "losmimo/fusion/rawlog/mission/format.h"
#include "losmimo/fusion/rawlog/mission/log.h"
#include "losmimo/fusion/rawlog/mission/recorder.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/fusion/rawlog/mission/replay.h"
#include "rawlog/rawlog_test_util.h"
#include "support/dependencies.h"

namespace losmimo::rawlog {
namespace {

using test_support::small_mission;
using test_support::temp_path;

// Everything the loop showed its observer.
struct Capture : fusion::ClosedLoopObserver {
  std::vector<fusion::EpochObservation> epochs;
  std::vector<fusion::MoveObservation> moves;
  void on_epoch(const fusion::EpochObservation& e) override { epochs.push_back(e); }
  void on_move(const fusion::MoveObservation& m) override { moves.push_back(m); }
};

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

bool same_bits(const Eigen::Vector3d& a, const mrpt::poses::CPose3D& p) {
  return same_bits(a.x(), p.x()) && same_bits(a.y(), p.y()) && same_bits(a.z(), p.z());
}

TEST(RawlogRoundTrip, EveryObservationReadsBackEqualToWhatTheLoopProduced) {
  // GIVEN: a small mission with refinement (CSI from the loop) and an outage, recorded.
  const MissionConfig config = small_mission();
  const std::string path = temp_path("roundtrip.rawlog");
  const RecordResult rec = record_mission(config, {path, 6, {}});
  Capture cap;
  const fusion::ClosedLoopRun run = fusion::run_closed_loop(config.placement, mission_start_positions_m(config),
                                                            config.closed_loop, config.seed, &cap);
  ASSERT_EQ(run.run.iterations, rec.run.run.iterations);  // the recorder did not change the run

  // WHEN: read back object by object.
  rawlog_io::RawlogReader reader = rawlog_io::RawlogReader::open_file(path);
  std::vector<rawlog_io::RawlogObject> objects;
  while (auto o = reader.next()) objects.push_back(std::move(*o));

  // THEN: a clean end, and every object in the order written.
  EXPECT_EQ(reader.status().stop, rawlog_io::RawlogStop::kEnd) << reader.status().describe();
  ASSERT_EQ(static_cast<std::int64_t>(objects.size()), rec.objects);
  std::size_t next_epoch = 0, next_move = 0;
  std::map<std::string, int> seen;
  std::map<int, Eigen::Vector2d> odometry_sum;  // per UAV
  for (int m = 0; m < config.placement.scenario.num_uavs; ++m) odometry_sum[m] = Eigen::Vector2d::Zero();
  int checked = 0;
  for (const rawlog_io::RawlogObject& o : objects) {
    const auto* obs = dynamic_cast<const mrpt::obs::CObservation*>(o.object.get());
    ASSERT_NE(obs, nullptr) << o.class_name;
    const auto label = parse_uav_label(obs->sensorLabel);
    if (!label) continue;  // CONFIG and marks: checked through load_mission_log below
    ++seen[obs->sensorLabel];
    const auto* pose = dynamic_cast<const mrpt::obs::CObservationRobotPose*>(obs);
    const auto* daq = dynamic_cast<const mrpt::obs::CObservationRawDAQ*>(obs);
    if (label->stream == UavStream::kMove) {
      ASSERT_LT(next_move, cap.moves.size());
      const fusion::MoveObservation& mv = cap.moves[next_move++];
      ASSERT_TRUE(daq && daq->AIN_double.size() == 8);
      EXPECT_EQ(label->uav, mv.uav);
      EXPECT_EQ(daq->AIN_double[0], mv.iteration);
      for (int i = 0; i < 3; ++i) {
        EXPECT_TRUE(same_bits(daq->AIN_double[2 + i], mv.commanded_m(i)));
        EXPECT_TRUE(same_bits(daq->AIN_double[5 + i], mv.actual_m(i)));
      }
      ++checked;
      continue;
    }
    // One UAV's epoch records come together, REFINED last (refine is on); then the moves,
    // and after the last epoch the final positions.
    if (next_epoch >= cap.epochs.size()) {
      // The final positions after the last iteration.
      ASSERT_EQ(label->stream, UavStream::kTruth);
      EXPECT_TRUE(same_bits(run.run.final_m.col(label->uav), pose->pose.mean));
      ++checked;
      continue;
    }
    const fusion::EpochObservation& e = cap.epochs[next_epoch];
    ASSERT_EQ(label->uav, e.uav) << obs->sensorLabel;
    switch (*label->stream) {
      case UavStream::kDr:
        ASSERT_TRUE(pose && e.measured_displacement_m);
        EXPECT_TRUE(same_bits(*e.measured_displacement_m, pose->pose.mean));
        break;
      case UavStream::kTruth:
        ASSERT_TRUE(pose);
        EXPECT_TRUE(same_bits(e.true_position_m, pose->pose.mean));
        EXPECT_EQ(pose->pose.cov.norm(), 0.0);
        break;
      case UavStream::kBeacon: {
        const auto* b = dynamic_cast<const mrpt::obs::CObservationBearingRange*>(obs);
        ASSERT_TRUE(b && e.beacon && b->sensedData.size() == 1);
        EXPECT_EQ(b->sensedData[0].range, static_cast<float>(e.beacon->range_m));
        EXPECT_EQ(b->sensedData[0].yaw, static_cast<float>(e.beacon->azimuth_rad));
        EXPECT_EQ(b->sensedData[0].pitch, static_cast<float>(-e.beacon->elevation_rad));
        break;
      }
      case UavStream::kBeacon64:
        ASSERT_TRUE(daq && e.beacon && daq->AIN_double.size() == 3);
        EXPECT_TRUE(same_bits(daq->AIN_double[0], e.beacon->range_m));
        EXPECT_TRUE(same_bits(daq->AIN_double[1], e.beacon->azimuth_rad));
        EXPECT_TRUE(same_bits(daq->AIN_double[2], e.beacon->elevation_rad));
        break;
      case UavStream::kCsi:
        ASSERT_TRUE(daq && e.csi);
        ASSERT_EQ(daq->AIN_double.size(), static_cast<std::size_t>(2 * e.csi->y.size()));
        for (Eigen::Index k = 0; k < e.csi->y.size(); ++k) {
          EXPECT_TRUE(same_bits(daq->AIN_double[2 * k], e.csi->y(k).real()));
          EXPECT_TRUE(same_bits(daq->AIN_double[2 * k + 1], e.csi->y(k).imag()));
        }
        break;
      case UavStream::kBelief:
      case UavStream::kRefined: {
        const localization::Belief& b = *label->stream == UavStream::kBelief ? e.filter_belief : e.belief;
        ASSERT_TRUE(pose);
        EXPECT_TRUE(same_bits(b.mean_m, pose->pose.mean));
        // The refined covariance of two runs differs in the last bits (ceres::Covariance orders
        // parameter blocks by heap address, rawlog/replay.h); the filter's is bit for bit. The
        // log keeps the upper triangle (CPose3DPDFGaussian).
        for (int i = 0; i < 3; ++i)
          for (int j = i; j < 3; ++j) {
            if (*label->stream == UavStream::kBelief)
              EXPECT_TRUE(same_bits(b.cov_m2(i, j), pose->pose.cov(i, j)));
            else
              EXPECT_NEAR(b.cov_m2(i, j), pose->pose.cov(i, j), 1e-9 * b.cov_m2.cwiseAbs().maxCoeff());
          }
        if (*label->stream == UavStream::kRefined) ++next_epoch;  // the last record of the epoch
        break;
      }
      case UavStream::kOdometry: {
        // The cumulative reading: the sum of the UAV's displacements so far, in x and y.
        const auto* odo = dynamic_cast<const mrpt::obs::CObservationOdometry*>(obs);
        ASSERT_TRUE(odo);
        if (e.measured_displacement_m) odometry_sum[e.uav] += e.measured_displacement_m->head<2>();
        EXPECT_NEAR(odo->odometry.x(), odometry_sum[e.uav].x(), 1e-12);
        EXPECT_NEAR(odo->odometry.y(), odometry_sum[e.uav].y(), 1e-12);
        EXPECT_EQ(odo->odometry.phi(), 0.0);
        break;
      }
      case UavStream::kBsRanges: {
        const auto* b = dynamic_cast<const mrpt::obs::CObservationBeaconRanges*>(obs);
        ASSERT_TRUE(b && e.beacon && b->sensedData.size() == 1);
        EXPECT_EQ(b->sensedData[0].beaconID, kBsBeaconId);
        EXPECT_EQ(b->sensedData[0].sensedDistance, static_cast<float>(e.beacon->range_m));
        EXPECT_EQ(b->stdError, static_cast<float>(config.closed_loop.simulator.sigma_range_m));
        EXPECT_GT(b->maxSensorDistance, b->sensedData[0].sensedDistance);
        break;
      }
      case UavStream::kMove:
        break;
    }
    ++checked;
  }
  EXPECT_EQ(next_epoch, cap.epochs.size());
  EXPECT_EQ(next_move, cap.moves.size());
  EXPECT_GT(checked, 300);
  // UAV 1 had no beacon at epochs 3..6: 4 fewer beacons than epochs.
  EXPECT_EQ(seen["UAV01_BEACON"], rec.epochs - 4);
  EXPECT_EQ(seen["UAV00_BEACON"], rec.epochs);
  EXPECT_EQ(seen["UAV01_BS_RANGES"], rec.epochs - 4);
  EXPECT_EQ(seen["UAV01_ODOMETRY"], rec.epochs);
  for (const auto& [label, n] : seen) EXPECT_EQ(n, rec.label_counts.at(label)) << label;

  // AND: the interpreter accepts every mark and sees the whole log.
  rawlog_io::RawlogReader again = rawlog_io::RawlogReader::open_file(path);
  const MissionLog log = load_mission_log(again);
  EXPECT_TRUE(log.ours);
  EXPECT_TRUE(log.complete);
  EXPECT_TRUE(log.integrity_error.empty()) << log.integrity_error;
  EXPECT_EQ(static_cast<int>(log.epochs.size()), rec.epochs);
  ASSERT_TRUE(log.final_truth_epoch.has_value());
  EXPECT_EQ(*log.final_truth_epoch, rec.run.run.iterations);
  EXPECT_TRUE(log.skipped.empty());
  ASSERT_TRUE(log.config.has_value());
  EXPECT_EQ(mission_to_ini(*log.config), mission_to_ini(config));
}

TEST(RawlogRoundTrip, StockRawlogEditInfo_CountsWhatWasWritten) {
  LOSMIMO_REQUIRE_PROGRAM("rawlog-edit", "mrpt-apps");
  // GIVEN
  const std::string path = temp_path("info.rawlog");
  const RecordResult rec = record_mission(small_mission(), {path, 6, {}});
  // WHEN
  const std::string cmd = "rawlog-edit -i '" + path + "' --info 2>&1";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(cmd.c_str(), "r"), pclose);
  ASSERT_TRUE(pipe);
  std::string text;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), buf.size(), pipe.get())) text += buf.data();
  // THEN: the total and every label's count.
  std::smatch m;
  ASSERT_TRUE(std::regex_search(text, m, std::regex("Overall number of objects\\s*:\\s*(\\d+)"))) << text;
  EXPECT_EQ(std::stoll(m[1]), rec.objects);
  const std::regex row("\\s(UAV\\d+_[A-Z0-9_]+)\\s*/\\s*(\\d+)\\s*/");
  int labels = 0;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), row); it != std::sregex_iterator(); ++it) {
    EXPECT_EQ(std::stoll((*it)[2]), rec.label_counts.at((*it)[1])) << (*it)[1];
    ++labels;
  }
  EXPECT_EQ(labels, 4 * 10);  // 4 UAVs x 10 streams
}

TEST(RawlogMissionConfig, BadKeysAndValues_NameTheKey) {
  const auto load = [](const std::string& text) {
    return load_mission_config(common::IniConfig::from_string(text, "m.ini"));
  };
  EXPECT_THROW(load("[closed_loop]\nfilter = kalman\n"), common::InputError);
  EXPECT_THROW(load("[closed_loop]\nbogus = 1\n"), common::InputError);
  EXPECT_THROW(load("[closed_loop]\noutages = 3:1\n"), common::InputError);
  EXPECT_THROW(load("[closed_loop]\noutages = 16:0:4\n"), common::InputError);  // 16 UAVs: 0..15
  EXPECT_THROW(load("[closed_loop]\nbeacon_sigma_range_m = -1\n"), common::InputError);
  EXPECT_THROW(load("[mission]\nepoch_period_s = 0\n"), common::InputError);
  try {
    load("[closed_loop]\noutages = 2:x:4\n");
    FAIL();
  } catch (const common::InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("m.ini:2"), std::string::npos) << msg;
    EXPECT_NE(msg.find("first_epoch"), std::string::npos) << msg;
  }
  const MissionConfig ok = load("[closed_loop]\noutages = 2:0:1000, 5:20:30\nfilter = pf\n");
  ASSERT_EQ(ok.closed_loop.outages.size(), 2u);
  EXPECT_EQ(ok.closed_loop.outages[1].uav, 5);
  EXPECT_EQ(ok.closed_loop.outages[1].window.first_epoch, 20);
  EXPECT_EQ(ok.closed_loop.outages[1].window.num_epochs, 30);
  EXPECT_EQ(ok.closed_loop.filter_kind, localization::FilterKind::kParticle);
  // The complete INI loads back to the same mission.
  EXPECT_EQ(mission_to_ini(load(mission_to_ini(ok))), mission_to_ini(ok));
}

TEST(RawlogMissionConfig, TheExperimentsIni_LoadsWhenItsSectionsAreDeclaredKnown) {
  const common::IniConfig ini = common::IniConfig::from_file(test_support::source_path("datasets/configs/paper.ini"));
  EXPECT_THROW(load_mission_config(ini), common::InputError);  // [experiment] is not a mission section
  const MissionConfig c = load_mission_config(ini, experiment::experiment_config_keys());
  EXPECT_EQ(c.placement.scenario.num_uavs, 16);
  EXPECT_EQ(mission_to_ini(c).find("[experiment]"), std::string::npos);
}

TEST(RawlogRecordApp, TheExperimentsIni_IsAMissionSource) {
  std::ostringstream out, err;
  const std::string path = temp_path("paper_ini.rawlog");
  EXPECT_EQ(
      apps::run_record_app(
          {test_support::source_path("datasets/configs/paper.ini"), {"placement.max_iterations=1"}, path}, out, err),
      0)
      << err.str();
  std::remove(path.c_str());
  std::remove(beacons_ini_path(path).c_str());
}

TEST(RawlogRecordApp, WritesTheBeaconsIniBesideTheLog_AndRefusesOneInTheWay) {
  // GIVEN / WHEN: a recording into NAME.rawlog.
  const std::string path = temp_path("with_beacons.rawlog");
  const std::string ini = temp_path("with_beacons.beacons.ini");
  std::ostringstream out, err;
  ASSERT_EQ(apps::run_record_app({"", {"placement.max_iterations=1"}, path, true}, out, err), 0) << err.str();
  // THEN: NAME.beacons.ini, the mission's, is beside it.
  EXPECT_EQ(beacons_ini_path(path), ini);
  MissionConfig defaults = load_mission_config(common::IniConfig());
  EXPECT_EQ(test_support::read_file(ini), mission_beacons_ini_text(defaults));
  EXPECT_NE(out.str().find(ini), std::string::npos) << out.str();
  // AND: the summary splits the beliefs' lateral error into the common offset and the shape, as
  // the replay of the log does (replay.h).
  const ReplayResult replayed = replay_mission(test_support::load_log(path), {});
  std::ostringstream split;
  split << "lateral RMSE " << replayed.lateral_rmse_m << " m, of it a common offset of "
        << replayed.common_lateral_rms_m << " m (RMS) and a shape error of " << replayed.shape_lateral_rmse_m << " m";
  EXPECT_NE(out.str().find(split.str()), std::string::npos) << out.str() << "\nexpected: " << split.str();
  // AND: a beacons.ini in the way is refused up front (exit 2, no staged log left behind).
  std::remove(path.c_str());
  std::ostringstream out2, err2;
  EXPECT_EQ(apps::run_record_app({"", {"placement.max_iterations=1"}, path, false}, out2, err2), 2);
  EXPECT_NE(err2.str().find(ini + " holds a file"), std::string::npos) << err2.str();
  EXPECT_FALSE(std::filesystem::exists(path + ".partial"));
  EXPECT_FALSE(std::filesystem::exists(path));
  std::remove(ini.c_str());
}

TEST(RawlogRecordApp, ExitCodes) {
  std::ostringstream out, err;
  EXPECT_EQ(apps::run_record_app({"/nonexistent/x.ini", {}, temp_path("x.rawlog")}, out, err), 2);
  EXPECT_EQ(apps::run_record_app({"", {"closed_loop.filter=ukf"}, temp_path("x.rawlog")}, out, err), 2);
  EXPECT_NE(err.str().find("filter"), std::string::npos) << err.str();
  EXPECT_EQ(apps::run_record_app({"", {"placement.max_iterations=1"}, "/nonexistent-dir/x.rawlog"}, out, err), 1);
}

}  // namespace
}  // namespace losmimo::rawlog
