#pragma once
// The 3-D scenes of losmimo-record and losmimo-replay --scene (fusion/scene, docs/scenes.md).
#include <string>

#include "losmimo/localization/pose/range_model.h"
#include "losmimo/fusion/rawlog/mrpt_logs/bearing_replay.h"
#include "losmimo/fusion/rawlog/mrpt_logs/range_replay.h"
#include "losmimo/fusion/rawlog/mission/log.h"
#include "losmimo/fusion/rawlog/mission/replay.h"
#include "losmimo/fusion/scene/scene.h"

namespace losmimo::apps {

// A mission log (ours or foreign), one track "uavNN" per UAV (NN from 00, the rawlog labels'
// UAVnn_ and estimates.csv's `uav`): the logged truth of every epoch that has one, then the final
// positions (after the last iteration) when logged; the beliefs of `replay` when given (every
// estimates.csv row of the UAV, held beliefs of silent epochs included), else the logged ones
// (the refined belief where there is one, else the filter's; none for a silent epoch). Ours
// also has the BS array (its config's scenario) and the BS beacon of the BS_RANGES stream.
scene::SceneContent mission_scene(const rawlog::MissionLog& log, const rawlog::ReplayResult* replay);

// A range-only replay: the map's beacons, track "robot" (the filter's pose per frame, its
// position block's covariance, and the ground truth where given, at z = 0: MRPT's ground truth
// is 2-D) and with refinement "robot_refined" (the smoother's poses). No BS array.
scene::SceneContent range_scene(const mrpt_logs::RangeReplayResult& result, const localization::BeaconMap& beacons);

// A bearing-range replay (losmimo-replay --landmarks / a kf-slam --mrpt-config): the map's landmarks
// as beacons, the robot's true path, filter beliefs with covariances and the smoother's path.
scene::SceneContent bearing_scene(const mrpt_logs::BearingReplayResult& result,
                                  const localization::BeaconMap& landmarks);

// Where losmimo-record --scene writes: "<log path without a .rawlog extension>.3Dscene".
std::string scene_path_beside(const std::string& log_path);

}  // namespace losmimo::apps
