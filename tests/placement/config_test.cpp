#include <gtest/gtest.h>

#include "losmimo/placement/experiment_extension.h"
#include "losmimo/placement/settings.h"

namespace lp = losmimo::placement;

namespace {
// Runs f, expecting an InputError whose message contains every fragment.
template <typename F>
void expect_input_error(F&& f, const std::vector<std::string>& fragments) {
  try {
    f();
    FAIL() << "no InputError";
  } catch (const lp::InputError& e) {
    for (const auto& frag : fragments) EXPECT_NE(std::string(e.what()).find(frag), std::string::npos) << e.what();
  }
}
}  // namespace

TEST(IniConfig, ParsesSectionsKeysAndComments) {
  const auto cfg = lp::IniConfig::from_string("# top\n[scenario]\nsnr_db = 7.5 ; trailing\n\n[errors]\nsigma_loc_m=0.1\n");
  EXPECT_DOUBLE_EQ(cfg.get_double("scenario", "snr_db", 0.0), 7.5);
  EXPECT_DOUBLE_EQ(cfg.get_double("errors", "sigma_loc_m", 0.0), 0.1);
  EXPECT_DOUBLE_EQ(cfg.get_double("errors", "sigma_act_m", 0.25), 0.25);
}

TEST(IniConfig, MalformedLines_NameTheLine) {
  expect_input_error([] { lp::IniConfig::from_string("[scenario]\nsnr_db 10\n", "a.ini"); }, {"a.ini:2", "key = value"});
  expect_input_error([] { lp::IniConfig::from_string("snr_db = 10\n", "b.ini"); }, {"b.ini:1", "outside"});
  expect_input_error([] { lp::IniConfig::from_string("[s]\nk=1\nk=2\n", "c.ini"); }, {"c.ini:3", "duplicate"});
  expect_input_error([] { lp::IniConfig::from_string("[scen\n", "d.ini"); }, {"d.ini:1"});
  expect_input_error([] { lp::IniConfig::from_file("/nonexistent/x.ini"); }, {"/nonexistent/x.ini", "cannot open"});
}

TEST(PlacementSettings, UnknownKey_IsRejectedWithItsLine) {
  const auto cfg = lp::IniConfig::from_string("[scenario]\nsnr_db = 10\nsnr_dB = 3\n", "e.ini");
  expect_input_error([&] { cfg.require_known(lp::placement_config_keys()); }, {"e.ini:3", "snr_dB", "unknown key"});
  const auto cfg2 = lp::IniConfig::from_string("[scenery]\nx = 1\n", "f.ini");
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
    const auto cfg = lp::IniConfig::from_string(text, "g.ini");
    expect_input_error([&] { lp::load_placement_settings(cfg); }, {"g.ini:2", key});
  }
}

TEST(PlacementSettings, Overrides_TakePrecedenceAndAreValidated) {
  auto cfg = lp::IniConfig::from_string("[errors]\nsigma_loc_m = 0.1\n");
  cfg.set_override("errors.sigma_loc_m=0.04");
  EXPECT_DOUBLE_EQ(lp::load_placement_settings(cfg).errors.sigma_loc_m, 0.04);
  expect_input_error([&] { cfg.set_override("errors_sigma=1"); }, {"section.key=value"});
  cfg.set_override("gd.step=-2");
  expect_input_error([&] { lp::load_placement_settings(cfg); }, {"--set", "step"});
}

TEST(PlacementSettings, DefaultsRoundTripThroughIni) {
  const lp::PlacementSettings defaults;
  const std::string text = lp::to_ini(defaults);
  const auto cfg = lp::IniConfig::from_string(text);
  cfg.require_known(lp::placement_config_keys());
  EXPECT_EQ(lp::to_ini(lp::load_placement_settings(cfg)), text);
}

TEST(PlacementSettings, ShippedPaperIni_IsTheBuiltInDefaultsWith500Trials) {
  const auto cfg = lp::IniConfig::from_file(std::string(LOSMIMO_SOURCE_DIR) + "/datasets/configs/paper.ini");
  const lp::ExperimentSettings loaded = lp::load_experiment_settings(cfg);
  EXPECT_EQ(lp::to_ini(loaded.placement), lp::to_ini(lp::PlacementSettings{}));
  EXPECT_EQ(loaded.trials, 500);
  lp::ExperimentSettings expected;
  expected.trials = 500;
  EXPECT_EQ(lp::to_ini(loaded), lp::to_ini(expected));
}
