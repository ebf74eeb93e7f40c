// The placement settings' key table (placement/settings.h): every key round-trips, every refused
// value and every validator failure names its key, generated from the table.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "losmimo/placement/common/field_error.h"
#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/settings.h"

namespace losmimo::placement {
namespace {

std::string error_of(const common::IniConfig& cfg) {
  try {
    load_placement_settings(cfg);
  } catch (const common::InputError& e) {
    return e.what();
  }
  return "accepted";
}

std::string error_of(const std::string& text) { return error_of(common::IniConfig::from_string(text, "p.ini")); }

TEST(PlacementKeys, Defaults_WriteThePaperSettingsInTableOrder) {
  // The text inside every recorded rawlog's CONFIG: it must not change.
  EXPECT_EQ(to_ini(PlacementSettings{}),
            "[scenario]\nbs_rows = 4\nbs_cols = 4\nbs_spacing_m = 0.25\ncarrier_hz = 6e+10\nnum_uavs = 16\n"
            "cube_side_m = 50\ncube_center_x_m = 1000\ncube_center_y_m = 0\ncube_center_z_m = 0\nsnr_db = 10\n"
            "gain_model = far_field\n\n"
            "[errors]\nsigma_loc_m = 0\nsigma_act_m = 0\n\n"
            "[placement]\ntarget_icn = 0.95\nmax_iterations = 1000\n\n"
            "[gd]\nstep = 0.05\ndecay = 0.999\nmax_move_m = 0.5\nbacktracking = true\nmax_halvings = 6\n"
            "escape = true\nstall_window = 20\nstall_min_decrease = 0.01\n\n"
            "[bf]\nstep = 0.3\ndecay = 0.999\ncontraction = 0.5\nmin_step_m = 0.01\nescape = true\n"
            "stall_window = 20\nstall_min_decrease = 0.01\n");
}

TEST(PlacementKeys, EveryKeysExample_RoundTripsThroughToIni) {
  for (const auto& k : placement_keys().keys()) {
    // GIVEN the key alone at its example value
    ASSERT_FALSE(k.example.empty()) << k.key;
    common::IniConfig cfg;
    cfg.set(k.section, k.key, k.example);
    // WHEN written and read back
    const std::string text = to_ini(load_placement_settings(cfg));
    const common::IniConfig again = common::IniConfig::from_string(text, "again");
    again.require_known(placement_config_keys());
    // THEN it took effect, is written, and reads back to the same text
    EXPECT_NE(text, to_ini(PlacementSettings{})) << k.key;
    EXPECT_EQ(again.get_string(k.section, k.key, "?"), k.example) << k.key;
    EXPECT_EQ(to_ini(load_placement_settings(again)), text) << k.key;
  }
}

TEST(PlacementKeys, EveryRefusedValue_NamesFileLineAndKey) {
  for (const auto& k : placement_keys().keys()) {
    for (const std::string& bad : k.refused) {
      const std::string msg = error_of("# a comment\n[" + k.section + "]\n" + k.key + " = " + bad + "\n");
      EXPECT_EQ(msg.rfind("p.ini:3: [" + k.section + "] " + k.key + ": ", 0), 0u) << bad << " -> " << msg;
    }
  }
}

TEST(PlacementKeys, RangeFailures_NameTheKeyWithFileAndLine) {
  // A key's range (the struct's *_range constants) is checked as the value is read.
  EXPECT_EQ(error_of("[gd]\nstep = 0.1\ndecay = 1.5\n"), "p.ini:3: [gd] decay: 1.5: must be in (0, 1]");
  EXPECT_EQ(error_of("[bf]\n\nmin_step_m = -1\n"), "p.ini:3: [bf] min_step_m: -1: must be in (0, 1000000]");
  EXPECT_EQ(error_of("[placement]\ntarget_icn = 2\n"), "p.ini:2: [placement] target_icn: 2: must be in (0, 1]");
  EXPECT_EQ(error_of("[errors]\nsigma_act_m = 2000\n"), "p.ini:2: [errors] sigma_act_m: 2000: must be in [0, 1000]");
  EXPECT_EQ(error_of("[scenario]\ncube_center_y_m = 2e7\n"),
            "p.ini:2: [scenario] cube_center_y_m: 2e7: must be in [-10000000, 10000000]");
  EXPECT_EQ(error_of("[gd]\nstall_window = 200000\n"),
            "p.ini:2: [gd] stall_window: 200000 is out of range [1, 100000]");
  // A rule across keys whose field's key is not given names the key without a line.
  EXPECT_EQ(error_of("[scenario]\ncube_side_m = 3000\n"),
            "[scenario] cube_center_x_m: scenario.cube_center_x_m = 1000: the start cube must lie entirely in front of "
            "the BS (x > 0)");
  // --set values are located as such.
  common::IniConfig cfg;
  cfg.set_override("gd.max_move_m=0");
  EXPECT_EQ(error_of(cfg), "--set: [gd] max_move_m: 0: must be > 0");
}

TEST(PlacementKeys, ValidatorsRefuseWhatTheKeysRefuse) {
  // A struct built in code is checked against the same ranges as the INI keys.
  const auto message = [](auto options) {
    try {
      placement::validate(options);
    } catch (const common::FieldError& e) {
      return e.field() + " | " + e.what();
    }
    return std::string("accepted");
  };
  placement::GdOptions gd;
  gd.decay = 1.5;
  EXPECT_EQ(message(gd), "decay | gd.decay = 1.5: must be in (0, 1]");
  gd = {};
  gd.stall_window = 200000;
  EXPECT_EQ(message(gd), "stall_window | gd.stall_window = 200000: must be in [1, 100000]");
  placement::BfOptions bf;
  bf.min_step_m = std::numeric_limits<double>::infinity();
  EXPECT_EQ(message(bf), "min_step_m | bf.min_step_m = inf: must be in (0, 1000000]");
  placement::ErrorModel errors;
  errors.sigma_act_m = 2000;
  EXPECT_EQ(message(errors), "sigma_act_m | errors.sigma_act_m = 2000: must be in [0, 1000]");
  placement::Scenario scenario;
  scenario.cube_center_m.y() = 2e7;
  EXPECT_EQ(message(scenario),
            "cube_center_y_m | scenario.cube_center_y_m = 20000000: must be in [-10000000, 10000000]");
  placement::RunOptions run;
  run.max_iterations = 0;  // the baselines' "evaluate the start": allowed in code, not as a key
  EXPECT_EQ(message(run), "accepted");
  EXPECT_NE(error_of("[placement]\nmax_iterations = 0\n").find("max_iterations: 0 is out of range [1, "),
            std::string::npos);
}

}  // namespace
}  // namespace losmimo::placement
