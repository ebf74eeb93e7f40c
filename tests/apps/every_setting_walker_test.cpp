// The settings walker's own checks (every_setting_walker.h): it flags a key whose setter does
// nothing, in a fake app and in a real one, and lets a config file hold keys an app does not use.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "apps/every_setting_walker.h"
#include "losmimo/apps/lib/eval_app.h"
#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/experiment/settings.h"

namespace losmimo::every_setting {
namespace {

namespace fs = std::filesystem;

// The walker's own checks. A fake app reads a fake table: `gain` scales its result, `noop`'s
// setter does nothing, `refused` is refused naming it, `mute` is refused without naming it.
struct FakeSettings {
  double gain = 1.0;
  double refused = 0.0;
  double mute = 0.0;
};

const common::KeyTable<FakeSettings>& fake_keys() {
  using K = common::Key<FakeSettings>;
  static const common::KeyTable<FakeSettings> table({
      K::real("fake", "gain", &FakeSettings::gain, common::Range::at_least(0.0), "scales the result", "2"),
      K::real(
          "fake", "noop", [](const FakeSettings&) { return 0.0; }, [](FakeSettings&, double) {},
          common::Range::at_least(0.0), "does nothing", "3"),
      K::real("fake", "refused", &FakeSettings::refused, common::Range::at_least(0.0), "refused when set", "1"),
      K::real("fake", "mute", &FakeSettings::mute, common::Range::at_least(0.0), "refused namelessly", "1"),
  });
  return table;
}

Context fake_context() {
  Context c;
  c.name = "fake";
  c.run = [](const std::vector<std::string>& overrides) {
    Outcome r;
    try {
      common::IniConfig config;
      for (const std::string& o : overrides) config.set_override(o);
      config.require_known(fake_keys().known_keys());
      FakeSettings s;
      fake_keys().load(config, s);
      if (s.refused != 0.0) throw common::InputError(config.where("fake", "refused") + ": not used by the fake app");
      if (s.mute != 0.0) throw common::InputError("something is wrong");
      r.code = 0;
      r.result = std::to_string(10.0 * s.gain);
    } catch (const common::InputError& e) {
      r.code = 2;
      r.err = e.what();
    }
    return r;
  };
  return c;
}

Verdict verdict_of(const Context& c, const TableKey& k, const Exemptions& exempt = {}) {
  const Outcome tiny = c.run(overrides_of(c.tiny));
  EXPECT_EQ(tiny.code, 0) << tiny.err;
  return judge(c, c.tiny, tiny, k, exempt).verdict;
}

TEST(EverySettingActsWalker, FakeTable_FlagsTheKeyWhoseSetterDoesNothing) {
  // GIVEN: the fake app and its table's keys as the walker collects them.
  std::vector<TableKey> keys;
  collect(fake_keys(), keys);
  ASSERT_EQ(keys.size(), 4u);
  const Context c = fake_context();
  // THEN: each key gets the verdict its setter and the app earn.
  EXPECT_EQ(verdict_of(c, keys[0]), Verdict::kActs);
  EXPECT_EQ(verdict_of(c, keys[1]), Verdict::kIgnored);
  EXPECT_EQ(verdict_of(c, keys[2]), Verdict::kRefused);
  EXPECT_EQ(verdict_of(c, keys[3]), Verdict::kFailed);  // exit 2, but the message names no key
  // An exempt key is only checked to be accepted; a refused exempt key fails.
  EXPECT_EQ(verdict_of(c, keys[1], {{"fake.noop", {"fake", "no results"}}}), Verdict::kAccepted);
  EXPECT_EQ(verdict_of(c, keys[2], {{"fake.refused", {"fake", "no results"}}}), Verdict::kFailed);
}

TEST(EverySettingActsWalker, RealApp_FlagsAKeyThatLeavesTheResultsAlone) {
  // GIVEN: losmimo-experiment's sigma_loc_m run and [experiment] threads, whose results do not
  // depend on it.
  const Context& c = context_named(experiment::kSweepSigmaLoc);
  const auto threads = std::find_if(every_key().begin(), every_key().end(),
                                    [](const TableKey& k) { return k.name == "experiment.threads"; });
  ASSERT_NE(threads, every_key().end());
  // THEN: without its exemption the walker calls it ignored, with it accepted.
  EXPECT_EQ(verdict_of(c, *threads), Verdict::kIgnored);
  EXPECT_EQ(verdict_of(c, *threads, kFigureOrLoggingOnly), Verdict::kAccepted);
  fs::remove_all(scratch(c.name));
}

TEST(EverySettingActsWalker, ConfigFile_MayHoldKeysTheAppDoesNotUse) {
  // GIVEN: a config file for every app (an experiment's keys and [gd]) and losmimo-eval.
  const fs::path ini = scratch("config_file") / "shared.ini";
  std::ofstream(ini) << "[experiment]\ntrials = 3\n[gd]\nstep = 0.1\n";
  apps::EvalOptions o;
  o.positions_path = std::string(LOSMIMO_SOURCE_DIR) + "/datasets/examples/random_start_16.csv";
  o.config_path = ini.string();
  std::ostringstream out, err;
  // THEN: the file is accepted; the same key given with --set is refused, naming it and why.
  EXPECT_EQ(apps::run_eval_app(o, out, err), 0) << err.str();
  o.overrides = {"gd.step=0.2"};
  std::ostringstream err2;
  EXPECT_EQ(apps::run_eval_app(o, out, err2), 2);
  EXPECT_NE(err2.str().find("--set: [gd] step: not used by losmimo-eval: it evaluates given positions"),
            std::string::npos)
      << err2.str();
  fs::remove_all(scratch("config_file"));
}

}  // namespace
}  // namespace losmimo::every_setting
