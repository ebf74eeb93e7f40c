#pragma once
// The settings walker (every_setting_acts_test.cpp): the keys of every key table, the contexts
// they are tried in (every_setting_contexts.cpp), the exemptions, conditions, regimes and values
// (every_setting_tables.cpp) and the judgement of one key in one context
// (every_setting_walker.cpp).
#include <algorithm>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "losmimo/placement/common/format.h"
#include "losmimo/placement/common/key_table.h"

namespace losmimo::every_setting {

// One key of a table: its name, the value the walker sets, and the default's text.
struct TableKey {
  std::string name;  // "section.key"
  std::string section, key, example, default_text;
};

template <typename S>
void collect(const common::KeyTable<S>& table, std::vector<TableKey>& keys) {
  // On the heap, as in KeyTable::markdown (GCC 12's maybe-uninitialised on a large S).
  const auto defaults = std::make_unique<const S>();
  for (const common::Key<S>& k : table.keys()) {
    const std::string name = k.section + "." + k.key;
    // A key shared by two tables (the co-evaluation's [closed_loop] keys) is walked once.
    if (std::any_of(keys.begin(), keys.end(), [&](const TableKey& t) { return t.name == name; })) continue;
    keys.push_back({name, k.section, k.key, k.example, k.write(*defaults, &common::format_double)});
  }
}

// Every key of the six tables.
const std::vector<TableKey>& every_key();

struct Outcome {
  int code = -1;
  std::string result;  // the bytes that carry the run's results
  std::string err;
};

// An app or sweep: its tiny configuration and how to run it with --set assignments.
struct Context {
  std::string name;
  std::vector<std::pair<std::string, std::string>> tiny;  // "section.key", value: the tiny configuration
  std::function<Outcome(const std::vector<std::string>& overrides)> run;
};

// Keys that change only figures, logging, scheduling or the report's text: never compared, and
// accepted (exit 0) by the app that reads them (`app`: "experiment" for every sweep, or a
// context's name).
struct FigureOrLogging {
  std::string app, reason;
};
using Exemptions = std::map<std::string, FigureOrLogging>;
extern const Exemptions kFigureOrLoggingOnly;

using Assignments = std::vector<std::pair<std::string, std::string>>;

// Keys that act only when another key enables them: in `context` ("*": every context) they are
// tried on the tiny configuration with `given` set, against the tiny run with `given` (a context
// that refuses `given` tries the key on the tiny configuration). With `refused_without`, the app
// refuses the key while `given` is not set (unused_keys.h's conditions): the key is tried on the
// tiny configuration too, where it must be refused.
struct Condition {
  std::string context, key;
  Assignments given;
  std::string reason;
  bool refused_without = false;
};

// Regimes in which the planners' stop rules and options act: a key that leaves the tiny run's
// results unchanged is tried in each in turn (on top of the tiny configuration, against the
// regime's own run) until one shows its effect. A key that acts in none is ignored.
struct Regime {
  std::string name;
  Assignments given;
};
extern const std::vector<Regime> kRegimes;
extern const std::vector<Condition> kConditions;

// The value tried instead of the example: [experiment] sweeps adds a sweep to the context's
// (the example replaces it, leaving the context's sweep points unused).
struct Value {
  std::string context, key, value;
};
extern const std::vector<Value> kValues;

enum class Verdict { kActs, kRefused, kAccepted, kIgnored, kFailed };

struct Judgement {
  Verdict verdict;
  std::string detail;
};

// `base` with `key` set to `value` (replacing base's own value of it), as --set assignments.
std::vector<std::string> overrides_of(const Assignments& base, const std::string& key = "",
                                      const std::string& value = "");
// `base` with `more` set (replacing base's values of those keys).
Assignments with(const Assignments& base, const Assignments& more);
// kValues' value, else the example, or the default's text when `base` already sets the example.
std::string value_to_try(const std::string& context, const Assignments& base, const TableKey& k);
// What setting `k` does in context `c` on the configuration `base`, whose run is `before`; keys
// in `exempt` are only checked to be accepted.
Judgement judge(const Context& c, const Assignments& base, const Outcome& before, const TableKey& k,
                const Exemptions& exempt = kFigureOrLoggingOnly);

// A scratch folder for `context`'s runs; on tmpfs when there is one: the apps fsync every
// output (apps/staged_output.h).
std::filesystem::path scratch(const std::string& context);

// Every app and sweep context (every_setting_contexts.cpp), and one by name.
const std::vector<Context>& contexts();
const Context& context_named(const std::string& name);

}  // namespace losmimo::every_setting
