// The co-evaluation's key table (coevaluation.h): its [coevaluation] keys and the [closed_loop]
// keys it shares with losmimo-record, generated from the table; the old spellings are refused.
#include <gtest/gtest.h>

#include <string>

#include "losmimo/fusion/coevaluation/coevaluation.h"
#include "losmimo/fusion/coevaluation/extensions.h"
#include "losmimo/placement/common/ini_config.h"
#include "losmimo/fusion/closed_loop_settings.h"

namespace losmimo::coevaluation {
namespace {

// The co-evaluation settings of an INI text, both sweeps on (so that every check runs).
CoevaluationSettings load(const std::string& text) {
  common::IniConfig cfg = common::IniConfig::from_string(text, "c.ini");
  cfg.set_override("experiment.sweeps=beacon_noise_m, beacon_outage");
  return load_coevaluation_settings(experiment::load_experiment_settings(cfg, experiment_extensions()));
}

std::string error_of(const std::string& text) {
  try {
    load(text);
  } catch (const common::InputError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(CoevaluationKeys, Defaults_AreTheClosedLoopsForTheSharedKeys) {
  // The shared settings' defaults are the ones [coevaluation] had, and losmimo-record's.
  const CoevaluationSettings c = load("");
  const fusion::ClosedLoopConfig record = fusion::load_closed_loop_config(common::IniConfig(), {});
  EXPECT_EQ(c.closed_loop.simulator.sigma_range_m, 0.1);
  EXPECT_EQ(c.closed_loop.simulator.dr_sigma_floor_m, 0.01);
  EXPECT_EQ(c.closed_loop.simulator.dr_sigma_fraction, 0.02);
  EXPECT_EQ(c.closed_loop.filter.num_particles, 1000);
  EXPECT_EQ(c.closed_loop.refinement.window_epochs, 5);
  EXPECT_TRUE(c.closed_loop.refinement.use_csi);
  EXPECT_EQ(record.simulator.sigma_range_m, c.closed_loop.simulator.sigma_range_m);
  EXPECT_EQ(record.simulator.dr_sigma_floor_m, c.closed_loop.simulator.dr_sigma_floor_m);
  EXPECT_EQ(record.simulator.dr_sigma_fraction, c.closed_loop.simulator.dr_sigma_fraction);
  EXPECT_EQ(record.filter.num_particles, c.closed_loop.filter.num_particles);
  EXPECT_EQ(record.refinement.window_epochs, c.closed_loop.refinement.window_epochs);
  EXPECT_EQ(record.refinement.use_csi, c.closed_loop.refinement.use_csi);
  EXPECT_EQ(
      to_ini(c),
      "[coevaluation]\nbeacon_noise_values_m = 0, 0.02, 0.04, 0.06, 0.08, 0.1, 0.12, 0.14, 0.16, 0.18\n"
      "algorithms = gd_gauss, gd_ekf, gd_gauss_matched, gd_gauss_shape_matched, gd_pf, gd_ekf_ceres, bf, ura_ekf, "
      "centralized\nura_variant = rigid\n"
      "outage_values = 0, 2, 4, 8\noutage_algorithms = gd_ekf, gd_ekf_nofallback\noutage_first_epoch = 10\n"
      "outage_epochs = 30\noutage_degraded_after_epochs = 5\noutage_beacon_noise_m = 0.1\n"
      "misalignment_values_rad = 0, 0.000244140625, 0.00048828125, 0.0009765625, 0.001953125\n"
      "misalignment_algorithms = gd_gauss, gd_ekf, gd_gauss_matched, gd_gauss_shape_matched, "
      "gd_gauss_split_matched, bf\nmisalignment_beacon_noise_m = 0.02\n\n"
      "[closed_loop]\nbeacon_sigma_range_m = 0.1\ndr_sigma_floor_m = 0.01\ndr_sigma_fraction = 0.02\n"
      "num_particles = 1000\nwindow_epochs = 5\nuse_csi = true\n");
}

TEST(CoevaluationKeys, EveryKeysExample_RoundTripsThroughToIni) {
  const std::string defaults = to_ini(load(""));
  for (const auto& k : coevaluation_keys().keys()) {
    ASSERT_FALSE(k.example.empty()) << k.key;
    const std::string text = to_ini(load("[" + k.section + "]\n" + k.key + " = " + k.example + "\n"));
    EXPECT_NE(text, defaults) << k.key;
    EXPECT_EQ(common::IniConfig::from_string(text).get_string(k.section, k.key, "?"), k.example) << k.key;
    EXPECT_EQ(to_ini(load(text)), text) << k.key;
  }
}

TEST(CoevaluationKeys, EveryRefusedValue_NamesFileLineAndKey) {
  for (const auto& k : coevaluation_keys().keys()) {
    ASSERT_FALSE(k.refused.empty()) << k.key;
    for (const std::string& bad : k.refused) {
      const std::string msg = error_of("\n[" + k.section + "]\n" + k.key + " = " + bad + "\n");
      EXPECT_EQ(msg.rfind("c.ini:3: [" + k.section + "] " + k.key + ": ", 0), 0u) << bad << " -> " << msg;
    }
  }
}

TEST(CoevaluationKeys, OldSpellings_AreRefusedNamingTheClosedLoopKey) {
  const std::pair<const char*, const char*> renamed[] = {
      {"sigma_range_m", "beacon_sigma_range_m"},  {"dr_sigma_floor_m", "dr_sigma_floor_m"},
      {"dr_sigma_fraction", "dr_sigma_fraction"}, {"pf_particles", "num_particles"},
      {"refine_window_epochs", "window_epochs"},  {"refine_use_csi", "use_csi"}};
  for (const auto& [old_key, key] : renamed) {
    EXPECT_EQ(
        error_of(std::string("[coevaluation]\n") + old_key + " = 1\n"),
        std::string("c.ini:2: [coevaluation] ") + old_key + ": no longer read: set [closed_loop] " + key + " instead");
    EXPECT_NO_THROW(fusion::closed_loop_keys().key("closed_loop", key));
  }
}

TEST(CoevaluationKeys, ChannelConditions_AreRefusedNamingTheKey) {
  EXPECT_EQ(error_of("[channel]\ncsi_snr_db = 20\n"),
            "c.ini:2: [channel] csi_snr_db: 20 is not supported by co-evaluation, which models the LoS channel with "
            "perfect CSI (use losmimo-experiment)");
  EXPECT_NE(error_of("[channel]\nrician_k_db = 0\n").find("[channel] rician_k_db: 0 is not supported"),
            std::string::npos);
}

TEST(CoevaluationKeys, RuleFailures_NameTheKeyWithFileAndLine) {
  // The closed loop's own rules for the shared keys.
  EXPECT_EQ(error_of("[closed_loop]\nbeacon_sigma_range_m = -1\n"),
            "c.ini:2: [closed_loop] beacon_sigma_range_m: -1: must be >= 0");
  EXPECT_EQ(error_of("[closed_loop]\n\ndr_sigma_floor_m = 0\n"),
            "c.ini:3: [closed_loop] dr_sigma_floor_m: 0: must be > 0");
  // The co-evaluation's, across keys.
  EXPECT_EQ(error_of("[scenario]\nnum_uavs = 9\n[coevaluation]\nalgorithms = gd_ekf, ura_ekf\noutage_values = 0, 4\n"),
            "c.ini:4: [coevaluation] algorithms: ura_ekf needs scenario.num_uavs = bs_rows * bs_cols (16), got 9");
  EXPECT_EQ(error_of("[scenario]\nnum_uavs = 4\n[coevaluation]\nalgorithms = gd_ekf\noutage_values = 0, 5\n"),
            "c.ini:5: [coevaluation] outage_values: 5 UAVs without beacon, but the swarm has 4");
  EXPECT_EQ(error_of("[scenario]\nnum_uavs = 4\n[coevaluation]\nalgorithms = gd_ekf\n"),
            "[coevaluation] outage_values: 8 UAVs without beacon, but the swarm has 4");
}

}  // namespace
}  // namespace losmimo::coevaluation
