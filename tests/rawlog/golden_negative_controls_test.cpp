// Negative controls of the golden missions' checker (golden_invariants.h): doctored figures, a
// filter told the wrong noise and malformed invariants files must be violations.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <set>
#include <string>
#include <vector>

#include "rawlog/golden_invariants.h"
#include "rawlog/rawlog_test_util.h"
#include "support/files.h"

namespace losmimo::rawlog::golden {
namespace {

using test_support::load_log;
using test_support::source_path;

TEST(GoldenInvariants, DoctoredNees_IsAViolation) {
  // GIVEN: beacon_outage replayed with the EKF, its figures passing the [ekf+ceres] invariants
  // (the same bounds), and the same figures with a plausible average NEES.
  const std::string dir = source_path("datasets/missions/beacon_outage");
  const InvariantsFile file = read_invariants(dir + "/invariants.ini");
  const MissionLog log = load_log(dir + "/mission.rawlog");
  ReplayFigures f = figures_of(log, replay_mission(log, options_of("ekf")));
  const Bounds bounds = bounds_of(file, "ekf+ceres");
  f.average_nees = 2.78;
  EXPECT_TRUE(violations(bounds, f).empty()) << joined(violations(bounds, f));
  // WHEN: the summary says 1378.88 (a filter that trusts its beliefs far too much).
  f.average_nees = 1378.88;
  const std::vector<std::string> v = violations(bounds, f);
  // THEN: exactly the NEES band's upper edge is violated, with its reason.
  ASSERT_EQ(v.size(), 1u) << joined(v);
  EXPECT_EQ(v[0].rfind("nees_mean_high", 0), 0u) << v[0];
  EXPECT_NE(v[0].find("reason: "), std::string::npos) << v[0];
  // AND: so is one epoch's NEES blown up by one UAV, and a wrong status.
  ReplayFigures g = figures_of(log, replay_mission(log, options_of("ekf")));
  g.status = "iteration_cap";
  for (int k = 0; k < g.epochs / 5; ++k) g.epoch_average_nees[k] += 1000.0 / g.uavs;
  const std::vector<std::string> w = violations(bounds, g);
  std::cout << "[invariants] beacon_outage doctored:" << joined(v) << joined(w) << "\n";
  EXPECT_EQ(w.size(), 2u) << joined(w);
}

TEST(GoldenInvariants, FilterToldHalfTheBeaconNoise_IsAViolation) {
  // GIVEN: the nominal mission replayed by an EKF (and refinement) that assumes half the true
  // beacon sigmas.
  const std::string dir = source_path("datasets/missions/nominal");
  const InvariantsFile file = read_invariants(dir + "/invariants.ini");
  MissionLog log = load_log(dir + "/mission.rawlog");
  ASSERT_TRUE(log.config);
  fusion::ClosedLoopConfig& cl = log.config->closed_loop;
  cl.filter.noise.sigma_range_m = cl.refinement.beacon_sigma_range_m = 0.5 * cl.simulator.sigma_range_m;
  cl.filter.noise.sigma_angle_rad = cl.refinement.beacon_sigma_angle_rad = 0.5 * cl.simulator.sigma_angle_rad;
  // WHEN
  const ReplayFigures f = figures_of(log, replay_mission(log, options_of("ekf")));
  const std::vector<std::string> v = violations(bounds_of(file, "ekf"), f);
  std::cout << "[invariants] nominal ekf told half the beacon noise:" << joined(v) << "\n";
  // THEN: the NEES invariants fail (overconfident beliefs), whatever else does.
  const auto names = [&](const std::string& key) {
    return std::any_of(v.begin(), v.end(), [&](const std::string& s) { return s.rfind(key, 0) == 0; });
  };
  EXPECT_TRUE(names("nees_mean_high")) << joined(v);
  EXPECT_TRUE(names("nees_epoch_min_fraction")) << joined(v);
  // AND: so does the swarm shape's NEES, computed apart (the shape residual alone).
  EXPECT_TRUE(names("shape_nees_mean_high")) << joined(v);
}

TEST(GoldenInvariants, Reader_NamesAKeyWithoutReasonAndAnUnknownKey) {
  const std::string path = test_support::temp_path("invariants.ini");
  std::ofstream(path) << "[mission]\n# golden/ holds it\nvariants = ekf\n\n# a reason\nstatus = converged\nepochs = 3\n"
                         "[ekf]\n# typo\nbeacon = 3\n";
  const InvariantsFile f = read_invariants(path);
  ASSERT_EQ(f.problems.size(), 1u) << joined(f.problems);
  EXPECT_NE(f.problems[0].find(":7: epochs has no reason"), std::string::npos) << f.problems[0];
  const std::vector<std::string> v = violations(bounds_of(f, "ekf"), ReplayFigures{});
  EXPECT_TRUE(std::any_of(v.begin(), v.end(), [](const std::string& s) {
    return s.rfind("unknown key beacon", 0) == 0;
  })) << joined(v);
  EXPECT_TRUE(std::any_of(v.begin(), v.end(), [](const std::string& s) {
    return s.rfind("rmse_max_m = ?: missing", 0) == 0;
  })) << joined(v);
}

}  // namespace
}  // namespace losmimo::rawlog::golden
