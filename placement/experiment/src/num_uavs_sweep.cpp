// The swarm-size sweep's keys, trials, timing log and extension (num_uavs_sweep.h); figure and
// report section in num_uavs_report.cpp.
#include "losmimo/placement/experiment/num_uavs_sweep.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <mutex>
#include <random>
#include <stdexcept>
#include <utility>

#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/scenario.h"

namespace losmimo::experiment {

namespace {
const std::string kSection = "experiment";

std::vector<common::Key<NumUavsSweepSettings>> num_uavs_key_list() {
  using K = common::Key<NumUavsSweepSettings>;
  return {
      K::integer_list(kSection, "num_uavs_values", &NumUavsSweepSettings::num_uavs_values, 1, 4096,
                      "sweep points of num_uavs: swarm sizes Nr", "4, 9"),
      K::text(
          kSection, "num_uavs_array",
          [](NumUavsSweepSettings& s, const std::string& text, const std::string& where) {
            if (text == "square") {
              s.array = NumUavsArray::kSquare;
            } else if (text == "fixed") {
              s.array = NumUavsArray::kFixed;
            } else {
              throw common::InputError(where + ": '" + text + "' is not square or fixed");
            }
          },
          [](const NumUavsSweepSettings& s) { return to_string(s.array); }, "square | fixed",
          "BS array of the num_uavs sweep: square = n x n with n^2 >= Nr (smallest n), fixed = scenario "
          "bs_rows x bs_cols (Nr <= Nt)",
          "fixed"),
      K::integer(kSection, "num_uavs_cap_max", &NumUavsSweepSettings::cap_max_uavs, 1, 4096,
                 "largest swarm of the num_uavs sweep at which cap runs (its iteration costs O(Nr^4))", "16"),
  };
}

}  // namespace

std::string to_string(NumUavsArray array) { return array == NumUavsArray::kSquare ? "square" : "fixed"; }

const common::KeyTable<NumUavsSweepSettings>& num_uavs_sweep_keys() {
  static const common::KeyTable<NumUavsSweepSettings> table(num_uavs_key_list());
  return table;
}

NumUavsSweepSettings load_num_uavs_sweep_settings(const ExperimentSettings& s) {
  NumUavsSweepSettings c;
  num_uavs_sweep_keys().load(s.config, c);
  const placement::Scenario& sc = s.placement.scenario;
  if (c.array == NumUavsArray::kFixed) {
    for (const int n : c.num_uavs_values) {
      if (n <= sc.num_bs_antennas()) continue;
      throw common::InputError(s.config.where(kSection, "num_uavs_values") + ": point " + std::to_string(n) +
                               " UAVs > bs_rows x bs_cols = " + std::to_string(sc.num_bs_antennas()) +
                               " antennas: num_uavs_array = fixed needs Nr <= Nt (use square or drop the point)");
    }
  }
  return c;
}

int square_array_side(int num_uavs) {
  int n = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(num_uavs))));
  while (n > 1 && (n - 1) * (n - 1) >= num_uavs) --n;  // guard the square root's rounding
  while (n * n < num_uavs) ++n;
  return n;
}

placement::Scenario num_uavs_scenario(const placement::Scenario& base, NumUavsArray array, int num_uavs) {
  placement::Scenario sc = base;
  sc.num_uavs = num_uavs;
  if (array == NumUavsArray::kSquare) sc.bs_rows = sc.bs_cols = square_array_side(num_uavs);
  return sc;
}

bool runs_at(const NumUavsSweepSettings& sweep, const Algorithm& a, int num_uavs) {
  return a != Algorithm::kCap || num_uavs <= sweep.cap_max_uavs;
}

const ExtensionMetrics& num_uavs_sweep_metrics() {
  static const ExtensionMetrics kTable = {kBsAntennas};
  return kTable;
}

struct NumUavsTiming::Impl {
  mutable std::mutex mutex;
  std::map<std::pair<int, std::string>, Entry> entries;
};

NumUavsTiming::NumUavsTiming() : impl_(std::make_shared<Impl>()) {}

void NumUavsTiming::add(int point, const std::string& algorithm, int iterations, double wall_s) {
  const std::lock_guard<std::mutex> lock(impl_->mutex);
  Entry& e = impl_->entries[{point, algorithm}];
  ++e.runs;
  e.iterations += iterations;
  e.wall_s += wall_s;
}

std::unique_ptr<NumUavsTiming::Entry> NumUavsTiming::find(int point, const std::string& algorithm) const {
  const std::lock_guard<std::mutex> lock(impl_->mutex);
  const auto it = impl_->entries.find({point, algorithm});
  return it == impl_->entries.end() ? nullptr : std::make_unique<Entry>(it->second);
}

void NumUavsTiming::clear() {
  const std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->entries.clear();
}

std::vector<TrialRecord> run_num_uavs_trial(const ExperimentSettings& s, const NumUavsSweepSettings& sweep, int point,
                                            int trial, NumUavsTiming* timing) {
  const SweepPoints* points = s.sweep(kSweepNumUavs);
  if (!points) throw std::invalid_argument("run_num_uavs_trial: the settings have no num_uavs sweep");
  const int num_uavs = static_cast<int>(points->values.at(point));
  placement::PlacementSettings p = s.placement;
  p.scenario = num_uavs_scenario(p.scenario, sweep.array, num_uavs);
  std::mt19937_64 rng(trial_start_seed(s, trial));  // trial t's start seed, Nr UAVs
  const Eigen::Matrix3Xd start = placement::random_start_positions_m(p.scenario, rng);
  const std::uint64_t seed = trial_seed(s, kSweepNumUavs, point, trial);
  placement::RunOptions run = p.run;
  run.full_icn_trace = false;  // only milestones and the final positions are recorded
  std::vector<TrialRecord> records;
  for (const Algorithm& a : s.algorithms) {
    if (!runs_at(sweep, a, num_uavs)) continue;
    const auto t0 = std::chrono::steady_clock::now();
    const placement::RunResult r = run_algorithm(s, p, a, trial, start, seed, run);
    const std::chrono::duration<double> wall = std::chrono::steady_clock::now() - t0;
    if (timing) timing->add(point, to_string(a), r.iterations, wall.count());
    TrialRecord rec = make_record(s, p, kSweepNumUavs, point, trial, to_string(a), r);
    rec.extension.set(kBsAntennas, p.scenario.num_bs_antennas());
    records.push_back(std::move(rec));
  }
  return records;
}

ExperimentExtension num_uavs_extension() {
  NumUavsTiming timing;  // shared by the copies in the lambdas below
  ExperimentExtension e;
  e.sweep = kSweepNumUavs;
  e.config_keys = num_uavs_sweep_keys().known_keys();
  e.metrics = num_uavs_sweep_metrics();
  e.load_values = [](const ExperimentSettings& s) {
    const NumUavsSweepSettings c = load_num_uavs_sweep_settings(s);
    return std::vector<double>(c.num_uavs_values.begin(), c.num_uavs_values.end());
  };
  e.run = [timing](const ExperimentSettings& s, int point, int trial) mutable {
    return run_num_uavs_trial(s, load_num_uavs_sweep_settings(s), point, trial, &timing);
  };
  e.figures = [timing](const ExperimentSettings& s, const std::vector<SummaryRow>& rows, const std::string& dir) {
    return write_num_uavs_figure(s, rows, timing, dir);
  };
  e.report_section = [timing](const ExperimentSettings& s, const std::vector<SummaryRow>& rows) mutable {
    std::string section = num_uavs_report_section(s, rows, timing);
    timing.clear();  // the last reader of this run's timing (figures are written before)
    return section;
  };
  e.unused_conditions = [](const ExperimentSettings& s) {
    const NumUavsSweepSettings c = load_num_uavs_sweep_settings(s);
    std::vector<std::string> out;
    if (c.array == NumUavsArray::kSquare) out.push_back(kNumUavsSquareArray);
    if (std::none_of(c.num_uavs_values.begin(), c.num_uavs_values.end(), [&c](int n) { return n > c.cap_max_uavs; })) {
      out.push_back(kNumUavsNoneAboveCapMax);
    }
    return out;
  };
  return e;
}

}  // namespace losmimo::experiment
