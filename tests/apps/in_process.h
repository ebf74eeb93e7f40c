#pragma once
// The experiment and merge apps run in process, as their mains run them: the exit code, and
// what they print on stderr into *err_text when given.
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "losmimo/apps/lib/experiment_app.h"

namespace losmimo::test_support {

inline int run_experiment(const apps::ExperimentOptions& o, std::string* err_text = nullptr) {
  std::ostringstream out, err;
  const int code = apps::run_experiment_app(o, {}, out, err);
  if (err_text) *err_text = err.str();
  return code;
}

inline int run_merge(const std::vector<std::filesystem::path>& shard_dirs, const std::filesystem::path& out_dir,
                     std::string* err_text = nullptr) {
  apps::MergeOptions o;
  for (const std::filesystem::path& d : shard_dirs) o.shard_dirs.push_back(d.string());
  o.out_dir = out_dir.string();
  std::ostringstream out, err;
  const int code = apps::merge_experiment_app(o, {}, out, err);
  if (err_text) *err_text = err.str();
  return code;
}

}  // namespace losmimo::test_support
