// The golden missions' invariants (golden_invariants.h) on a fresh replay of each mission and
// variant, and the shipped invariants files: complete, every bound with its reason.
// LOSMIMO_GOLDEN_MISSIONS=DIR checks DIR/<mission>/{mission.rawlog, invariants.ini} instead of
// datasets/missions (scripts/regenerate-golden runs the Missions/* cases on its candidates).
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

namespace losmimo::rawlog::golden {
namespace {

using test_support::load_log;
using test_support::source_path;

// ---------------------------------------------------------------------------------------------
// Missions and their variants.

std::string missions_root() {
  const char* env = std::getenv("LOSMIMO_GOLDEN_MISSIONS");
  return env && *env ? std::string(env) : source_path("datasets/missions");
}

struct MissionVariant {
  std::string mission;
  std::string variant;  // "ekf", "pf", "ekf+ceres"
};
void PrintTo(const MissionVariant& c, std::ostream* os) { *os << c.mission << " " << c.variant; }

std::vector<MissionVariant> mission_variants() {
  std::vector<MissionVariant> out;
  std::error_code ec;
  std::vector<std::filesystem::path> dirs;
  for (const auto& entry : std::filesystem::directory_iterator(missions_root(), ec))
    if (std::filesystem::exists(entry.path() / "invariants.ini")) dirs.push_back(entry.path());
  std::sort(dirs.begin(), dirs.end());
  for (const auto& dir : dirs)
    for (const std::string& v : listed_variants(read_invariants((dir / "invariants.ini").string())))
      out.push_back({dir.filename().string(), v});
  return out;
}

class Missions : public ::testing::TestWithParam<MissionVariant> {};

TEST_P(Missions, InvariantsHoldOnAFreshReplay) {
  // GIVEN: a mission's rawlog and its invariants.
  const MissionVariant& c = GetParam();
  const std::string dir = missions_root() + "/" + c.mission;
  const InvariantsFile file = read_invariants(dir + "/invariants.ini");
  ASSERT_TRUE(file.problems.empty()) << joined(file.problems);
  const MissionLog log = load_log(dir + "/mission.rawlog");
  ASSERT_TRUE(log.complete) << log.stop_description();
  // WHEN: replayed with the variant's estimator.
  const ReplayFigures f = figures_of(log, replay_mission(log, options_of(c.variant)));
  std::cout << "[invariants] " << c.mission << " " << c.variant << ": status " << f.status << ", epochs " << f.epochs
            << ", final ICN " << f.final_icn << ", NEES " << f.average_nees << ", LoS RMSE " << f.range_rmse_m
            << " m, RMSE " << f.rmse_m << " m (beacon epochs), beacons " << f.beacons << ", fallback "
            << f.fallback_fraction << "\n";
  // THEN
  const std::vector<std::string> v = violations(bounds_of(file, c.variant), f);
  EXPECT_TRUE(v.empty()) << dir << "/invariants.ini [" << c.variant << "]:" << joined(v);
}

INSTANTIATE_TEST_SUITE_P(Golden, Missions, ::testing::ValuesIn(mission_variants()),
                         [](const ::testing::TestParamInfo<MissionVariant>& i) {
                           std::string v = i.param.variant;
                           for (char& ch : v)
                             if (ch == '+') ch = '_';
                           return i.param.mission + "_" + v;
                         });

// ---------------------------------------------------------------------------------------------
// The files: complete, every bound with its reason, and the numbers following from the config.

TEST(GoldenInvariants, EveryShippedGoldenVariant_HasEveryInvariantWithAReason) {
  const std::string root = source_path("datasets/missions");
  std::set<std::string> on_disk;
  for (const auto& entry : std::filesystem::directory_iterator(root))
    if (entry.is_directory()) on_disk.insert(entry.path().filename().string());
  EXPECT_EQ(on_disk, std::set<std::string>(shipped_missions().begin(), shipped_missions().end()));
  for (const std::string& mission : shipped_missions()) {
    const InvariantsFile file = read_invariants(root + "/" + mission + "/invariants.ini");
    EXPECT_TRUE(file.problems.empty()) << joined(file.problems);
    // THEN: the listed variants are exactly golden/'s folders.
    std::set<std::string> golden;
    for (const auto& entry : std::filesystem::directory_iterator(root + "/" + mission + "/golden"))
      golden.insert(entry.path().filename().string());
    const std::vector<std::string> listed = listed_variants(file);
    EXPECT_EQ(std::set<std::string>(listed.begin(), listed.end()), golden) << mission;
    // AND: every variant has every key, and nothing else.
    for (const std::string& v : listed) {
      const Bounds b = bounds_of(file, v);
      for (const std::string& key : variant_keys()) EXPECT_TRUE(b.count(key)) << mission << " [" << v << "] " << key;
      EXPECT_EQ(b.size(), variant_keys().size()) << mission << " [" << v << "]";
    }
    for (const auto& [section, bounds] : file.sections)
      EXPECT_TRUE(section == "mission" || std::count(listed.begin(), listed.end(), section))
          << mission << " [" << section << "]";
  }
}

}  // namespace
}  // namespace losmimo::rawlog::golden
