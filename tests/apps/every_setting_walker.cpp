#include "apps/every_setting_walker.h"

#include <unistd.h>

#include <gtest/gtest.h>

#include "losmimo/fusion/coevaluation/coevaluation.h"
#include "losmimo/placement/experiment/channel_sweeps.h"
#include "losmimo/placement/experiment/num_uavs_sweep.h"
#include "losmimo/placement/experiment/settings.h"
#include "losmimo/fusion/closed_loop_settings.h"
#include "losmimo/placement/settings.h"
#include "losmimo/fusion/rawlog/mission/mission.h"

namespace losmimo::every_setting {

namespace fs = std::filesystem;

const std::vector<TableKey>& every_key() {
  static const std::vector<TableKey> keys = [] {
    std::vector<TableKey> all;
    collect(placement::placement_keys(), all);
    collect(experiment::experiment_keys(), all);
    collect(experiment::channel_sweep_keys(), all);
    collect(experiment::num_uavs_sweep_keys(), all);
    collect(coevaluation::coevaluation_keys(), all);
    collect(fusion::closed_loop_keys(), all);
    collect(rawlog::mission_keys(), all);
    return all;
  }();
  return keys;
}

std::vector<std::string> overrides_of(const Assignments& base, const std::string& key, const std::string& value) {
  std::vector<std::string> sets;
  for (const auto& [k, v] : base) {
    if (k != key) sets.push_back(k + "=" + v);
  }
  if (!key.empty()) sets.push_back(key + "=" + value);
  return sets;
}

Assignments with(const Assignments& base, const Assignments& more) {
  Assignments out;
  for (const auto& [k, v] : base) {
    if (std::none_of(more.begin(), more.end(), [&](const auto& m) { return m.first == k; })) out.emplace_back(k, v);
  }
  out.insert(out.end(), more.begin(), more.end());
  return out;
}

std::string value_to_try(const std::string& context, const Assignments& base, const TableKey& k) {
  for (const Value& v : kValues) {
    if (v.context == context && v.key == k.name) return v.value;
  }
  for (const auto& [key, value] : base) {
    if (key == k.name && value == k.example) return k.default_text;
  }
  return k.example;
}

namespace {
bool is_experiment(const std::string& context) { return context != "eval" && context != "record" && context != "fake"; }
}  // namespace

Judgement judge(const Context& c, const Assignments& base, const Outcome& before, const TableKey& k,
                const Exemptions& exempt) {
  const std::string value = value_to_try(c.name, base, k);
  const Outcome o = c.run(overrides_of(base, k.name, value));
  const std::string named = "[" + k.section + "] " + k.key;
  const std::string what = k.name + "=" + value;
  const auto exemption = exempt.find(k.name);
  const bool exempt_here =
      exemption != exempt.end() &&
      (exemption->second.app == c.name || (exemption->second.app == "experiment" && is_experiment(c.name)));
  if (o.code == 2) {
    if (exempt_here) return {Verdict::kFailed, what + ": " + exemption->second.reason + ", but refused: " + o.err};
    if (o.err.find(named) != std::string::npos) return {Verdict::kRefused, o.err};
    return {Verdict::kFailed, what + ": exit 2 without naming " + named + ": " + o.err};
  }
  if (o.code != 0) return {Verdict::kFailed, what + ": exit " + std::to_string(o.code) + ": " + o.err};
  if (exemption != exempt.end()) return {Verdict::kAccepted, ""};
  if (o.result != before.result) return {Verdict::kActs, ""};
  return {Verdict::kIgnored, what + ": accepted, and the results are the same"};
}

fs::path scratch(const std::string& context) {
  const fs::path root = fs::is_directory("/dev/shm") ? fs::path("/dev/shm") : fs::path(::testing::TempDir());
  const fs::path dir = root / ("losmimo-every-setting-" + std::to_string(::getpid())) / context;
  fs::create_directories(dir);
  return dir;
}

}  // namespace losmimo::every_setting
