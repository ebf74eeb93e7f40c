#include "losmimo/apps/lib/experiment_scene.h"

#include <cstdio>

#include "losmimo/placement/common/format.h"
#include "losmimo/placement/experiment/paths.h"
#include "losmimo/placement/scenario.h"

namespace losmimo::apps {

namespace {
std::string run_name(const experiment::TracedRun& t) {
  return experiment::to_string(t.algorithm) +
         (t.fig1() ? "_no_error" : "_sigma_act_" + common::format_double(t.sigma_act_m));
}
}  // namespace

scene::SceneContent experiment_scene(const experiment::ExperimentSettings& settings,
                                     const experiment::ExperimentResults& results) {
  scene::SceneContent content;
  content.bs_elements_m = placement::bs_antenna_positions_m(settings.placement.scenario);
  for (const experiment::TracedRun* t : experiment::runs_with_path(results.traces)) {
    const std::vector<Eigen::Matrix3Xd>& path = t->result.path;
    for (Eigen::Index m = 0; m < path.front().cols(); ++m) {
      char uav[16];
      std::snprintf(uav, sizeof uav, "/uav%02d", static_cast<int>(m + 1));
      scene::Track track;
      track.name = run_name(*t) + uav;
      for (const Eigen::Matrix3Xd& q : path) track.true_m.push_back(q.col(m));
      content.tracks.push_back(std::move(track));
    }
  }
  return content;
}

void write_experiment_scene(const experiment::ExperimentSettings& settings,
                            const experiment::ExperimentResults& results, const std::string& path) {
  scene::write_scene_file(experiment_scene(settings, results), path);
}

}  // namespace losmimo::apps
