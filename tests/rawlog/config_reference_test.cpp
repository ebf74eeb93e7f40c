// docs/configuration.md is the key tables written out: this test fails when a key, its default,
// its values or its meaning change without the page. To rewrite the page:
//   LOSMIMO_WRITE_CONFIG_REFERENCE=1 build/tests/rawlog/rawlog_tests --gtest_filter='ConfigReference.*'
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include "losmimo/apps/lib/unused_keys.h"
#include "losmimo/fusion/coevaluation/coevaluation.h"
#include "losmimo/placement/experiment/channel_sweeps.h"
#include "losmimo/placement/experiment/num_uavs_sweep.h"
#include "losmimo/placement/experiment/settings.h"
#include "losmimo/fusion/closed_loop_settings.h"
#include "losmimo/placement/settings.h"
#include "losmimo/fusion/rawlog/mission/mission.h"
#include "support/files.h"

namespace losmimo {
namespace {

std::string reference() {
  return "# Configuration reference\n\n"
         "Every INI key, generated from the key tables in the code (a test keeps this page equal to "
         "them). Defaults are the paper's setup. A key can be given in a `--config` file or as "
         "`--set section.key=value`; a bad value stops the app before any work, naming the file, line, "
         "key and value.\n\n"
         "## Scenario and placement (every app)\n\n" +
         placement::placement_keys().markdown() + "\n## Experiment (`losmimo-experiment`)\n\n" +
         experiment::experiment_keys().markdown() +
         "\n## Co-evaluation sweeps (`losmimo-experiment`, `[experiment] sweeps = beacon_noise_m, "
         "beacon_outage`)\n\n" +
         coevaluation::coevaluation_keys().markdown({"coevaluation"}) +
         "\nThe co-evaluation also reads the closed loop's sensor keys listed below (`[closed_loop]`).\n"
         "\n## Channel sweeps (`losmimo-experiment`, `[experiment] sweeps = rician_k_db, csi_snr_db, "
         "bs_antennas`)\n\n" +
         experiment::channel_sweep_keys().markdown() +
         "\n## Swarm-size sweep (`losmimo-experiment`, `[experiment] sweeps = num_uavs`)\n\n" +
         experiment::num_uavs_sweep_keys().markdown() +
         "\n## Closed loop (`losmimo-record`, and the co-evaluation's shared settings)\n\n" +
         fusion::closed_loop_keys().markdown() + "\n## Mission (`losmimo-record`)\n\n" +
         rawlog::mission_keys().markdown() +
         "\n## Keys an app or sweep does not use\n\n"
         "A key given with `--set` that the run does not use is refused (exit 2), naming the key and "
         "why: for `losmimo-experiment` when none of the run's sweeps uses it. A user (an app or a "
         "sweep) leaves a key unused by its name or by a condition of the run (e.g. no gd in "
         "`[experiment] algorithms`) in the \"not used by\" column. A `--config` file may "
         "hold them (one file serves every app, e.g. `datasets/configs/paper.ini`). Sections an app "
         "does not know at all (e.g. `[mission]` in `losmimo-experiment`) are refused as unknown "
         "wherever they are given.\n\n" +
         apps::unused_keys_markdown();
}

TEST(ConfigReference, DocsPage_IsTheKeyTables) {
  const std::string path = std::string(LOSMIMO_SOURCE_DIR) + "/docs/configuration.md";
  if (std::getenv("LOSMIMO_WRITE_CONFIG_REFERENCE")) {
    std::ofstream(path, std::ios::binary) << reference();
  }
  EXPECT_EQ(test_support::read_file(path), reference())
      << "docs/configuration.md is out of date: rewrite it with LOSMIMO_WRITE_CONFIG_REFERENCE=1 (see the test's "
         "header)";
}

}  // namespace
}  // namespace losmimo
