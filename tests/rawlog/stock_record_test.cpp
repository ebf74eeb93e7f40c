// A log written by losmimo-record, used by MRPT's stock tools (Debian mrpt-apps): one UAV's
// ODOMETRY and BS_RANGES streams kept with stock rawlog-edit, then stock pf-localization run to
// the end on them with a config built from the beacons.ini written beside the log. Without the
// stock tools: skipped when mrpt-apps is not installed, failed when it is
// (support/dependencies.h).
//
// Geometry: one beacon (the BS) about 1 km away gives radial information only. So the stock
// estimate is checked where ranges can place it (its distance to the BS against the truth's)
// and, laterally, only against dead reckoning from the same prior's centre: the stock PF cannot
// do much better there, and must not do worse.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "losmimo/fusion/rawlog/mission/format.h"
#include "losmimo/fusion/rawlog/mission/log.h"
#include "losmimo/fusion/rawlog/mission/recorder.h"
#include "rawlog_test_util.h"
#include "support/dependencies.h"

namespace losmimo::rawlog {
namespace {

// Measured over 17 runs (the stock PF seeds from the clock; about 2 s each): radial error
// 0.00004-0.12 m (sigma_range 0.1 m); x-y error 14.7-26.1 m, dead reckoning's 24.6 m (UAV 0
// starts 24 m from the prior box's centre, laterally). The prior box is the start cube's x-y
// extent, 50 m x 50 m: with no lateral information the stock PF's lateral mean wanders within
// that spread (its 1-sigma is 50 / sqrt(12) = 14 m), hence the margin.
constexpr double kRadialTolerance_m = 0.5;  // 5 range sigmas
constexpr double kLateralMargin_m = 10.0;   // the stock estimate vs dead reckoning

// pf-localization's remaining sections, appended to the written beacons.ini (MRPT merges a
// repeated section): the log, no GUI, the per-step motion noise of observation-only logs
// ([DummyOdometryParams]; the prior box comes from the beacons.ini).
std::string pf_config(const std::string& beacons_ini, const std::string& log, const std::string& out_dir) {
  std::ostringstream c;
  c << beacons_ini << "\n[LocalizationExperiment]\nrawlog_file=" << log << "\nlogOutput_dir=" << out_dir
    << "\n3DSceneFrequency=-1\nexperimentRepetitions=1\nparticles_count=5000\nSHOW_PROGRESS_3D_REAL_TIME=false\n"
    << "\n[DummyOdometryParams]\nminStdXY=0.05\nminStdPHI=0\n"
    << "\n[PF_options]\nPF_algorithm=0\nresamplingMethod=0\nadaptiveSampleSize=1\nBETA=0.5\nsampleSize=5000\n"
    << "\n[KLD_options]\nKLD_binSize_PHI_deg=5\nKLD_binSize_XY=0.15\nKLD_delta=0.01\nKLD_epsilon=0.01\n"
    << "KLD_maxSampleSize=5000\nKLD_minSampleSize=1000\n";
  return c.str();
}

TEST(StockPfLocalization, RecordedMission_OneUavsStreamLocalizesOnTheWrittenBeaconsIni) {
  LOSMIMO_REQUIRE_PROGRAM("pf-localization", "mrpt-apps");
  LOSMIMO_REQUIRE_PROGRAM("rawlog-edit", "mrpt-apps");
  // GIVEN: a recorded mission (4 UAVs, 12 epochs), its beacons.ini, and UAV 0's two standard
  // streams kept by stock rawlog-edit.
  const std::string dir = test_support::temp_path("stock_record");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const MissionConfig config = test_support::small_mission("ekf", false);
  const std::string log_path = dir + "/run.rawlog";
  const RecordResult rec = record_mission(config, {log_path, 6, {}});
  const std::string beacons = mission_beacons_ini_text(config);
  const std::string keep = "cd '" + dir + "' && rawlog-edit -i run.rawlog -o uav0.rawlog --keep-label " +
                           uav_label(0, UavStream::kOdometry) + "," + uav_label(0, UavStream::kBsRanges) +
                           " > edit.txt 2>&1";
  ASSERT_EQ(std::system(keep.c_str()), 0) << "rawlog-edit failed, see " << dir << "/edit.txt";
  const placement::Scenario& scenario = config.placement.scenario;
  std::ofstream(dir + "/pf.ini") << pf_config(beacons, dir + "/uav0.rawlog", dir + "/pflog");

  // WHEN: stock pf-localization runs on them.
  const std::string cmd = "cd '" + dir + "' && pf-localization pf.ini < /dev/null > out.txt 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << "pf-localization failed, see " << dir << "/out.txt";

  // THEN: one estimate per range record, to the end of the log.
  std::ifstream out(dir + "/out.txt");
  const std::regex pdf(R"(PDF estimation: \(([-0-9.]+),([-0-9.]+),([-0-9.]+)deg\))");
  const std::regex odo(R"(Odometry estimation: \(([-0-9.]+),([-0-9.]+),([-0-9.]+)deg\))");
  std::vector<Eigen::Vector2d> estimates, odometry;
  std::smatch m;
  for (std::string line; std::getline(out, line);) {
    if (std::regex_search(line, m, pdf)) estimates.emplace_back(std::stod(m[1]), std::stod(m[2]));
    if (std::regex_search(line, m, odo)) odometry.emplace_back(std::stod(m[1]), std::stod(m[2]));
  }
  ASSERT_EQ(static_cast<std::int64_t>(estimates.size()), rec.label_counts.at(uav_label(0, UavStream::kBsRanges)));
  ASSERT_FALSE(odometry.empty());
  const MissionLog log = test_support::load_log(log_path);
  ASSERT_TRUE(log.complete);
  ASSERT_TRUE(log.epochs.back()[0].truth_m.has_value());
  const Eigen::Vector3d truth = *log.epochs.back()[0].truth_m;
  const Eigen::Vector2d stock = estimates.back();
  // The stock app's odometry is the log's: the sum of UAV 0's displacements (printed to 1 mm).
  Eigen::Vector2d displacement_sum = Eigen::Vector2d::Zero();
  for (const auto& epoch : log.epochs)
    if (epoch[0].displacement_m) displacement_sum += epoch[0].displacement_m->head<2>();
  EXPECT_LT((odometry.back() - displacement_sum).cwiseAbs().maxCoeff(), 1e-3);
  // Dead reckoning from the prior's centre (the stock app's own odometry sum).
  const Eigen::Vector2d dr = scenario.cube_center_m.head<2>() + odometry.back();
  // Radial: the 2-D estimate's distance to the BS (the BS beacon at the origin) carries the
  // measured 3-D range (the stock app puts the UAV in the beacon's plane).
  const double radial_error_m = std::abs(stock.norm() - truth.norm());
  const double error_m = (stock - truth.head<2>()).norm();
  const double dr_error_m = (dr - truth.head<2>()).norm();
  std::cout << "stock pf-localization, UAV 0, epoch " << log.epochs.size() - 1 << ": radial error " << radial_error_m
            << " m, position error " << error_m << " m, dead reckoning's " << dr_error_m << " m\n";
  EXPECT_LT(radial_error_m, kRadialTolerance_m);
  EXPECT_LT(error_m, dr_error_m + kLateralMargin_m);
}

}  // namespace
}  // namespace losmimo::rawlog
