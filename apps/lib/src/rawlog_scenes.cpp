#include "rawlog_scenes.h"

#include <cstdio>

#include "losmimo/placement/scenario.h"
#include "losmimo/fusion/rawlog/mission/recorder.h"

namespace losmimo::apps {

namespace {
std::string uav_name(int uav) {
  char name[16];
  std::snprintf(name, sizeof name, "uav%02d", uav);
  return name;
}

void add_belief(scene::Track& track, const localization::Belief& belief) {
  track.believed_m.push_back(belief.mean_m);
  track.believed_cov_m2.push_back(belief.cov_m2);
}
}  // namespace

scene::SceneContent mission_scene(const rawlog::MissionLog& log, const rawlog::ReplayResult* replay) {
  scene::SceneContent content;
  if (log.ours && log.config) {
    content.bs_elements_m = placement::bs_antenna_positions_m(log.config->placement.scenario);
    const localization::BeaconMap bs_beacon = rawlog::bs_ranges_beacon_map();
    for (const auto& [id, p] : bs_beacon.beacons()) content.beacons.push_back({id, p});
  }
  std::vector<scene::Track> tracks(log.num_uavs);
  for (int u = 0; u < log.num_uavs; ++u) tracks[u].name = uav_name(u);
  for (const std::vector<rawlog::LoggedUavEpoch>& row : log.epochs) {
    for (int u = 0; u < static_cast<int>(row.size()) && u < log.num_uavs; ++u) {
      if (row[u].truth_m) tracks[u].true_m.push_back(*row[u].truth_m);
      if (replay) continue;
      if (row[u].refined_belief) {
        add_belief(tracks[u], *row[u].refined_belief);
      } else if (row[u].filter_belief) {
        add_belief(tracks[u], *row[u].filter_belief);
      }
    }
  }
  if (log.final_truth_m && log.final_truth_m->cols() == log.num_uavs) {
    for (int u = 0; u < log.num_uavs; ++u) tracks[u].true_m.push_back(log.final_truth_m->col(u));
  }
  if (replay) {
    for (const rawlog::ReplayUavEpoch& e : replay->estimates) {
      if (e.uav >= 0 && e.uav < log.num_uavs) add_belief(tracks[e.uav], e.belief);
    }
  }
  content.tracks = std::move(tracks);
  return content;
}

scene::SceneContent range_scene(const mrpt_logs::RangeReplayResult& result, const localization::BeaconMap& beacons) {
  scene::SceneContent content;
  for (const auto& [id, p] : beacons.beacons()) content.beacons.push_back({id, p});
  scene::Track robot, refined;
  robot.name = "robot";
  refined.name = "robot_refined";
  for (const mrpt_logs::RangeTrackRow& row : result.track) {
    if (row.has_truth) robot.true_m.emplace_back(row.truth(0), row.truth(1), 0.0);
    robot.believed_m.push_back(row.belief.mean.head<3>());
    robot.believed_cov_m2.push_back(row.belief.cov.topLeftCorner<3, 3>());
    if (row.refined) {
      refined.believed_m.push_back(row.refined->mean.head<3>());
      refined.believed_cov_m2.push_back(row.refined->cov.topLeftCorner<3, 3>());
    }
  }
  content.tracks.push_back(std::move(robot));
  if (!refined.believed_m.empty()) content.tracks.push_back(std::move(refined));
  return content;
}

scene::SceneContent bearing_scene(const mrpt_logs::BearingReplayResult& result,
                                  const localization::BeaconMap& landmarks) {
  scene::SceneContent content;
  for (const auto& [id, p] : landmarks.beacons()) content.beacons.push_back({id, p});
  scene::Track robot, refined;
  robot.name = "robot";
  refined.name = "robot_refined";
  for (const mrpt_logs::BearingTrackRow& row : result.track) {
    if (row.has_truth) robot.true_m.push_back(row.truth.head<3>());  // Pose6: x y z yaw pitch roll
    robot.believed_m.push_back(row.belief.mean.head<3>());
    robot.believed_cov_m2.push_back(row.belief.cov.topLeftCorner<3, 3>());
    if (row.refined) refined.believed_m.push_back(row.refined->head<3>());  // the smoother gives no covariance
  }
  content.tracks.push_back(std::move(robot));
  if (!refined.believed_m.empty()) content.tracks.push_back(std::move(refined));
  return content;
}

std::string scene_path_beside(const std::string& log_path) {
  // The stem beacons_ini_path uses, so that the two files stay side by side.
  const std::string suffix = ".beacons.ini";
  const std::string beacons = rawlog::beacons_ini_path(log_path);
  return beacons.substr(0, beacons.size() - suffix.size()) + ".3Dscene";
}

}  // namespace losmimo::apps
