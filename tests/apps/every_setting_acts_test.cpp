// Every key of every key table, in every app and sweep that accepts it, either changes that
// run's results or is refused. For each context (an app, or losmimo-experiment with one sweep),
// a tiny configuration runs once as it is and once per key with `--set section.key=<value>`:
// the table's `example` (kValues' value for [experiment] sweeps; the default's text when the
// tiny configuration already sets the example). The key passes when
//   - the run exits 0 and its result bytes differ (the results: the experiment's *.csv files,
//     eval's --csv output, the records of the rawlog), or
//   - the run exits 2 with a message naming "[section] key" (an unknown key, a value the
//     context cannot use, a key the context does not use: apps/unused_keys.h).
// A key that exits 0 with the same results in every regime it is tried in is silently ignored:
// the test fails, naming it. The configuration a key is tried on is the tiny one, with
// kConditions' keys set for a key that another key enables (the particle count with filter =
// pf), then, while the results stay the same, each of kRegimes (runs that do not converge,
// stall, overshoot) on top of it; each run is compared with the same configuration without the
// key. Exceptions, each with its reason: keys that only change figures, logging or scheduling
// (kFigureOrLoggingOnly: they must still be accepted).
// losmimo-replay takes no key-table settings (it reads the recorded CONFIG; its options are
// flags), so it has no context here: what it replays is the rawlog that the record context checks.
#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "apps/every_setting_walker.h"

namespace losmimo::every_setting {
namespace {

namespace fs = std::filesystem;

class EverySettingActs : public ::testing::TestWithParam<std::string> {};

TEST_P(EverySettingActs, EachKey_ChangesTheResultsOrIsRefused) {
  const Context& c = context_named(GetParam());
  // GIVEN: the tiny configuration runs and has results.
  const Outcome tiny = c.run(overrides_of(c.tiny));
  ASSERT_EQ(tiny.code, 0) << tiny.err;
  ASSERT_FALSE(tiny.result.empty());
  std::vector<std::string> acts, refused;
  for (const TableKey& k : every_key()) {
    // A key that needs another key's value is tried with it; one that the app refuses without
    // that value is tried without it first.
    Assignments base = c.tiny;
    Outcome before = tiny;
    for (const Condition& condition : kConditions) {
      if ((condition.context == "*" || condition.context == c.name) && condition.key == k.name) {
        const Assignments given = with(c.tiny, condition.given);
        const Outcome o = c.run(overrides_of(given));
        // A condition the context refuses (its key unused there) leaves the key to be tried as it is.
        if (o.code == 2) continue;
        ASSERT_EQ(o.code, 0) << c.name << ": " << k.name << "'s condition: " << o.err;
        if (condition.refused_without) {
          const Judgement without = judge(c, c.tiny, tiny, k);
          EXPECT_EQ(without.verdict, Verdict::kRefused)
              << c.name << ": " << k.name << " without " << condition.given.front().first << ": " << without.detail;
        }
        base = given;
        before = o;
      }
    }
    // WHEN: the key is set to another valid value.
    Judgement j = judge(c, base, before, k);
    for (const Regime& regime : kRegimes) {
      if (j.verdict != Verdict::kIgnored) break;
      const Assignments given = with(base, regime.given);
      const Outcome o = c.run(overrides_of(given));
      if (o.code != 0) continue;  // a regime the context refuses
      if (const Judgement in_regime = judge(c, given, o, k); in_regime.verdict != Verdict::kIgnored) j = in_regime;
    }
    // THEN: the results change, or the app refuses it naming the key.
    switch (j.verdict) {
      case Verdict::kActs:
        acts.push_back(k.name);
        break;
      case Verdict::kRefused:
        refused.push_back(k.name + ": " + j.detail);
        break;
      case Verdict::kAccepted:
        break;
      case Verdict::kIgnored:
        ADD_FAILURE() << c.name << ": " << j.detail;
        break;
      case Verdict::kFailed:
        ADD_FAILURE() << c.name << ": " << j.detail;
        break;
    }
  }
  std::string summary =
      c.name + ": " + std::to_string(acts.size()) + " keys act, " + std::to_string(refused.size()) + " refused\n";
  for (const std::string& r : refused) summary += "  refused " + r;
  std::cout << summary;
  fs::remove_all(scratch(c.name));
}

std::vector<std::string> context_names() {
  std::vector<std::string> names;
  for (const Context& c : contexts()) names.push_back(c.name);
  return names;
}

INSTANTIATE_TEST_SUITE_P(Contexts, EverySettingActs, ::testing::ValuesIn(context_names()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

}  // namespace
}  // namespace losmimo::every_setting
