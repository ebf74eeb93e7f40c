// Regressions for bad inputs found by fuzzing and review (docs/reliability.md).
// Each input here must give an InputError naming the file, line, key or field and the value:
// never NaN or garbage results, nor an error that does not name the key.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "losmimo/apps/lib/eval_app.h"
#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/experiment/extension.h"
#include "losmimo/placement/positions_csv.h"
#include "losmimo/placement/settings.h"

namespace lp = losmimo::placement;

namespace {
// Loads `ini` and expects an InputError whose message contains every fragment.
void expect_config_error(const std::string& ini, const std::vector<std::string>& fragments) {
  try {
    lp::load_placement_settings(losmimo::common::IniConfig::from_string(ini, "bad.ini"));
    ADD_FAILURE() << "accepted: " << ini;
  } catch (const losmimo::common::InputError& e) {
    for (const auto& f : fragments) EXPECT_NE(std::string(e.what()).find(f), std::string::npos) << e.what();
  }
}

std::string temp_file(const std::string& name, const std::string& content) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << content;
  return path;
}
}  // namespace

// GIVEN finite values whose derived quantities overflow (found by fuzz_ini_config: a 1e300 m
// cube centre gave an infinite range and a NaN channel; snr_db = 1e5 a zero noise variance
// reported as "config: noise variance = 0", without the key).
// THEN the key, its line and value are named.
TEST(ScenarioLimits, OverflowingFiniteValues_AreRejectedNamingTheKey) {
  expect_config_error("[scenario]\ncube_center_x_m = 1e300\n", {"bad.ini:2", "cube_center_x_m", "1e300"});
  expect_config_error("[scenario]\ncube_center_y_m = -2e7\n", {"bad.ini:2", "cube_center_y_m"});
  expect_config_error("[scenario]\ncube_side_m = 1e300\n", {"bad.ini:2", "cube_side_m"});
  expect_config_error("[scenario]\nbs_spacing_m = 1e300\n", {"bad.ini:2", "bs_spacing_m"});
  expect_config_error("[scenario]\n\ncarrier_hz = 1e-300\n", {"bad.ini:3", "carrier_hz"});
  expect_config_error("[scenario]\ncarrier_hz = 1e300\n", {"bad.ini:2", "carrier_hz"});
  expect_config_error("[scenario]\nsnr_db = 1e5\n", {"bad.ini:2", "snr_db", "1e5"});
  expect_config_error("[scenario]\nsnr_db = -1e5\n", {"bad.ini:2", "snr_db"});
}

TEST(ScenarioLimits, ValuesAtTheLimits_AreAccepted) {
  const auto s = lp::load_placement_settings(losmimo::common::IniConfig::from_string(
      "[scenario]\ncube_center_x_m = 1e7\ncube_side_m = 1e7\nbs_spacing_m = 1e3\ncarrier_hz = 1e15\n"
      "snr_db = -300\n"));
  EXPECT_TRUE(std::isfinite(s.scenario.range_m()));
  EXPECT_GT(s.scenario.noise_variance(), 0.0);
  EXPECT_TRUE(std::isfinite(s.scenario.noise_variance()));
}

// GIVEN a positions CSV with a finite coordinate so large that distances overflow (found by
// fuzz_positions_csv: `1e308,0,0` made losmimo-eval print objective -nan with exit code 0).
TEST(PositionsCsv, HugeCoordinate_IsRejectedNamingLineAndField) {
  std::istringstream in("x,y,z\n1000,0,0\n1000,1e200,0\n");
  try {
    lp::parse_positions_csv(in, "p.csv");
    ADD_FAILURE() << "accepted";
  } catch (const losmimo::common::InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("p.csv:3: field y"), std::string::npos) << msg;
    EXPECT_NE(msg.find("1e200"), std::string::npos) << msg;
  }
  std::istringstream ok("1e9,-1e9,0\n");
  EXPECT_EQ(lp::parse_positions_csv(ok, "ok.csv").cols(), 1);
}

TEST(LosmimoEval, HugeCoordinate_ExitsTwoWithoutNan) {
  losmimo::apps::EvalOptions o;
  o.positions_path = temp_file("huge.csv", "1e308,0,0\n");
  o.csv = true;
  std::ostringstream out, err;
  EXPECT_EQ(losmimo::apps::run_eval_app(o, out, err), 2);
  EXPECT_EQ(out.str().find("nan"), std::string::npos) << out.str();
  EXPECT_NE(err.str().find("huge.csv:1: field x"), std::string::npos) << err.str();
}

TEST(LosmimoEval, ExperimentsPositionsTable_OneSwarmBySelect_IsThatSwarmAsAPlainFile) {
  // GIVEN: one swarm inside a table of two, and the same swarm as a plain x,y,z file.
  const std::string table = temp_file("positions_table.csv",
                                      "sweep,value,algorithm,trial,uav,stage,x,y,z\n"
                                      "s,0,gd,0,1,final,1000,0,0\ns,0,gd,0,2,final,1000,5,0\n"
                                      "s,0,gd,1,1,final,1000,0,1\ns,0,gd,1,2,final,1000,0,6\n");
  losmimo::apps::EvalOptions a;
  a.positions_path = table;
  a.selection = {"trial=1"};
  a.csv = true;
  losmimo::apps::EvalOptions b;
  b.positions_path = temp_file("positions_plain.csv", "1000,0,1\n1000,0,6\n");
  b.csv = true;
  std::ostringstream out_a, err_a, out_b, err_b;
  // THEN: the same metrics.
  ASSERT_EQ(losmimo::apps::run_eval_app(a, out_a, err_a), 0) << err_a.str();
  ASSERT_EQ(losmimo::apps::run_eval_app(b, out_b, err_b), 0) << err_b.str();
  EXPECT_EQ(out_a.str(), out_b.str());
  // AND: without the selection, or with a malformed one, exit 2 with what to choose.
  a.selection.clear();
  std::ostringstream out_c, err_c;
  EXPECT_EQ(losmimo::apps::run_eval_app(a, out_c, err_c), 2);
  EXPECT_NE(err_c.str().find("trial: 0, 1"), std::string::npos) << err_c.str();
  a.selection = {"trial"};
  std::ostringstream out_d, err_d;
  EXPECT_EQ(losmimo::apps::run_eval_app(a, out_d, err_d), 2);
  EXPECT_NE(err_d.str().find("--select trial: expected column=value"), std::string::npos) << err_d.str();
}

// GIVEN a directory as --config (found by review: it opened fine, read as an empty config and
// the app ran with the defaults, exit code 0). An empty file stays a valid empty config.
TEST(IniConfig, DirectoryAsConfig_IsAReadError) {
  try {
    losmimo::common::IniConfig::from_file(::testing::TempDir());
    ADD_FAILURE() << "a directory was accepted as a config file";
  } catch (const losmimo::common::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot read config file"), std::string::npos) << e.what();
  }
  const losmimo::common::IniConfig empty = losmimo::common::IniConfig::from_file(temp_file("empty.ini", ""));
  EXPECT_FALSE(empty.has("scenario", "snr_db"));

  losmimo::apps::EvalOptions o;
  o.positions_path = std::string(LOSMIMO_SOURCE_DIR) + "/datasets/examples/ura_optimal_16.csv";
  o.config_path = ::testing::TempDir();
  std::ostringstream out, err;
  EXPECT_EQ(losmimo::apps::run_eval_app(o, out, err), 2);
  EXPECT_NE(err.str().find("cannot read config file"), std::string::npos) << err.str();
}

// GIVEN an error sigma so large that drawn positions overflow (found by review:
// `--set experiment.sigma_loc_values_m=1e300` ran and stopped mid-sweep with exit code 1,
// "assignment: non-finite cost"; `errors.sigma_act_m = 1e300` ran on NaN channels).
TEST(ErrorSigmas, BeyondTheLimit_AreRejectedBeforeAnyWork) {
  expect_config_error("[errors]\nsigma_act_m = 1e300\n", {"bad.ini:2", "sigma_act_m", "1e300"});
  expect_config_error("[errors]\nsigma_loc_m = 1001\n", {"bad.ini:2", "sigma_loc_m"});
  try {
    losmimo::experiment::load_experiment_settings(
        losmimo::common::IniConfig::from_string("[experiment]\nsigma_loc_values_m = 0, 1e300\n", "exp.ini"));
    ADD_FAILURE() << "accepted";
  } catch (const losmimo::common::InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("exp.ini:2"), std::string::npos) << msg;
    EXPECT_NE(msg.find("1e300"), std::string::npos) << msg;
  }
  EXPECT_NO_THROW(losmimo::experiment::load_experiment_settings(losmimo::common::IniConfig::from_string(
      "[experiment]\nsigma_act_values_m = 0, 1e3\n[errors]\nsigma_loc_m = 1e3\n")));
}
