#pragma once
// losmimo-experiment --scene: paths.3Dscene beside paths.png, the path figure's runs as an MRPT
// 3-D scene (fusion/scene, docs/scenes.md). In its own target (apps_scene) so that the apps
// library, and losmimo-eval with it, do not load MRPT's OpenGL libraries.
#include <string>

#include "losmimo/placement/experiment/engine.h"
#include "losmimo/fusion/scene/scene.h"

namespace losmimo::apps {

// The BS array (experiment settings' scenario) and, per run with a recorded path
// (experiment::runs_with_path) and UAV, a track "<algorithm>_<error>/uavNN" of the true
// positions after every iteration: <algorithm> "gd" or "bf", <error> "no_error" (a Fig 1 run)
// or "sigma_act_<value>"; NN from 01, as paths.csv's `uav`. No beliefs: these runs know their
// positions exactly.
scene::SceneContent experiment_scene(const experiment::ExperimentSettings& settings,
                                     const experiment::ExperimentResults& results);

// Writes experiment_scene into `path` (atomically); what ExperimentOptions::scene_writer takes.
void write_experiment_scene(const experiment::ExperimentSettings& settings,
                            const experiment::ExperimentResults& results, const std::string& path);

}  // namespace losmimo::apps
