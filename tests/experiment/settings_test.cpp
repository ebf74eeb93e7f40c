#include <gtest/gtest.h>

#include <string>

#include "losmimo/common/ini_config.h"
#include "losmimo/experiment/extension.h"
#include "losmimo/placement/settings.h"

namespace lp = losmimo::placement;

TEST(PlacementSettings, ShippedPaperIni_IsTheBuiltInDefaultsWith500Trials) {
  const auto cfg = losmimo::common::IniConfig::from_file(std::string(LOSMIMO_SOURCE_DIR) + "/datasets/configs/paper.ini");
  const losmimo::experiment::ExperimentSettings loaded = losmimo::experiment::load_experiment_settings(cfg);
  EXPECT_EQ(lp::to_ini(loaded.placement), lp::to_ini(lp::PlacementSettings{}));
  EXPECT_EQ(loaded.trials, 500);
  losmimo::experiment::ExperimentSettings expected;
  expected.trials = 500;
  EXPECT_EQ(losmimo::experiment::to_ini(loaded), losmimo::experiment::to_ini(expected));
}
