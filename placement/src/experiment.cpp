#include "losmimo/placement/experiment.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <mutex>
#include <sstream>
#include <thread>
#include <unistd.h>

#include "losmimo/placement/experiment_report.h"

namespace losmimo::placement {

namespace {
struct PointTask {
  const SweepPoints* sweep;
  int point;
  const ExperimentExtension* extension;  // nullptr: a built-in sweep
};

std::vector<PointTask> point_tasks(const ExperimentSettings& s, const ExperimentExtensions& extensions) {
  std::vector<PointTask> tasks;
  for (const SweepPoints& sweep : s.sweeps) {
    const ExperimentExtension* extension = nullptr;
    for (const ExperimentExtension& e : extensions) {
      if (e.sweep == sweep.name) extension = &e;
    }
    for (int i = 0; i < static_cast<int>(sweep.values.size()); ++i) tasks.push_back({&sweep, i, extension});
  }
  return tasks;
}

std::string fmt(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}
}  // namespace

ExperimentResults run_experiment(const ExperimentSettings& s, const ExperimentExtensions& extensions, int threads,
                                 const ProgressFn& progress,
                                 const std::function<void(const std::vector<TrialRecord>&)>& row_sink) {
  const std::vector<PointTask> points = point_tasks(s, extensions);
  const std::size_t num_extra = extra_metric_names(s, extensions).size();
  const int trials = s.trials;
  const int total_jobs = static_cast<int>(points.size()) * trials;
  const int num_threads = std::max(1, threads);

  // One slot per (point, trial): results land where their index says, whatever thread ran them.
  std::vector<std::vector<TrialRecord>> slots(total_jobs);
  std::vector<int> remaining(points.size(), trials);
  std::atomic<int> next{0};
  std::mutex mutex;
  std::condition_variable point_done;
  std::exception_ptr failure;

  const auto worker = [&] {
    for (int job = next++; job < total_jobs; job = next++) {
      const PointTask& task = points[job / trials];
      try {
        slots[job] = task.extension ? task.extension->run(s, task.point, job % trials)
                                    : run_trial(s, task.sweep->name, task.point, job % trials);
        for (TrialRecord& r : slots[job]) r.extra.resize(num_extra, std::nan(""));
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
  for (int t = 0; t < num_threads; ++t) pool.emplace_back(worker);

  ExperimentResults results;
  for (std::size_t p = 0; p < points.size(); ++p) {
    {
      std::unique_lock<std::mutex> lock(mutex);
      point_done.wait(lock, [&] { return remaining[p] == 0; });
      if (failure) break;
    }
    std::vector<TrialRecord> point_records;
    for (int t = 0; t < trials; ++t) {
      for (TrialRecord& r : slots[p * trials + t]) point_records.push_back(std::move(r));
    }
    if (row_sink) row_sink(point_records);
    results.records.insert(results.records.end(), point_records.begin(), point_records.end());
    if (progress) {
      progress(static_cast<int>(p) + 1, static_cast<int>(points.size()),
               points[p].sweep->name + " = " + fmt(points[p].sweep->values[points[p].point]));
    }
  }
  if (failure) next = total_jobs;  // stop handing out work
  for (std::thread& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);

  const bool builtin = s.sweep(kSweepSigmaLoc) || s.sweep(kSweepSigmaAct);
  for (const Algorithm a : s.algorithms) {
    if (!builtin || (a != Algorithm::kGd && a != Algorithm::kBf)) continue;
    for (int t = 0; t < s.fig1_trials; ++t) results.traces.push_back({a, t, run_traced(s, a, t)});
  }
  return results;
}

void write_trials_header(std::ostream& out, const std::vector<std::string>& extra) {
  out << "sweep,value,algorithm,trial,seed,iterations,converged,final_icn,dist_to_icn050_m,"
         "dist_to_icn095_m,dist_total_m,probe_dist_m,sinr_nv_db,sinr_zf_db,sinr_mf_db,"
         "sum_rate_nv_bps_hz,sum_rate_zf_bps_hz,mean_sinr_nv_db,mean_sinr_zf_db,mean_sinr_mf_db,"
         "dist_placement_m,start_seed,status";
  for (const std::string& e : extra) out << "," << e;
  out << "\n";
}

void write_trials_rows(std::ostream& out, const std::vector<TrialRecord>& records, std::size_t num_extra) {
  for (const TrialRecord& r : records) {
    out << r.sweep << "," << fmt(r.value) << "," << r.algorithm << "," << r.trial << ","
        << r.seed << "," << r.iterations << "," << (r.converged ? 1 : 0) << "," << fmt(r.final_icn) << ","
        << fmt(r.dist_to_icn050_m) << "," << fmt(r.dist_to_icn095_m) << "," << fmt(r.dist_total_m) << ","
        << fmt(r.probe_dist_m) << "," << fmt(r.sinr_nv_db) << "," << fmt(r.sinr_zf_db) << ","
        << fmt(r.sinr_mf_db) << "," << fmt(r.sum_rate_nv_bps_hz) << "," << fmt(r.sum_rate_zf_bps_hz) << ","
        << fmt(r.mean_sinr_nv_db) << "," << fmt(r.mean_sinr_zf_db) << "," << fmt(r.mean_sinr_mf_db) << ","
        << fmt(r.dist_placement_m) << "," << r.start_seed << "," << r.status;
    for (std::size_t i = 0; i < num_extra; ++i) out << "," << fmt(i < r.extra.size() ? r.extra[i] : std::nan(""));
    out << "\n";
  }
}

void write_positions_header(std::ostream& out) { out << "sweep,value,algorithm,trial,uav,stage,x,y,z\n"; }

void write_positions_rows(std::ostream& out, const std::vector<TrialRecord>& records) {
  char buf[128];
  for (const TrialRecord& r : records) {
    const std::string prefix = r.sweep + "," + fmt(r.value) + "," + r.algorithm + "," +
                               std::to_string(r.trial) + ",";
    for (const auto& [stage, q] : {std::pair<const char*, const Eigen::Matrix3Xd*>{"start", &r.start_m},
                                   {"final", &r.final_m}}) {
      for (Eigen::Index n = 0; n < q->cols(); ++n) {
        // %.17g: positions must round-trip exactly for recomputation.
        std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g", (*q)(0, n), (*q)(1, n), (*q)(2, n));
        out << prefix << n + 1 << "," << stage << "," << buf << "\n";
      }
    }
  }
}

void write_traces_csv(std::ostream& out, const std::vector<TracedRun>& traces) {
  out << "algorithm,trial,iteration,icn,objective,sinr_nv_db,sinr_zf_db,sinr_mf_db,placement_dist_m,probe_dist_m\n";
  for (const TracedRun& t : traces) {
    for (const IterationRecord& r : t.result.trace) {
      out << to_string(t.algorithm) << "," << t.trial << "," << r.iteration << "," << fmt(r.icn) << ","
          << fmt(r.objective) << "," << fmt(r.sinr_nv_db) << "," << fmt(r.sinr_zf_db) << ","
          << fmt(r.sinr_mf_db) << "," << fmt(r.placement_dist_m) << "," << fmt(r.probe_dist_m) << "\n";
    }
  }
}

Estimate estimate(const std::vector<double>& values) {
  Estimate e;
  double sum = 0.0;
  for (const double v : values) {
    if (std::isfinite(v)) {
      sum += v;
      ++e.n;
    }
  }
  if (e.n == 0) return {std::nan(""), std::nan(""), 0};
  e.mean = sum / e.n;
  if (e.n < 2) {
    e.ci95 = std::nan("");
    return e;
  }
  double ss = 0.0;
  for (const double v : values) {
    if (std::isfinite(v)) ss += (v - e.mean) * (v - e.mean);
  }
  const double sd = std::sqrt(ss / (e.n - 1));
  // Student t quantile 0.975: exact for 1 and 2 degrees of freedom, Cornish-Fisher beyond
  // (within 0.3% from 3 degrees of freedom on).
  const int dof = e.n - 1;
  const double z = 1.959963984540054;
  double t = z + (z * z * z + z) / (4.0 * dof) +
             (5 * std::pow(z, 5) + 16 * z * z * z + 3 * z) / (96.0 * dof * dof);
  if (dof == 1) t = 12.706204736;
  if (dof == 2) t = 4.302652730;
  e.ci95 = t * sd / std::sqrt(static_cast<double>(e.n));
  return e;
}

std::vector<std::string> summary_metric_names() {
  return {"final_icn",       "dist_to_icn050_m", "dist_to_icn095_m",   "dist_total_m",
          "probe_dist_m",    "iterations",       "sinr_nv_db",         "sinr_zf_db",
          "sinr_mf_db",      "mean_sinr_nv_db",  "mean_sinr_zf_db",    "mean_sinr_mf_db",
          "sum_rate_nv_bps_hz", "sum_rate_zf_bps_hz"};
}

const Estimate* SummaryRow::metric(const std::string& name) const {
  for (const auto& [n, e] : metrics) {
    if (n == name) return &e;
  }
  return nullptr;
}

std::vector<SummaryRow> summarize(const std::vector<TrialRecord>& records, const std::vector<std::string>& extra) {
  std::vector<SummaryRow> rows;
  std::size_t i = 0;
  while (i < records.size()) {
    // Records of one point are contiguous; group each algorithm's trials.
    std::size_t j = i;
    while (j < records.size() && records[j].sweep == records[i].sweep && records[j].value == records[i].value) ++j;
    std::vector<std::string> order;
    for (std::size_t k = i; k < j; ++k) {
      if (std::find(order.begin(), order.end(), records[k].algorithm) == order.end()) order.push_back(records[k].algorithm);
    }
    std::vector<std::string> names = summary_metric_names();
    names.insert(names.end(), extra.begin(), extra.end());
    for (const std::string& a : order) {
      SummaryRow row{records[i].sweep, records[i].value, a, 0, 0.0, {}};
      std::vector<std::vector<double>> columns(names.size());
      int converged = 0;
      for (std::size_t k = i; k < j; ++k) {
        const TrialRecord& r = records[k];
        if (r.algorithm != a) continue;
        ++row.trials;
        converged += r.converged;
        const double v[] = {r.final_icn,       r.dist_to_icn050_m, r.dist_to_icn095_m,  r.dist_total_m,
                            r.probe_dist_m,    static_cast<double>(r.iterations), r.sinr_nv_db, r.sinr_zf_db,
                            r.sinr_mf_db,      r.mean_sinr_nv_db,  r.mean_sinr_zf_db,   r.mean_sinr_mf_db,
                            r.sum_rate_nv_bps_hz, r.sum_rate_zf_bps_hz};
        constexpr std::size_t kBuiltIn = sizeof v / sizeof v[0];
        for (std::size_t c = 0; c < kBuiltIn; ++c) columns[c].push_back(v[c]);
        for (std::size_t c = 0; c < extra.size(); ++c) {
          columns[kBuiltIn + c].push_back(c < r.extra.size() ? r.extra[c] : std::nan(""));
        }
      }
      row.converged_fraction = row.trials ? static_cast<double>(converged) / row.trials : 0.0;
      for (std::size_t c = 0; c < columns.size(); ++c) row.metrics.emplace_back(names[c], estimate(columns[c]));
      rows.push_back(std::move(row));
    }
    i = j;
  }
  return rows;
}

void write_summary_csv(std::ostream& out, const std::vector<SummaryRow>& rows) {
  out << "sweep,value,algorithm,trials,converged_fraction";
  const std::vector<std::pair<std::string, Estimate>> no_metrics;
  for (const auto& [m, e] : rows.empty() ? no_metrics : rows.front().metrics) {
    out << "," << m << "_mean," << m << "_ci95," << m << "_n";
  }
  out << "\n";
  for (const SummaryRow& r : rows) {
    out << r.sweep << "," << fmt(r.value) << "," << r.algorithm << "," << r.trials << ","
        << fmt(r.converged_fraction);
    for (const auto& [name, e] : r.metrics) out << "," << fmt(e.mean) << "," << fmt(e.ci95) << "," << e.n;
    out << "\n";
  }
}

void write_file_atomically(const std::string& path, const std::string& content) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << content;
    out.flush();
    if (!out) throw std::runtime_error(tmp + ": write failed");
  }
  std::filesystem::rename(tmp, path);
}

namespace {
class Progress {
 public:
  explicit Progress(std::ostream& err) : err_(err), tty_(isatty(STDERR_FILENO) != 0), t0_(clock::now()) {}
  void operator()(int done, int total, const std::string& label) {
    const double elapsed = std::chrono::duration<double>(clock::now() - t0_).count();
    const double eta = done > 0 ? elapsed * (total - done) / done : 0.0;
    if (tty_) {
      constexpr int kWidth = 30;
      const int filled = kWidth * done / total;
      err_ << "\r[" << std::string(filled, '#') << std::string(kWidth - filled, '.') << "] " << done << "/"
           << total << "  " << std::fixed << std::setprecision(0) << elapsed << " s, ETA " << eta << " s   "
           << (done == total ? "\n" : "") << std::flush;
    } else {
      err_ << "point " << done << "/" << total << " done (" << label << "), " << std::fixed << std::setprecision(1)
           << elapsed << " s elapsed, ETA " << eta << " s\n";
    }
  }

 private:
  using clock = std::chrono::steady_clock;
  std::ostream& err_;
  bool tty_;
  clock::time_point t0_;
};
}  // namespace

int run_experiment_app(const ExperimentOptions& options, const ExperimentExtensions& extensions,
                       std::ostream& out, std::ostream& err) {
  ExperimentSettings settings;
  try {
    IniConfig config = options.config_path.empty() ? IniConfig() : IniConfig::from_file(options.config_path);
    for (const std::string& o : options.overrides) config.set_override(o);
    if (options.trials > 0) config.set("experiment", "trials", std::to_string(options.trials));
    if (options.threads >= 0) config.set("experiment", "threads", std::to_string(options.threads));
    settings = load_experiment_settings(config, extensions);
  } catch (const InputError& e) {
    err << "losmimo-experiment: " << e.what() << "\n";
    return 2;
  }
  try {
    namespace fs = std::filesystem;
    const fs::path dir(options.out_dir);
    fs::create_directories(dir);
    const int threads = settings.threads > 0 ? settings.threads
                                             : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    write_file_atomically((dir / "config.ini").string(), to_ini(settings));

    std::ofstream trials_part(dir / "trials.csv.partial", std::ios::trunc);
    std::ofstream positions_part(dir / "positions.csv.partial", std::ios::trunc);
    const std::vector<std::string> extra = extra_metric_names(settings, extensions);
    write_trials_header(trials_part, extra);
    write_positions_header(positions_part);
    const auto sink = [&](const std::vector<TrialRecord>& rows) {
      write_trials_rows(trials_part, rows, extra.size());
      write_positions_rows(positions_part, rows);
      trials_part.flush();
      positions_part.flush();
    };
    Progress progress(err);
    const auto t0 = std::chrono::steady_clock::now();
    const ExperimentResults results = run_experiment(settings, extensions, threads, std::ref(progress), sink);
    const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    trials_part.close();
    positions_part.close();
    if (!trials_part || !positions_part) throw std::runtime_error("writing trials/positions failed");
    fs::rename(dir / "trials.csv.partial", dir / "trials.csv");
    fs::rename(dir / "positions.csv.partial", dir / "positions.csv");

    std::ostringstream traces, summary;
    write_traces_csv(traces, results.traces);
    write_file_atomically((dir / "traces.csv").string(), traces.str());
    const std::vector<SummaryRow> rows = summarize(results.records, extra);
    write_summary_csv(summary, rows);
    write_file_atomically((dir / "summary.csv").string(), summary.str());
    const ReportOutcome report =
        write_figures_and_report(settings, extensions, results, rows, dir.string(), wall_s, threads);
    for (const std::string& w : report.warnings) err << "losmimo-experiment: warning: " << w << "\n";
    out << "losmimo-experiment: " << results.records.size() << " trial rows, " << settings.trials
        << " trials per point, " << threads << " threads, " << std::fixed << std::setprecision(1) << wall_s
        << " s; results in " << dir.string() << "/ (report.md, summary.csv, trials.csv, fig*.png)\n";
    return 0;
  } catch (const std::exception& e) {
    err << "losmimo-experiment: error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace losmimo::placement
