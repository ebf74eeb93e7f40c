#include <gtest/gtest.h>

#include <string>

#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/experiment/extension.h"
#include "losmimo/placement/settings.h"

namespace lp = losmimo::placement;

TEST(PlacementSettings, ShippedPaperIni_IsTheBuiltInDefaultsWith500Trials) {
  const auto cfg =
      losmimo::common::IniConfig::from_file(std::string(LOSMIMO_SOURCE_DIR) + "/datasets/configs/paper.ini");
  const losmimo::experiment::ExperimentSettings loaded = losmimo::experiment::load_experiment_settings(cfg);
  EXPECT_EQ(lp::to_ini(loaded.placement), lp::to_ini(lp::PlacementSettings{}));
  EXPECT_EQ(loaded.trials, 500);
  losmimo::experiment::ExperimentSettings expected;
  expected.trials = 500;
  EXPECT_EQ(losmimo::experiment::to_ini(loaded), losmimo::experiment::to_ini(expected));
}

TEST(PlacementSettings, ShippedPaperFaithfulIni_IsPaperIniWithTheReadingsChoicesOnly) {
  // GIVEN: the shipped best reading of the paper (docs/fidelity.md).
  const auto cfg =
      losmimo::common::IniConfig::from_file(std::string(LOSMIMO_SOURCE_DIR) + "/datasets/configs/paper-faithful.ini");
  const losmimo::experiment::ExperimentSettings loaded = losmimo::experiment::load_experiment_settings(cfg);
  // THEN: it is paper.ini (the defaults, 500 trials) with exactly the reading's choices set.
  losmimo::experiment::ExperimentSettings expected;
  expected.trials = 500;
  expected.placement.gd.step = 0.8;  // the paper's 0.05 on f itself
  expected.placement.run.target_icn = 1.0;
  expected.placement.run.max_iterations = 2000;
  expected.placement.ura.spacing_multiple = 3;
  expected.placement.ura.depth = lp::UraDepth::kOwn;
  expected.milestone_columns = true;
  expected.reading_trials = 20;
  expected.readings = loaded.readings;  // report.md's Why lines; any set is allowed
  EXPECT_FALSE(loaded.readings.empty());
  EXPECT_EQ(lp::to_ini(loaded.placement), lp::to_ini(expected.placement));
  EXPECT_EQ(losmimo::experiment::to_ini(loaded), losmimo::experiment::to_ini(expected));
}
