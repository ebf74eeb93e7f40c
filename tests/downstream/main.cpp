// Downstream use of the installed losmimo: the scenario of a shipped configuration, the swarm
// placed by distributed gradient descent from a random start, then the link evaluated at the
// final positions (ICN, per-stream SINR), all through the public headers of losmimo::placement.
//   place_and_evaluate [CONFIG.ini]   (default: the installed configs/paper.ini)
#include <iostream>
#include <random>
#include <string>

#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/channel.h"
#include "losmimo/placement/gd.h"
#include "losmimo/placement/metrics.h"
#include "losmimo/placement/run.h"
#include "losmimo/placement/scenario.h"
#include "losmimo/placement/settings.h"
#include "losmimo/placement/swarm.h"

namespace lp = losmimo::placement;

int main(int argc, char** argv) {
  const std::string config_path = argc > 1 ? argv[1] : std::string(LOSMIMO_DATA_DIR) + "/configs/paper.ini";
  try {
    const lp::PlacementSettings settings =
        lp::load_placement_settings(losmimo::common::IniConfig::from_file(config_path));
    const lp::Scenario& scenario = settings.scenario;
    const lp::ChannelModel model(scenario);
    std::mt19937_64 rng(2024);
    const Eigen::Matrix3Xd start = lp::random_start_positions_m(scenario, rng);

    lp::Swarm swarm(model, start, {}, 1);  // no localization or actuation errors
    lp::GradientDescentPlanner gd(scenario, settings.gd);
    const lp::RunResult run = lp::run_placement(gd, swarm, settings.run);

    const lp::LinkMetrics start_link = lp::evaluate_link(model.matrix(start), scenario.noise_variance());
    const lp::LinkMetrics link = lp::evaluate_link(model.matrix(run.final_m), scenario.noise_variance());
    std::cout << "uavs " << scenario.num_uavs << ", planner " << run.planner << ", status " << lp::to_string(run.status)
              << " after " << run.iterations << " iterations\n";
    std::cout << "icn start " << start_link.icn << " final " << link.icn << "\n";
    std::cout << "sinr_zf_db min " << lp::to_db(link.sinr.zf.minCoeff()) << " max "
              << lp::to_db(link.sinr.zf.maxCoeff()) << "\n";
    std::cout << "sum_rate_zf_bps_hz " << link.sum_rate_zf_bps_hz << "\n";
    return run.converged() && link.icn > start_link.icn ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "place_and_evaluate: " << e.what() << "\n";
    return 2;
  }
}
