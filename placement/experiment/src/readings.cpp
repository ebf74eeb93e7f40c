#include "losmimo/placement/experiment/readings.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <map>
#include <mutex>
#include <ostream>
#include <sstream>
#include <thread>
#include <utility>

#include "losmimo/placement/common/format.h"
#include "losmimo/placement/experiment/metrics.h"

namespace losmimo::experiment {

namespace {

// One (sweep, point) the paper values need, with the algorithms they use there.
struct PointJob {
  std::string sweep;
  int point = 0;
  std::vector<Algorithm> algorithms;
};

int point_index(const ExperimentSettings& s, const std::string& sweep, double value) {
  const SweepPoints* points = s.sweep(sweep);
  if (!points) return -1;
  for (std::size_t i = 0; i < points->values.size(); ++i) {
    if (std::abs(points->values[i] - value) < 1e-12) return static_cast<int>(i);
  }
  return -1;
}

// Whether some registered planner owns `section` (PlannerEntry::sections).
bool planner_section(const std::string& section) {
  for (const std::string& name : placement::planner_names()) {
    const std::vector<std::string>& own = placement::planner_entry(name).sections;
    if (std::find(own.begin(), own.end(), section) != own.end()) return true;
  }
  return false;
}

// The algorithms a reading can change: a key of a planner's own section ([gd], [bf], [ura],
// [cap]) changes the planners owning it (its options and stop rules reach no other planner); a
// key of any other section, all of them.
bool changes(const ReadingSpec& r, const Algorithm& a) {
  const std::vector<std::string>& own = a.entry().sections;
  for (const auto& [name, value] : r.assignments) {
    const std::string section = name.substr(0, name.find('.'));
    if (planner_section(section) && std::find(own.begin(), own.end(), section) == own.end()) continue;
    return true;
  }
  return false;
}

bool has_algorithm(const ExperimentSettings& s, const std::string& name) {
  return std::any_of(s.algorithms.begin(), s.algorithms.end(),
                     [&](const Algorithm& a) { return to_string(a) == name; });
}

}  // namespace

const ReadingMeasure* ReadingResults::find(std::size_t r, int number) const {
  if (r >= measures.size()) return nullptr;
  for (std::size_t v = 0; v < value_numbers.size(); ++v) {
    if (value_numbers[v] == number) return &measures[r][v];
  }
  return nullptr;
}

double record_metric(const TrialRecord& r, MetricId metric) {
  const auto iteration = [](int i) { return i >= 0 ? static_cast<double>(i) : std::nan(""); };
  if (metric == metrics::kIterationsToIcn050) return iteration(r.icn050_iteration);
  if (metric == metrics::kIterationsToIcn095) return iteration(r.icn095_iteration);
  const Metric* m = find_metric(metric);
  return m ? m->get(r) : std::nan("");
}

bool agrees(const Estimate& e, const PaperValue& p) {
  if (e.n == 0) return false;
  const double ci = std::isfinite(e.ci95) ? e.ci95 : 0.0;
  return std::abs(e.mean - p.paper) <= ci + p.resolution;
}

namespace {

// The paper values the run can measure (into out.values and out.value_numbers) and the sweep
// points they need, each with its algorithms; point_of_value[v]: value v's point.
std::vector<PointJob> points_of_values(const ExperimentSettings& s, ReadingResults& out,
                                       std::vector<int>& point_of_value) {
  std::vector<PointJob> points;
  const std::vector<PaperValue> all = paper_values();
  for (std::size_t i = 0; i < all.size(); ++i) {
    const PaperValue& p = all[i];
    const int point = point_index(s, p.sweep, p.value);
    if (point < 0 || !has_algorithm(s, p.algorithm)) continue;
    out.values.push_back(p);
    out.value_numbers.push_back(static_cast<int>(i) + 1);
    auto job = std::find_if(points.begin(), points.end(),
                            [&](const PointJob& j) { return j.sweep == p.sweep && j.point == point; });
    if (job == points.end()) job = points.insert(points.end(), PointJob{p.sweep, point, {}});
    const Algorithm a = algorithm_from_string(p.algorithm, "paper value");
    if (std::find(job->algorithms.begin(), job->algorithms.end(), a) == job->algorithms.end()) {
      job->algorithms.push_back(a);
    }
    point_of_value.push_back(static_cast<int>(job - points.begin()));
  }
  return points;
}

// Every (configuration, point, trial) job's records, slot (c * points + point) * trials + trial,
// on `threads` threads; configuration 0 is the base, 1.. the readings, each running only the
// algorithms its points need that it changes.
std::vector<std::vector<TrialRecord>> run_reading_jobs(const ExperimentSettings& s,
                                                       const std::vector<ExperimentSettings>& configs,
                                                       const std::vector<PointJob>& points, int trials, int threads) {
  const std::size_t num_jobs = configs.size() * points.size() * static_cast<std::size_t>(trials);
  std::vector<std::vector<TrialRecord>> slots(num_jobs);
  std::atomic<std::size_t> next{0};
  std::mutex mutex;
  std::exception_ptr failure;
  const auto worker = [&] {
    for (std::size_t j = next++; j < num_jobs; j = next++) {
      const std::size_t c = j / (points.size() * trials);
      const PointJob& point = points[(j / trials) % points.size()];
      const int trial = static_cast<int>(j % trials);
      try {
        ExperimentSettings here = configs[c];
        here.algorithms.clear();
        for (const Algorithm& a : point.algorithms) {
          if (c == 0 || changes(s.readings[c - 1], a)) here.algorithms.push_back(a);
        }
        if (!here.algorithms.empty()) slots[j] = run_trial(here, point.sweep, point.point, trial);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(mutex);
        if (!failure) failure = std::current_exception();
        next = num_jobs;
      }
    }
  };
  std::vector<std::thread> pool;
  const int n_threads = std::max(1, std::min<int>(threads, static_cast<int>(num_jobs)));
  for (int t = 0; t < n_threads; ++t) pool.emplace_back(worker);
  for (std::thread& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
  return slots;
}

}  // namespace

ReadingResults measure_readings(const ExperimentSettings& s, const ExperimentExtensions& extensions, int threads) {
  ReadingResults out;
  if (s.readings.empty()) return out;
  out.readings = s.readings;
  out.trials = std::min(s.reading_trials, s.trials);
  std::vector<int> point_of_value;
  const std::vector<PointJob> points = points_of_values(s, out, point_of_value);

  // Configuration 0 is the base, 1.. the readings; each runs only the algorithms its points need.
  std::vector<ExperimentSettings> configs{s};
  configs[0].readings.clear();
  for (const ReadingSpec& r : s.readings) configs.push_back(apply_reading(s, r, extensions));
  const int trials = out.trials;
  const std::vector<std::vector<TrialRecord>> slots = run_reading_jobs(s, configs, points, trials, threads);

  // Per configuration and value: the per-trial values (NaN where undefined). A reading that
  // cannot change the value's algorithm was not run: its values are the base's.
  const auto series = [&](std::size_t c, std::size_t v) {
    const PaperValue& p = out.values[v];
    if (c > 0 && !changes(s.readings[c - 1], algorithm_from_string(p.algorithm, "paper value"))) c = 0;
    const std::size_t point = static_cast<std::size_t>(point_of_value[v]);
    std::vector<double> x(static_cast<std::size_t>(trials), std::nan(""));
    for (int t = 0; t < trials; ++t) {
      for (const TrialRecord& r : slots[(c * points.size() + point) * trials + t]) {
        if (r.algorithm == p.algorithm) x[t] = record_metric(r, p.metric);
      }
    }
    return x;
  };
  for (std::size_t r = 1; r < configs.size(); ++r) {
    std::vector<ReadingMeasure> row;
    for (std::size_t v = 0; v < out.values.size(); ++v) {
      const std::vector<double> base = series(0, v);
      const std::vector<double> x = series(r, v);
      std::vector<double> d(x.size(), std::nan(""));
      for (std::size_t t = 0; t < x.size(); ++t) d[t] = x[t] - base[t];  // NaN unless both defined
      row.push_back({estimate(x), estimate(base), estimate(d)});
    }
    out.measures.push_back(std::move(row));
  }
  return out;
}

namespace {
// " dB", " m", " iterations": the unit its table declares, "" for a ratio or a flag.
std::string unit_of(MetricId metric) {
  const char* unit = "";
  if (const Metric* m = find_metric(metric)) unit = m->unit;
  for (const ExtensionMetric& m : milestone_metrics()) {
    if (m == metric) unit = m.unit;
  }
  return *unit ? std::string(" ") + unit : "";
}
std::string fixed(double v, int digits = 2) { return common::format_fixed(v, digits); }
std::string signed_fixed(double v) { return (v >= 0.0 ? "+" : "") + fixed(v); }
double ci_or_zero(const Estimate& e) { return std::isfinite(e.ci95) ? e.ci95 : 0.0; }
}  // namespace

std::string explain_difference(const PaperValue& p, int number, const ReadingResults& res) {
  if (res.empty()) {
    return "cause unknown: no reading was run here ([experiment] readings; docs/fidelity.md has the study)";
  }
  const std::string unit = unit_of(p.metric);
  struct Move {
    std::string text;
    double gap;  // |where it lands - paper|
  };
  std::vector<Move> toward;
  std::string largest_away;
  double largest_away_size = -1.0;
  for (std::size_t r = 0; r < res.readings.size(); ++r) {
    const ReadingMeasure* m = res.find(r, number);
    if (!m) continue;
    const std::string who = res.readings[r].text();
    if (m->base.n == 0 && m->value.n > 0) {
      toward.push_back({who + " reaches it in " + std::to_string(m->value.n) + " of " + std::to_string(res.trials) +
                            " trials, at " + fixed(m->value.mean) + " ± " + fixed(ci_or_zero(m->value)) + unit +
                            (agrees(m->value, p) ? " (agrees)" : ""),
                        std::abs(m->value.mean - p.paper)});
      continue;
    }
    if (m->base.n > 0 && m->value.n == 0) {
      if (largest_away.empty()) largest_away = who + " never reaches it";
      continue;
    }
    if (m->delta.n < 2 || !(std::abs(m->delta.mean) > ci_or_zero(m->delta))) continue;  // within its CI
    const std::string move = who + ": " + signed_fixed(m->delta.mean) + " ± " + fixed(ci_or_zero(m->delta)) + unit +
                             ", to " + fixed(m->value.mean) + (agrees(m->value, p) ? " (agrees)" : "");
    if (std::abs(m->value.mean - p.paper) < std::abs(m->base.mean - p.paper)) {
      toward.push_back({move, std::abs(m->value.mean - p.paper)});
    } else if (std::abs(m->delta.mean) > largest_away_size) {
      largest_away_size = std::abs(m->delta.mean);
      largest_away = move;
    }
  }
  const std::string trials = "paired runs, " + std::to_string(res.trials) + " trials per reading";
  if (toward.empty()) {
    std::string text = "cause unknown: none of the " + std::to_string(res.readings.size()) +
                       " readings moves it toward the paper beyond the CI of its paired difference (" + trials + ")";
    if (!largest_away.empty()) text += "; away from it: " + largest_away;
    return text;
  }
  std::stable_sort(toward.begin(), toward.end(), [](const Move& a, const Move& b) { return a.gap < b.gap; });
  std::string text;
  for (std::size_t i = 0; i < toward.size() && i < 3; ++i) text += (i ? "; " : "") + toward[i].text;
  if (toward.size() > 3) text += "; " + std::to_string(toward.size() - 3) + " more in readings.csv";
  return text + " (" + trials + ")";
}

std::string readings_section(const ReadingResults& res) {
  std::ostringstream md;
  md << "## Readings\n\nEach reading sets the keys shown on top of this configuration and runs the first " << res.trials
     << " trials at the paper values' sweep points with the same seeds (readings.csv has every "
     << "number). Agreement here is at " << res.trials << " trials, so its CIs are wider than the table's.\n\n"
     << "| reading | agrees (of " << res.values.size() << ") | gains | loses |\n|---|---|---|---|\n";
  int base_agrees = 0;
  for (std::size_t v = 0; v < res.values.size(); ++v)
    base_agrees += agrees(res.measures.front()[v].base, res.values[v]);
  md << "| (this configuration) | " << base_agrees << " | | |\n";
  for (std::size_t r = 0; r < res.readings.size(); ++r) {
    int count = 0;
    std::string gains, loses;
    for (std::size_t v = 0; v < res.values.size(); ++v) {
      const bool now = agrees(res.measures[r][v].value, res.values[v]);
      const bool before = agrees(res.measures[r][v].base, res.values[v]);
      count += now;
      const std::string id = "#" + std::to_string(res.value_numbers[v]);
      if (now && !before) gains += (gains.empty() ? "" : " ") + id;
      if (!now && before) loses += (loses.empty() ? "" : " ") + id;
    }
    md << "| `" << res.readings[r].text() << "` | " << count << " | " << gains << " | " << loses << " |\n";
  }
  return md.str();
}

void write_readings_csv(std::ostream& o, const ReadingResults& res) {
  const auto fmt = [](double v) { return common::format_g(v, common::kCsvDigits); };
  // Labels may hold commas: quoted.
  const auto quoted = [](const std::string& t) {
    std::string q = "\"";
    for (const char c : t) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
  };
  o << "reading,number,figure,quantity,sweep,value,algorithm,metric,paper,trials,mean,ci95,n,base_mean,base_ci95,"
       "base_n,delta_mean,delta_ci95,delta_n,agrees,settings\n";
  for (std::size_t r = 0; r < res.readings.size(); ++r) {
    for (std::size_t v = 0; v < res.values.size(); ++v) {
      const PaperValue& p = res.values[v];
      const ReadingMeasure& m = res.measures[r][v];
      o << res.readings[r].name << "," << res.value_numbers[v] << "," << quoted(p.figure) << "," << quoted(p.quantity)
        << "," << p.sweep << "," << fmt(p.value) << "," << p.algorithm << "," << p.metric.name << "," << fmt(p.paper)
        << "," << res.trials << "," << fmt(m.value.mean) << "," << fmt(m.value.ci95) << "," << m.value.n << ","
        << fmt(m.base.mean) << "," << fmt(m.base.ci95) << "," << m.base.n << "," << fmt(m.delta.mean) << ","
        << fmt(m.delta.ci95) << "," << m.delta.n << "," << (agrees(m.value, p) ? "yes" : "no") << ","
        << quoted(res.readings[r].text()) << "\n";
    }
  }
}

}  // namespace losmimo::experiment
