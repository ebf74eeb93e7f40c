#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/experiment/shards.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>

#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/isa.h"

namespace losmimo::experiment {

using common::InputError;

std::pair<int, int> parse_shard(const std::string& text) {
  const auto bad = [&] {
    return common::InputError("--shard '" + text + "': expected i/N with integers 0 <= i < N (e.g. 0/4)");
  };
  const std::size_t slash = text.find('/');
  if (slash == std::string::npos) throw bad();
  const std::string a = text.substr(0, slash);
  const std::string b = text.substr(slash + 1);
  const auto digits = [](const std::string& t) {
    return !t.empty() && t.size() <= 9 && std::all_of(t.begin(), t.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  if (!digits(a) || !digits(b)) throw bad();
  const int i = std::stoi(a);
  const int n = std::stoi(b);
  if (n < 1 || i >= n) throw bad();
  return {i, n};
}

ExperimentResults merge_shard_records(const ExperimentSettings& settings, const std::vector<RecordLines>& shards,
                                      const std::vector<std::string>& origins) {
  const int points = num_sweep_points(settings);
  const int trials = settings.trials;
  // (point, trial) -> shard that ran it, and its records.
  std::vector<int> owner(static_cast<std::size_t>(points) * trials, -1);
  std::vector<std::vector<std::vector<TrialRecord>>> by_job(points, std::vector<std::vector<TrialRecord>>(trials));
  std::vector<std::set<std::string>> algorithms(points);  // per point, over every shard
  for (std::size_t s = 0; s < shards.size(); ++s) {
    const RecordsHeader& h = shards[s].header;
    if (static_cast<int>(shards[s].points.size()) != points) {
      throw common::InputError(origins[s] + ": " + std::to_string(shards[s].points.size()) +
                               " points where the config has " + std::to_string(points));
    }
    for (const auto& [point, records] : shards[s].points) {
      if (point >= points)
        throw common::InputError(origins[s] + ": point " + std::to_string(point) + " beyond the config's " +
                                 std::to_string(points));
      std::set<int> mine;  // the trials of this point that are this shard's jobs
      for (int t = 0; t < trials; ++t) {
        if ((static_cast<long long>(point) * trials + t) % h.shard_count == h.shard_index) mine.insert(t);
      }
      check_point_jobs(origins[s], point, records, mine);
      for (const TrialRecord& r : records) {
        int& o = owner[static_cast<std::size_t>(point) * trials + r.trial];
        if (o != -1 && o != static_cast<int>(s)) {
          throw common::InputError(origins[s] + ": point " + std::to_string(point) + ", trial " +
                                   std::to_string(r.trial) + " is also in " + origins[o]);
        }
        o = static_cast<int>(s);
        algorithms[point].insert(r.algorithm);
        by_job[point][r.trial].push_back(r);
      }
    }
  }
  ExperimentResults results;
  for (int p = 0; p < points; ++p) {
    for (int t = 0; t < trials; ++t) {
      const int o = owner[static_cast<std::size_t>(p) * trials + t];
      if (o == -1) {
        throw common::InputError("merge: no records of point " + std::to_string(p) + ", trial " + std::to_string(t) +
                                 " (an incomplete or missing shard)");
      }
      if (by_job[p][t].size() != algorithms[p].size()) {
        for (const std::string& a : algorithms[p]) {
          bool found = false;
          for (const TrialRecord& r : by_job[p][t]) found = found || r.algorithm == a;
          if (!found) {
            throw common::InputError(origins[o] + ": point " + std::to_string(p) + ", trial " + std::to_string(t) +
                                     ": no record of algorithm " + a + " (a record missing)");
          }
        }
      }
      for (TrialRecord& r : by_job[p][t]) results.records.push_back(std::move(r));
    }
  }
  return results;
}

void add_shard_timing(const common::IniConfig& shard_ini, RunTiming& timing) {
  if (shard_ini.has("shard", "isa")) {
    const std::string isa = shard_ini.get_string("shard", "isa", "");
    try {
      ++timing.shard_isas[placement::to_string(placement::isa_from_string(isa))];
    } catch (const std::invalid_argument&) {
      throw common::InputError(shard_ini.where("shard", "isa") + " = " + isa + ": " +
                               placement::isa_name_requirement());
    }
  }
  if (!shard_ini.has("shard", "wall_s") || !shard_ini.has("shard", "threads")) return;
  const double wall_s = shard_ini.get_double("shard", "wall_s", 0.0);
  if (!std::isfinite(wall_s) || wall_s < 0.0) {
    throw common::InputError(shard_ini.where("shard", "wall_s") + " = " + shard_ini.get_string("shard", "wall_s", "") +
                             ": must be a finite number of seconds >= 0");
  }
  const int threads = static_cast<int>(shard_ini.get_integer("shard", "threads", 1, 1, 1'000'000));
  ++timing.timed_shards;
  timing.slowest_shard_wall_s = std::max(timing.slowest_shard_wall_s, wall_s);
  timing.shards_wall_s += wall_s;
  timing.min_shard_threads = timing.timed_shards == 1 ? threads : std::min(timing.min_shard_threads, threads);
  timing.max_shard_threads = std::max(timing.max_shard_threads, threads);
}

std::string isa_counts(const std::map<std::string, int>& parts_per_isa, const std::string& part) {
  std::string ran;
  for (const auto& [isa, n] : parts_per_isa) {
    ran += (ran.empty() ? "" : ", ") + isa + " in " + std::to_string(n) + " " + part + (n == 1 ? "" : "s");
  }
  return ran;
}

std::string mixed_isa_note(const std::map<std::string, int>& parts_per_isa, const std::string& part) {
  if (parts_per_isa.size() < 2) return "";
  return "the " + part + "s ran the placement kernels on different instruction sets (" +
         isa_counts(parts_per_isa, part) +
         "): the kernels give the same bits on each, but the C library picks its exp/log/sin variants by "
         "CPU, so across machine kinds the merged metrics agree with a one-machine run to 1e-9 relative, "
         "not necessarily to the bit";
}

}  // namespace losmimo::experiment
