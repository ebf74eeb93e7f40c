// The [experiment] key table (experiment/settings.h): every key round-trips through config.ini's
// text, every refused value and every check across keys names its key, generated from the table.
#include <gtest/gtest.h>

#include <string>

#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/experiment/extension.h"
#include "losmimo/placement/experiment/settings.h"

namespace losmimo::experiment {
namespace {

std::string error_of(const std::string& text) {
  try {
    load_experiment_settings(common::IniConfig::from_string(text, "e.ini"));
  } catch (const common::InputError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(ExperimentKeys, EveryKeysExample_RoundTripsThroughConfigIni) {
  const std::string defaults = to_ini(load_experiment_settings(common::IniConfig()));
  for (const auto& k : experiment_keys().keys()) {
    // GIVEN the key alone at its example value
    ASSERT_FALSE(k.example.empty()) << k.key;
    common::IniConfig cfg;
    cfg.set(k.section, k.key, k.example);
    // WHEN written as config.ini and read back
    const std::string text = to_ini(load_experiment_settings(cfg));
    const common::IniConfig again = common::IniConfig::from_string(text, "config.ini");
    // THEN it took effect, is written as given, and reads back to the same text
    EXPECT_NE(text, defaults) << k.key;
    EXPECT_EQ(again.get_string(k.section, k.key, "?"), k.example) << k.key;
    EXPECT_EQ(to_ini(load_experiment_settings(again)), text) << k.key;
  }
}

TEST(ExperimentKeys, EveryRefusedValue_NamesFileLineAndKey) {
  for (const auto& k : experiment_keys().keys()) {
    ASSERT_FALSE(k.refused.empty()) << k.key;
    for (const std::string& bad : k.refused) {
      const std::string msg = error_of("\n[" + k.section + "]\n" + k.key + " = " + bad + "\n");
      EXPECT_EQ(msg.rfind("e.ini:3: [" + k.section + "] " + k.key + ": ", 0), 0u) << bad << " -> " << msg;
    }
  }
}

TEST(ExperimentKeys, ChecksAcrossKeys_NameTheKey) {
  EXPECT_EQ(error_of("[experiment]\nsweeps = sigma_loc_m, beacon_noise_m\n"),
            "e.ini:2: [experiment] sweeps: unknown sweep 'beacon_noise_m' (known: sigma_loc_m, sigma_act_m)");
  EXPECT_EQ(error_of("[experiment]\nsweeps = sigma_act_m, sigma_act_m\n"),
            "e.ini:2: [experiment] sweeps: sweep 'sigma_act_m' listed twice");
  // URA needs a slot per UAV; the algorithms key is named even when not given.
  EXPECT_EQ(error_of("[scenario]\nnum_uavs = 20\n"),
            "[experiment] algorithms: ura needs scenario.num_uavs <= bs_rows * bs_cols (16), got 20");
  EXPECT_EQ(error_of("[scenario]\nnum_uavs = 20\n[experiment]\nalgorithms = gd, ura_lattice\n"),
            "e.ini:4: [experiment] algorithms: ura_lattice needs scenario.num_uavs <= bs_rows * bs_cols (16), got 20");
  EXPECT_EQ(error_of("[scenario]\nnum_uavs = 20\n[experiment]\nalgorithms = gd, bf\n"), "accepted");
  EXPECT_EQ(error_of("[scenario]\nnum_uavs = 9\n"), "accepted");  // 9 of the 16 slots
}

TEST(ExperimentKeys, SigmaPointsOfASweepNotRun_AreNotWritten) {
  const ExperimentSettings s = load_experiment_settings(
      common::IniConfig::from_string("[experiment]\nsweeps = sigma_act_m\nsigma_act_values_m = 0.1,0.2\n"));
  const common::IniConfig written = common::IniConfig::from_string(to_ini(s));
  EXPECT_FALSE(written.has("experiment", "sigma_loc_values_m"));
  EXPECT_EQ(written.get_string("experiment", "sigma_act_values_m", ""), "0.1, 0.2");
  ASSERT_EQ(s.sweeps.size(), 1u);
  EXPECT_EQ(s.sweeps[0].values, (std::vector<double>{0.1, 0.2}));
}

}  // namespace
}  // namespace losmimo::experiment
