#include "losmimo/placement/experiment/engine.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "losmimo/placement/common/format.h"
#include "losmimo/placement/experiment/capacity_claims.h"
#include "losmimo/placement/experiment/metrics.h"

namespace losmimo::experiment {

namespace {
struct PointTask {
  const SweepPoints* sweep;
  int point;
  const ExperimentExtension* extension;     // nullptr: a built-in sweep
  const ExperimentExtension::TrialFn* run;  // the extension's trial function, bound once per run
};

// The extensions' trial functions, one per enabled extension sweep, bound to `s` once
// (ExperimentExtension::bind, else run).
std::vector<ExperimentExtension::TrialFn> bind_extensions(const ExperimentSettings& s,
                                                          const ExperimentExtensions& extensions) {
  std::vector<ExperimentExtension::TrialFn> bound;
  for (const ExperimentExtension& e : extensions) {
    if (!s.sweep(e.sweep)) {
      bound.emplace_back();
    } else if (e.bind) {
      bound.push_back(e.bind(s));
    } else {
      bound.emplace_back([&s, &e](int point, int trial) { return e.run(s, point, trial); });
    }
  }
  return bound;
}

std::vector<PointTask> point_tasks(const ExperimentSettings& s, const ExperimentExtensions& extensions,
                                   const std::vector<ExperimentExtension::TrialFn>& bound) {
  std::vector<PointTask> tasks;
  for (const SweepPoints& sweep : s.sweeps) {
    const ExperimentExtension* extension = nullptr;
    const ExperimentExtension::TrialFn* run = nullptr;
    for (std::size_t k = 0; k < extensions.size(); ++k) {
      if (extensions[k].sweep == sweep.name) {
        extension = &extensions[k];
        run = &bound[k];
      }
    }
    for (int i = 0; i < static_cast<int>(sweep.values.size()); ++i) tasks.push_back({&sweep, i, extension, run});
  }
  return tasks;
}

// A record's extension metrics (extension_columns: every one set) at their columns among all
// enabled sweeps' extension metrics (NaN where its extension has none): two extensions may name
// different columns.
std::vector<double> place_extension_columns(const TrialRecord& r, const ExperimentExtension* extension,
                                            const std::vector<std::string>& names) {
  std::vector<double> placed(names.size(), std::nan(""));
  if (!extension) return placed;
  const std::vector<double> own = extension_columns(r, extension->metrics);
  for (std::size_t i = 0; i < own.size(); ++i) {
    const auto it = std::find(names.begin(), names.end(), extension->metrics[i].name);
    if (it != names.end()) placed[static_cast<std::size_t>(it - names.begin())] = own[i];
  }
  return placed;
}

}  // namespace

int num_sweep_points(const ExperimentSettings& s) {
  int n = 0;
  for (const SweepPoints& sweep : s.sweeps) n += static_cast<int>(sweep.values.size());
  return n;
}

ExperimentResults run_experiment(const ExperimentSettings& s, const ExperimentExtensions& extensions, int threads,
                                 const ProgressFn& progress,
                                 const std::function<void(const std::vector<TrialRecord>&)>& row_sink) {
  PointSink sink;
  if (row_sink) sink = [&](int /*point*/, const std::vector<TrialRecord>& rows) { row_sink(rows); };
  return run_experiment(s, extensions, threads, ExperimentSlice{}, progress, sink);
}

namespace {
// The slice's jobs (point * trials + trial), counted per point in `remaining`: points already
// finished are skipped, and shard i of N takes the jobs j with j % N == i.
std::vector<int> slice_jobs(std::size_t num_points, int trials, const ExperimentSlice& slice,
                            std::vector<int>& remaining) {
  std::vector<int> jobs;
  for (std::size_t p = 0; p < num_points; ++p) {
    if (slice.finished_points.count(static_cast<int>(p))) continue;
    for (int t = 0; t < trials; ++t) {
      const long long j = static_cast<long long>(p) * trials + t;
      if (j % slice.shard_count != slice.shard_index) continue;
      jobs.push_back(static_cast<int>(j));
      ++remaining[p];
    }
  }
  return jobs;
}

// A record's extra columns in the metric table's order: the extension's, then the milestone and
// capacity-claim columns where the settings ask for them.
void fill_extra_columns(const ExperimentSettings& s, const ExperimentExtension* extension,
                        const std::vector<std::string>& extension_names, TrialRecord& r) {
  r.extra = place_extension_columns(r, extension, extension_names);
  r.extension = {};
  if (s.milestone_columns) {  // milestone_metrics()' order
    const auto iteration = [](int i) { return i >= 0 ? static_cast<double>(i) : std::nan(""); };
    r.extra.push_back(iteration(r.icn050_iteration));
    r.extra.push_back(iteration(r.icn095_iteration));
  }
  if (s.capacity_columns) {
    for (const double v : capacity_claim_columns(r)) r.extra.push_back(v);
    r.capacity_claims = {};
  }
}
}  // namespace

ExperimentResults run_experiment(const ExperimentSettings& s, const ExperimentExtensions& extensions, int threads,
                                 const ExperimentSlice& slice, const ProgressFn& progress, const PointSink& sink) {
  if (slice.shard_count < 1 || slice.shard_index < 0 || slice.shard_index >= slice.shard_count) {
    throw std::invalid_argument("run_experiment: shard " + std::to_string(slice.shard_index) + "/" +
                                std::to_string(slice.shard_count) + " is not in 0..N-1");
  }
  const std::vector<ExperimentExtension::TrialFn> bound = bind_extensions(s, extensions);
  const std::vector<PointTask> points = point_tasks(s, extensions, bound);
  const std::vector<std::string> extension_names = extension_metric_names(s, extensions);
  const int trials = s.trials;
  const int num_threads = std::max(1, threads);

  // This slice's jobs; one slot per (point, trial): results land where their index says,
  // whatever thread ran them.
  std::vector<int> remaining(points.size(), 0);
  const std::vector<int> jobs = slice_jobs(points.size(), trials, slice, remaining);
  const int total_jobs = static_cast<int>(jobs.size());
  std::vector<std::vector<TrialRecord>> slots(points.size() * static_cast<std::size_t>(trials));
  std::atomic<int> next{0};
  std::mutex mutex;
  std::condition_variable point_done;
  std::exception_ptr failure;
  SeedFreeRuns seed_free;  // the runs the built-in sweeps' points share

  const auto worker = [&] {
    for (int i = next++; i < total_jobs; i = next++) {
      const int job = jobs[i];
      const PointTask& task = points[job / trials];
      try {
        slots[job] = task.extension ? (*task.run)(task.point, job % trials)
                                    : run_trial(s, task.sweep->name, task.point, job % trials, &seed_free);
        for (TrialRecord& r : slots[job]) fill_extra_columns(s, task.extension, extension_names, r);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(mutex);
        if (!failure) failure = std::current_exception();
      }
      const std::lock_guard<std::mutex> lock(mutex);
      --remaining[job / trials];
      point_done.notify_all();
    }
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < std::min(num_threads, std::max(1, total_jobs)); ++t) pool.emplace_back(worker);

  ExperimentResults results;
  for (std::size_t p = 0; p < points.size(); ++p) {
    const auto finished = slice.finished_points.find(static_cast<int>(p));
    if (finished != slice.finished_points.end()) {
      results.records.insert(results.records.end(), finished->second.begin(), finished->second.end());
    } else {
      {
        std::unique_lock<std::mutex> lock(mutex);
        point_done.wait(lock, [&] { return remaining[p] == 0 || failure; });
        if (failure) break;
      }
      std::vector<TrialRecord> point_records;
      for (int t = 0; t < trials; ++t) {
        for (TrialRecord& r : slots[p * trials + t]) point_records.push_back(std::move(r));
      }
      if (sink) sink(static_cast<int>(p), point_records);
      results.records.insert(results.records.end(), point_records.begin(), point_records.end());
    }
    if (progress) {
      progress(static_cast<int>(p) + 1, static_cast<int>(points.size()),
               points[p].sweep->name + " = " +
                   common::format_g(points[p].sweep->values[points[p].point], common::kCsvDigits));
    }
  }
  if (failure) next = total_jobs;  // stop handing out work
  for (std::thread& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);

  if (slice.traces) results.traces = traced_runs(s);
  return results;
}

namespace {
bool has_builtin_sweep(const ExperimentSettings& s) { return s.sweep(kSweepSigmaLoc) || s.sweep(kSweepSigmaAct); }
bool is_traced(const Algorithm& a) { return a == Algorithm::kGd || a == Algorithm::kBf; }
}  // namespace

bool records_paths(const ExperimentSettings& s) {
  return s.paths && s.fig1_trials > 0 && has_builtin_sweep(s) &&
         std::any_of(s.algorithms.begin(), s.algorithms.end(), is_traced);
}

std::vector<TracedRun> traced_runs(const ExperimentSettings& s) {
  std::vector<TracedRun> traces;
  const bool builtin = has_builtin_sweep(s);
  for (const Algorithm& a : s.algorithms) {
    if (!builtin || !is_traced(a)) continue;
    for (int t = 0; t < s.fig1_trials; ++t) traces.push_back({a, t, run_traced(s, a, t, s.paths && t == 0)});
  }
  // The path figure's runs under the largest actuation error, from trial 0's start.
  const SweepPoints* act = s.sweep(kSweepSigmaAct);
  if (s.paths && s.fig1_trials > 0 && act) {
    const double sigma = *std::max_element(act->values.begin(), act->values.end());
    for (const Algorithm& a : s.algorithms) {
      if (sigma > 0.0 && is_traced(a)) traces.push_back({a, 0, run_path(s, a, 0, sigma), sigma});
    }
  }
  return traces;
}

}  // namespace losmimo::experiment
