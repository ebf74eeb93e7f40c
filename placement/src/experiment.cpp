#include "losmimo/placement/experiment.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <mutex>
#include <set>
#include <tuple>
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

std::vector<TracedRun> traced_runs(const ExperimentSettings& s) {
  std::vector<TracedRun> traces;
  const bool builtin = s.sweep(kSweepSigmaLoc) || s.sweep(kSweepSigmaAct);
  for (const Algorithm a : s.algorithms) {
    if (!builtin || (a != Algorithm::kGd && a != Algorithm::kBf)) continue;
    for (int t = 0; t < s.fig1_trials; ++t) traces.push_back({a, t, run_traced(s, a, t)});
  }
  return traces;
}

std::string fmt(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
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

ExperimentResults run_experiment(const ExperimentSettings& s, const ExperimentExtensions& extensions, int threads,
                                 const ExperimentSlice& slice, const ProgressFn& progress,
                                 const PointSink& sink) {
  if (slice.shard_count < 1 || slice.shard_index < 0 || slice.shard_index >= slice.shard_count) {
    throw std::invalid_argument("run_experiment: shard " + std::to_string(slice.shard_index) + "/" +
                                std::to_string(slice.shard_count) + " is not in 0..N-1");
  }
  const std::vector<PointTask> points = point_tasks(s, extensions);
  const std::size_t num_extra = extra_metric_names(s, extensions).size();
  const int trials = s.trials;
  const int num_threads = std::max(1, threads);

  // This slice's jobs; one slot per (point, trial): results land where their index says,
  // whatever thread ran them.
  std::vector<int> jobs;
  std::vector<int> remaining(points.size(), 0);
  for (std::size_t p = 0; p < points.size(); ++p) {
    if (slice.finished_points.count(static_cast<int>(p))) continue;
    for (int t = 0; t < trials; ++t) {
      const long long j = static_cast<long long>(p) * trials + t;
      if (j % slice.shard_count != slice.shard_index) continue;
      jobs.push_back(static_cast<int>(j));
      ++remaining[p];
    }
  }
  const int total_jobs = static_cast<int>(jobs.size());
  std::vector<std::vector<TrialRecord>> slots(points.size() * static_cast<std::size_t>(trials));
  std::atomic<int> next{0};
  std::mutex mutex;
  std::condition_variable point_done;
  std::exception_ptr failure;

  const auto worker = [&] {
    for (int i = next++; i < total_jobs; i = next++) {
      const int job = jobs[i];
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
               points[p].sweep->name + " = " + fmt(points[p].sweep->values[points[p].point]));
    }
  }
  if (failure) next = total_jobs;  // stop handing out work
  for (std::thread& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);

  if (slice.traces) results.traces = traced_runs(s);
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


std::pair<int, int> parse_shard(const std::string& text) {
  const auto bad = [&] {
    return InputError("--shard '" + text + "': expected i/N with integers 0 <= i < N (e.g. 0/4)");
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

namespace {
// Full precision (round trip): the checkpoint and shard records.
std::string exact(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

void write_matrix(std::ostream& out, const Eigen::Matrix3Xd& q) {
  out << "," << q.cols();
  for (Eigen::Index n = 0; n < q.cols(); ++n) {
    for (int i = 0; i < 3; ++i) out << "," << exact(q(i, n));
  }
}

constexpr const char* kRecordsHeader = "# losmimo-experiment records v1";
}  // namespace

void write_record_lines(std::ostream& out, int point, const std::vector<TrialRecord>& records) {
  for (const TrialRecord& r : records) {
    out << "r," << point << "," << r.sweep << "," << exact(r.value) << "," << r.algorithm << "," << r.trial << ","
        << r.seed << "," << r.start_seed << "," << r.iterations << "," << (r.converged ? 1 : 0) << "," << r.status;
    for (const double v : {r.final_icn, r.dist_to_icn050_m, r.dist_to_icn095_m, r.dist_total_m, r.dist_placement_m,
                           r.probe_dist_m, r.sinr_nv_db, r.sinr_zf_db, r.sinr_mf_db, r.mean_sinr_nv_db,
                           r.mean_sinr_zf_db, r.mean_sinr_mf_db, r.sum_rate_nv_bps_hz, r.sum_rate_zf_bps_hz}) {
      out << "," << exact(v);
    }
    out << "," << r.extra.size();
    for (const double v : r.extra) out << "," << exact(v);
    write_matrix(out, r.start_m);
    write_matrix(out, r.final_m);
    out << "\n";
  }
}

void write_point_done(std::ostream& out, int point) { out << "d," << point << "\n"; }

RecordLines parse_record_lines(std::istream& in, const std::string& origin, bool allow_truncated_tail) {
  std::ostringstream buffer;
  buffer << in.rdbuf();
  std::string text = buffer.str();
  if (!text.empty() && text.back() != '\n') {
    if (!allow_truncated_tail) throw InputError(origin + ": truncated last line");
    text.erase(text.rfind('\n') == std::string::npos ? 0 : text.rfind('\n') + 1);
  }
  RecordLines result;
  std::istringstream lines(text);
  std::string line;
  int line_no = 0;
  while (std::getline(lines, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#') continue;
    const std::string where = origin + ":" + std::to_string(line_no);
    std::vector<std::string> f;
    {
      std::istringstream ls(line);
      std::string field;
      while (std::getline(ls, field, ',')) f.push_back(field);
    }
    std::size_t k = 0;
    const auto next = [&]() -> const std::string& {
      if (k >= f.size()) throw InputError(where + ": too few fields");
      return f[k++];
    };
    const auto integer = [&](long long lo, long long hi) { return parse_integer(next(), where, lo, hi); };
    const auto real = [&]() {
      const std::string& t = next();
      char* end = nullptr;
      const double v = std::strtod(t.c_str(), &end);
      if (t.empty() || end != t.c_str() + t.size()) throw InputError(where + ": '" + t + "' is not a number");
      return v;
    };
    const std::string& kind = next();
    if (kind == "d") {
      result.done.push_back(static_cast<int>(integer(0, 1 << 30)));
    } else if (kind == "r") {
      const int point = static_cast<int>(integer(0, 1 << 30));
      TrialRecord r;
      r.sweep = next();
      r.value = real();
      r.algorithm = next();
      r.trial = static_cast<int>(integer(0, 1 << 30));
      const auto u64 = [&]() {
        const std::string& t = next();
        if (t.empty() || !std::all_of(t.begin(), t.end(), [](char c) { return c >= '0' && c <= '9'; }))
          throw InputError(where + ": '" + t + "' is not a seed");
        return static_cast<std::uint64_t>(std::stoull(t));
      };
      r.seed = u64();
      r.start_seed = u64();
      r.iterations = static_cast<int>(integer(0, 1LL << 31));
      r.converged = integer(0, 1) == 1;
      r.status = next();
      for (double* v : {&r.final_icn, &r.dist_to_icn050_m, &r.dist_to_icn095_m, &r.dist_total_m,
                        &r.dist_placement_m, &r.probe_dist_m, &r.sinr_nv_db, &r.sinr_zf_db, &r.sinr_mf_db,
                        &r.mean_sinr_nv_db, &r.mean_sinr_zf_db, &r.mean_sinr_mf_db, &r.sum_rate_nv_bps_hz,
                        &r.sum_rate_zf_bps_hz}) {
        *v = real();
      }
      r.extra.resize(static_cast<std::size_t>(integer(0, 1 << 20)));
      for (double& v : r.extra) v = real();
      for (Eigen::Matrix3Xd* q : {&r.start_m, &r.final_m}) {
        q->resize(3, integer(0, 1 << 20));
        for (Eigen::Index n = 0; n < q->cols(); ++n) {
          for (int i = 0; i < 3; ++i) (*q)(i, n) = real();
        }
      }
      if (k != f.size()) throw InputError(where + ": " + std::to_string(f.size() - k) + " extra fields");
      result.points[point].push_back(std::move(r));
    } else {
      throw InputError(where + ": unknown line kind '" + kind + "'");
    }
  }
  return result;
}

namespace {
namespace fs = std::filesystem;

ExperimentSettings load_settings(const ExperimentOptions& options, const ExperimentExtensions& extensions) {
  IniConfig config = options.config_path.empty() ? IniConfig() : IniConfig::from_file(options.config_path);
  for (const std::string& o : options.overrides) config.set_override(o);
  if (options.trials > 0) config.set("experiment", "trials", std::to_string(options.trials));
  if (options.threads >= 0) config.set("experiment", "threads", std::to_string(options.threads));
  return load_experiment_settings(config, extensions);
}

// The configuration as far as results depend on it: threads and plots do not matter.
std::string results_config(ExperimentSettings s) {
  s.threads = 0;
  s.plots = true;
  s.config.set("experiment", "threads", "0");
  s.config.set("experiment", "plots", "true");
  return to_ini(s);
}

// The first line where two configs differ, for the error message.
std::string first_difference(const std::string& a, const std::string& b) {
  std::istringstream ia(a), ib(b);
  std::string la, lb;
  while (true) {
    const bool ga = static_cast<bool>(std::getline(ia, la));
    const bool gb = static_cast<bool>(std::getline(ib, lb));
    if (!ga && !gb) return "";
    if (!ga) la = "(nothing)";
    if (!gb) lb = "(nothing)";
    if (la != lb) return "'" + la + "' vs '" + lb + "'";
  }
}

ExperimentSettings load_stored_settings(const fs::path& config_ini, const ExperimentExtensions& extensions) {
  if (!fs::exists(config_ini)) throw InputError(config_ini.string() + ": missing");
  return load_experiment_settings(IniConfig::from_file(config_ini.string()), extensions);
}

int threads_of(const ExperimentSettings& settings) {
  return settings.threads > 0 ? settings.threads
                              : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

// Writes through a temp file renamed into place.
void write_stream_atomically(const fs::path& path, const std::function<void(std::ostream&)>& writer) {
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    writer(out);
    out.flush();
    if (!out) throw std::runtime_error(tmp.string() + ": write failed");
  }
  fs::rename(tmp, path);
}

// Everything after the runs: trials/positions (from the records unless renamed from the
// partial files), traces, summary, figures and report.
void finish_outputs(const ExperimentSettings& settings, const ExperimentExtensions& extensions,
                    const ExperimentResults& results, const fs::path& dir, const RunTiming& timing,
                    bool trial_files_written, std::ostream& out, std::ostream& err) {
  const std::vector<std::string> extra = extra_metric_names(settings, extensions);
  if (!trial_files_written) {
    write_stream_atomically(dir / "trials.csv", [&](std::ostream& o) {
      write_trials_header(o, extra);
      write_trials_rows(o, results.records, extra.size());
    });
    write_stream_atomically(dir / "positions.csv", [&](std::ostream& o) {
      write_positions_header(o);
      write_positions_rows(o, results.records);
    });
  }
  std::ostringstream traces, summary;
  write_traces_csv(traces, results.traces);
  write_file_atomically((dir / "traces.csv").string(), traces.str());
  const std::vector<SummaryRow> rows = summarize(results.records, extra);
  write_summary_csv(summary, rows);
  write_file_atomically((dir / "summary.csv").string(), summary.str());
  const ReportOutcome report = write_figures_and_report(settings, extensions, results, rows, dir.string(), timing);
  for (const std::string& w : report.warnings) err << "losmimo-experiment: warning: " << w << "\n";
  out << "losmimo-experiment: " << results.records.size() << " trial rows, " << settings.trials
      << " trials per point, " << describe(timing) << "; results in " << dir.string()
      << "/ (report.md, summary.csv, trials.csv, fig*.png)\n";
}

// Orders the records of complete shards as one process would have; InputError if a job is
// missing or duplicated.
ExperimentResults merge_shard_records(const ExperimentSettings& settings, const std::vector<RecordLines>& shards,
                                      const std::vector<std::string>& origins) {
  const int points = num_sweep_points(settings);
  const int trials = settings.trials;
  // (point, trial) -> shard that ran it
  std::vector<int> owner(static_cast<std::size_t>(points) * trials, -1);
  std::vector<std::vector<std::vector<TrialRecord>>> by_job(points, std::vector<std::vector<TrialRecord>>(trials));
  for (std::size_t s = 0; s < shards.size(); ++s) {
    std::set<std::pair<int, int>> jobs_here;
    for (const auto& [point, records] : shards[s].points) {
      if (point >= points) throw InputError(origins[s] + ": point " + std::to_string(point) + " beyond the config's " + std::to_string(points));
      for (const TrialRecord& r : records) {
        if (r.trial >= trials) throw InputError(origins[s] + ": trial " + std::to_string(r.trial) + " beyond the config's " + std::to_string(trials));
        int& o = owner[static_cast<std::size_t>(point) * trials + r.trial];
        if (o != -1 && o != static_cast<int>(s)) {
          throw InputError(origins[s] + ": point " + std::to_string(point) + ", trial " + std::to_string(r.trial) +
                           " is also in " + origins[o]);
        }
        o = static_cast<int>(s);
        by_job[point][r.trial].push_back(r);
      }
    }
  }
  ExperimentResults results;
  for (int p = 0; p < points; ++p) {
    for (int t = 0; t < trials; ++t) {
      if (owner[static_cast<std::size_t>(p) * trials + t] == -1) {
        throw InputError("merge: no records of point " + std::to_string(p) + ", trial " + std::to_string(t) +
                         " (an incomplete or missing shard)");
      }
      for (TrialRecord& r : by_job[p][t]) results.records.push_back(std::move(r));
    }
  }
  return results;
}

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

// The checkpoint of an interrupted run: the records of the finished points (a prefix).
struct Checkpoint {
  std::map<int, std::vector<TrialRecord>> finished;
};

Checkpoint read_checkpoint(const fs::path& dir) {
  const fs::path path = dir / "records.partial";
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": missing: nothing to resume (was the run already complete?)");
  const RecordLines lines = parse_record_lines(in, path.string(), true);
  Checkpoint c;
  for (std::size_t i = 0; i < lines.done.size(); ++i) {
    if (lines.done[i] != static_cast<int>(i)) throw InputError(path.string() + ": points not finished in order");
    const auto it = lines.points.find(lines.done[i]);
    c.finished[lines.done[i]] = it == lines.points.end() ? std::vector<TrialRecord>{} : it->second;
  }
  return c;
}
}  // namespace

int run_experiment_app(const ExperimentOptions& options, const ExperimentExtensions& extensions,
                       std::ostream& out, std::ostream& err) {
  ExperimentSettings settings;
  ExperimentSlice slice;
  const bool resume = !options.resume_dir.empty();
  const ExperimentCollective* collective = options.collective && options.collective->size > 1 ? options.collective : nullptr;
  const bool root = !collective || collective->rank == 0;
  const fs::path dir(resume ? options.resume_dir : options.out_dir);
  try {
    settings = load_settings(options, extensions);
    if (!options.shard.empty()) std::tie(slice.shard_index, slice.shard_count) = parse_shard(options.shard);
    if (resume && (!options.shard.empty() || collective)) {
      throw InputError("--resume runs a whole experiment: not with --shard or MPI");
    }
    if (!options.shard.empty() && collective) throw InputError("--shard and MPI (mpirun) cannot be combined");
    if (collective) {
      slice.shard_index = collective->rank;
      slice.shard_count = collective->size;
    }
    if (resume) {
      const ExperimentSettings stored = load_stored_settings(dir / "config.ini", extensions);
      const std::string diff = first_difference(results_config(stored), results_config(settings));
      if (!diff.empty()) {
        throw InputError("--resume " + dir.string() + ": the config differs from its config.ini: " + diff);
      }
    }
  } catch (const InputError& e) {
    err << "losmimo-experiment: " << e.what() << "\n";
    return 2;
  }
  const bool sharded = slice.shard_count > 1 || !options.shard.empty();
  const int threads = threads_of(settings);
  try {
    if (collective) {
      // Every rank runs its slice in memory; rank 0 gathers, merges and writes.
      std::string mine;
      ExperimentResults part;
      const auto t0 = std::chrono::steady_clock::now();
      try {
        slice.traces = false;
        Progress progress(err);
        std::ostringstream text;
        part = run_experiment(settings, extensions, threads, slice, root ? ProgressFn(std::ref(progress)) : ProgressFn(),
                              [&](int point, const std::vector<TrialRecord>& rows) { write_record_lines(text, point, rows); });
        mine = text.str();
      } catch (const std::exception& e) {
        mine = std::string("!") + e.what();  // reported by rank 0; the gather must still happen
      }
      const std::vector<std::string> all = collective->gather(mine);
      if (!root) return mine.rfind('!', 0) == 0 ? 1 : 0;
      std::vector<RecordLines> shards;
      std::vector<std::string> origins;
      for (std::size_t r = 0; r < all.size(); ++r) {
        origins.push_back("rank " + std::to_string(r));
        if (all[r].rfind('!', 0) == 0) throw std::runtime_error(origins.back() + ": " + all[r].substr(1));
        std::istringstream in(all[r]);
        shards.push_back(parse_record_lines(in, origins.back(), false));
      }
      ExperimentResults results = merge_shard_records(settings, shards, origins);
      results.traces = traced_runs(settings);
      const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      fs::create_directories(dir);
      write_file_atomically((dir / "config.ini").string(), to_ini(settings));
      finish_outputs(settings, extensions, results, dir, {wall_s, threads * collective->size}, false, out, err);
      return 0;
    }

    fs::create_directories(dir);
    const std::vector<std::string> extra = extra_metric_names(settings, extensions);
    if (resume) {
      Checkpoint c = read_checkpoint(dir);
      slice.finished_points = std::move(c.finished);
      // Cut the user-facing partial files back to the last finished point, rewrite the checkpoint.
      const int kept = static_cast<int>(slice.finished_points.size());
      std::ostringstream records;
      records << kRecordsHeader << "\n";
      for (const auto& [p, rows] : slice.finished_points) {
        write_record_lines(records, p, rows);
        write_point_done(records, p);
      }
      std::vector<TrialRecord> kept_rows;
      for (const auto& [p, rows] : slice.finished_points) kept_rows.insert(kept_rows.end(), rows.begin(), rows.end());
      write_stream_atomically(dir / "trials.csv.partial", [&](std::ostream& o) {
        write_trials_header(o, extra);
        write_trials_rows(o, kept_rows, extra.size());
      });
      write_stream_atomically(dir / "positions.csv.partial", [&](std::ostream& o) {
        write_positions_header(o);
        write_positions_rows(o, kept_rows);
      });
      write_file_atomically((dir / "records.partial").string(), records.str());
      err << "losmimo-experiment: resuming " << dir.string() << ": " << kept << " of " << num_sweep_points(settings)
          << " points already finished\n";
    }
    write_file_atomically((dir / "config.ini").string(), to_ini(settings));

    const auto mode = resume ? std::ios::app : std::ios::trunc;
    std::ofstream records_part(dir / "records.partial", std::ios::binary | mode);
    std::ofstream trials_part, positions_part;
    if (!resume) records_part << kRecordsHeader << "\n";
    if (!sharded) {
      trials_part.open(dir / "trials.csv.partial", std::ios::binary | mode);
      positions_part.open(dir / "positions.csv.partial", std::ios::binary | mode);
      if (!resume) {
        write_trials_header(trials_part, extra);
        write_positions_header(positions_part);
      }
    }
    const auto sink = [&](int point, const std::vector<TrialRecord>& rows) {
      if (!sharded) {
        write_trials_rows(trials_part, rows, extra.size());
        write_positions_rows(positions_part, rows);
        trials_part.flush();
        positions_part.flush();
      }
      // The checkpoint last: a `d` line promises the point is complete everywhere.
      write_record_lines(records_part, point, rows);
      write_point_done(records_part, point);
      records_part.flush();
    };
    Progress progress(err);
    const auto t0 = std::chrono::steady_clock::now();
    if (sharded) slice.traces = false;
    const ExperimentResults results = run_experiment(settings, extensions, threads, slice, std::ref(progress), sink);
    const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    records_part.close();
    if (!records_part) throw std::runtime_error("writing records.partial failed");
    if (sharded) {
      fs::rename(dir / "records.partial", dir / "records.csv");
      std::ostringstream shard;
      shard << "# losmimo-experiment shard: merge the folders of shards 0.." << slice.shard_count - 1
            << " with `losmimo-experiment merge`\n[shard]\nindex = " << slice.shard_index
            << "\ncount = " << slice.shard_count << "\n"
            << "# this shard's run, reported by the merge\nthreads = " << threads << "\nwall_s = "
            << std::setprecision(17) << wall_s << "\n";
      write_file_atomically((dir / "shard.ini").string(), shard.str());
      out << "losmimo-experiment: shard " << slice.shard_index << "/" << slice.shard_count << ": "
          << results.records.size() << " trial rows, " << describe({wall_s, threads}) << "; records in "
          << dir.string() << "/records.csv\n";
      return 0;
    }
    trials_part.close();
    positions_part.close();
    if (!trials_part || !positions_part) throw std::runtime_error("writing trials/positions failed");
    fs::rename(dir / "trials.csv.partial", dir / "trials.csv");
    fs::rename(dir / "positions.csv.partial", dir / "positions.csv");
    finish_outputs(settings, extensions, results, dir, {wall_s, threads}, true, out, err);
    fs::remove(dir / "records.partial");
    return 0;
  } catch (const InputError& e) {
    err << "losmimo-experiment: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    err << "losmimo-experiment: error: " << e.what() << "\n";
    return 1;
  }
}

namespace {
// Adds a shard's own run (its shard.ini `threads` and `wall_s`) to the merge's timing, if the
// shard recorded them (folders written before they were did not).
void add_shard_timing(const IniConfig& shard_ini, RunTiming& timing) {
  if (!shard_ini.has("shard", "wall_s") || !shard_ini.has("shard", "threads")) return;
  const double wall_s = shard_ini.get_double("shard", "wall_s", 0.0);
  if (!std::isfinite(wall_s) || wall_s < 0.0) {
    throw InputError(shard_ini.where("shard", "wall_s") + " = " + shard_ini.get_string("shard", "wall_s", "") +
                     ": must be a finite number of seconds >= 0");
  }
  const int threads = static_cast<int>(shard_ini.get_integer("shard", "threads", 1, 1, 1'000'000));
  ++timing.timed_shards;
  timing.slowest_shard_wall_s = std::max(timing.slowest_shard_wall_s, wall_s);
  timing.shards_wall_s += wall_s;
  timing.min_shard_threads = timing.timed_shards == 1 ? threads : std::min(timing.min_shard_threads, threads);
  timing.max_shard_threads = std::max(timing.max_shard_threads, threads);
}
}  // namespace

int merge_experiment_app(const std::vector<std::string>& shard_dirs, const std::string& out_dir,
                         const ExperimentExtensions& extensions, std::ostream& out, std::ostream& err) {
  ExperimentSettings settings;
  ExperimentResults results;
  RunTiming timing;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    if (shard_dirs.empty()) throw InputError("merge: no shard folders given");
    std::string reference;
    int count = -1;
    std::map<int, std::string> seen;  // shard index -> folder
    std::vector<RecordLines> shards;
    for (const std::string& d : shard_dirs) {
      const fs::path shard_ini = fs::path(d) / "shard.ini";
      if (!fs::exists(shard_ini)) {
        throw InputError(shard_ini.string() + ": missing: not a finished shard folder (run with --shard i/N)");
      }
      const IniConfig ini = IniConfig::from_file(shard_ini.string());
      ini.require_known({{"shard", {"index", "count", "threads", "wall_s"}}});
      if (!ini.has("shard", "count") || !ini.has("shard", "index")) {
        throw InputError(shard_ini.string() + ": needs [shard] index and count");
      }
      const int n = static_cast<int>(ini.get_integer("shard", "count", 1, 1, 1'000'000'000));
      const int i = static_cast<int>(ini.get_integer("shard", "index", 0, 0, n - 1));
      if (count != -1 && n != count) {
        throw InputError(d + ": shard " + std::to_string(i) + " of " + std::to_string(n) + ", but " +
                         seen.begin()->second + " is one of " + std::to_string(count));
      }
      count = n;
      if (seen.count(i)) throw InputError(d + ": shard " + std::to_string(i) + " given twice (also " + seen[i] + ")");
      seen[i] = d;
      add_shard_timing(ini, timing);
      const ExperimentSettings s = load_stored_settings(fs::path(d) / "config.ini", extensions);
      const std::string config = results_config(s);
      if (reference.empty()) {
        reference = config;
        settings = s;
      } else if (const std::string diff = first_difference(reference, config); !diff.empty()) {
        throw InputError(d + "/config.ini differs from " + shard_dirs.front() + "/config.ini: " + diff);
      }
    }
    std::string missing;
    for (int i = 0; i < count; ++i) {
      if (!seen.count(i)) missing += (missing.empty() ? "" : ", ") + std::to_string(i);
    }
    if (!missing.empty()) throw InputError("merge: missing shard(s) " + missing + " of " + std::to_string(count));
    std::vector<std::string> origins;
    for (const auto& [i, d] : seen) {
      const fs::path path = fs::path(d) / "records.csv";
      std::ifstream in(path, std::ios::binary);
      if (!in) throw InputError(path.string() + ": missing");
      origins.push_back(path.string());
      shards.push_back(parse_record_lines(in, path.string(), false));
    }
    results = merge_shard_records(settings, shards, origins);
  } catch (const InputError& e) {
    err << "losmimo-experiment merge: " << e.what() << "\n";
    return 2;
  }
  try {
    results.traces = traced_runs(settings);
    const fs::path dir(out_dir);
    fs::create_directories(dir);
    write_file_atomically((dir / "config.ini").string(), to_ini(settings));
    const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    timing.wall_s = wall_s;
    timing.shards = static_cast<int>(shard_dirs.size());
    finish_outputs(settings, extensions, results, dir, timing, false, out, err);
    return 0;
  } catch (const std::exception& e) {
    err << "losmimo-experiment merge: error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace losmimo::placement
