#include <gtest/gtest.h>

#include "losmimo/placement/common/ini_config.h"
#include "support/input_error.h"
#include "losmimo/placement/settings.h"

namespace lp = losmimo::placement;

using losmimo::test_support::expect_input_error;

TEST(PlacementSettings, UnknownKey_IsRejectedWithItsLine) {
  const auto cfg = losmimo::common::IniConfig::from_string("[scenario]\nsnr_db = 10\nsnr_dB = 3\n", "e.ini");
  expect_input_error([&] { cfg.require_known(lp::placement_config_keys()); }, {"e.ini:3", "snr_dB", "unknown key"});
  const auto cfg2 = losmimo::common::IniConfig::from_string("[scenery]\nx = 1\n", "f.ini");
  expect_input_error([&] { cfg2.require_known(lp::placement_config_keys()); }, {"unknown section", "scenery"});
}

TEST(PlacementSettings, BadValues_NameKeyAndValue) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"[errors]\nsigma_loc_m = nan\n", "sigma_loc_m"},
      {"[errors]\nsigma_act_m = -0.1\n", "sigma_act_m"},
      {"[gd]\nstep = 0\n", "step"},
      {"[bf]\nstep = -1\n", "step"},
      {"[gd]\ndecay = 1.5\n", "decay"},
      {"[scenario]\nbs_rows = 0\n", "bs_rows"},
      {"[scenario]\ncarrier_hz = abc\n", "carrier_hz"},
      {"[scenario]\ngain_model = nearfield\n", "gain_model"},
      {"[placement]\ntarget_icn = 2\n", "target_icn"},
      {"[placement]\nmax_iterations = -5\n", "max_iterations"},
  };
  for (const auto& [text, key] : cases) {
    const auto cfg = losmimo::common::IniConfig::from_string(text, "g.ini");
    expect_input_error([&] { lp::load_placement_settings(cfg); }, {"g.ini:2", key});
  }
}

TEST(PlacementSettings, Overrides_TakePrecedenceAndAreValidated) {
  auto cfg = losmimo::common::IniConfig::from_string("[errors]\nsigma_loc_m = 0.1\n");
  cfg.set_override("errors.sigma_loc_m=0.04");
  EXPECT_DOUBLE_EQ(lp::load_placement_settings(cfg).errors.sigma_loc_m, 0.04);
  expect_input_error([&] { cfg.set_override("errors_sigma=1"); }, {"section.key=value"});
  cfg.set_override("gd.step=-2");
  expect_input_error([&] { lp::load_placement_settings(cfg); }, {"--set", "step"});
}

TEST(PlacementSettings, DefaultsRoundTripThroughIni) {
  const lp::PlacementSettings defaults;
  const std::string text = lp::to_ini(defaults);
  const auto cfg = losmimo::common::IniConfig::from_string(text);
  cfg.require_known(lp::placement_config_keys());
  EXPECT_EQ(lp::to_ini(lp::load_placement_settings(cfg)), text);
}
