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

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "losmimo/apps/eval_app.h"
#include "losmimo/apps/experiment_app.h"
#include "losmimo/apps/record_app.h"
#include "losmimo/coevaluation/coevaluation.h"
#include "losmimo/coevaluation/extensions.h"
#include "losmimo/experiment/channel_sweeps.h"
#include "losmimo/experiment/num_uavs_sweep.h"
#include "losmimo/experiment/settings.h"
#include "losmimo/fusion/closed_loop_settings.h"
#include "losmimo/placement/settings.h"
#include "losmimo/rawlog/log.h"
#include "losmimo/rawlog/mission.h"
#include "support/files.h"

namespace losmimo {
namespace {

namespace fs = std::filesystem;

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
const Exemptions kFigureOrLoggingOnly = {
    {"experiment.threads", {"experiment", "worker threads: the results do not depend on it"}},
    {"experiment.plots", {"experiment", "gnuplot figures only (fig*.png)"}},
    {"mission.epoch_period_s", {"record", "the timestamps of the rawlog's observations: no estimator reads time"}},
};

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
const std::vector<Regime> kRegimes = {
    {"a run that does not converge", {{"placement.target_icn", "1"}}},
    {"a low target ICN, which the planners reach", {{"placement.target_icn", "0.7"}}},
    {"a high target ICN below 1 (centralized needs one)", {{"placement.target_icn", "0.99"}}},
    {"a long run that does not converge", {{"placement.target_icn", "1"}, {"placement.max_iterations", "200"}}},
    {"GD steps that overshoot", {{"gd.step", "5"}}},
    {"GD steps that overshoot more", {{"gd.step", "50"}, {"placement.target_icn", "1"}}},
    {"capacity steps that hit the move cap and overshoot", {{"cap.step", "1000"}, {"placement.target_icn", "1"}}},
    {"capacity steps far beyond the move cap",
     {{"cap.step", "1e6"}, {"cap.max_move_m", "5"}, {"placement.target_icn", "1"}}},
    {"BF at its smallest step", {{"placement.target_icn", "1"}, {"bf.step", "0.015"}}},
    {"a stall test at every iteration",
     {{"placement.target_icn", "1"}, {"gd.stall_window", "1"}, {"bf.stall_window", "1"}}},
    {"a long run with a stall test every two iterations",
     {{"placement.target_icn", "1"},
      {"placement.max_iterations", "200"},
      {"gd.stall_window", "2"},
      {"bf.stall_window", "2"}}},
    {"a long run with a stall test at every iteration",
     {{"placement.target_icn", "1"},
      {"placement.max_iterations", "200"},
      {"gd.stall_window", "1"},
      {"bf.stall_window", "1"}}},
};

const std::vector<Condition> kConditions = {
    {"*", "ura.retry", {{"placement.target_icn", "0.99"}}, "URA moves again only while the target ICN is not reached"},
    {"*",
     "channel.coherence_iterations",
     {{"channel.rician_k_db", "10"}},
     "block fading needs a finite K-factor",
     true},
    {"*", "channel.fading_eval_draws", {{"channel.rician_k_db", "10"}}, "scatter draws need a finite K-factor", true},
    // Readings are measured at the paper's values (sweep points such as 0), on at most the run's trials.
    {experiment::kSweepSigmaLoc,
     "experiment.reading_trials",
     {{"experiment.readings", "r: gd.escape=false"},
      {"experiment.trials", "21"},
      {"experiment.sigma_loc_values_m", "0"}},
     "the trials of the readings, when the run has more",
     true},
    {experiment::kSweepSigmaAct,
     "experiment.reading_trials",
     {{"experiment.readings", "r: gd.escape=false"},
      {"experiment.trials", "21"},
      {"experiment.sigma_act_values_m", "0"}},
     "the trials of the readings, when the run has more",
     true},
    {experiment::kSweepSigmaLoc,
     "experiment.readings",
     {{"experiment.sigma_loc_values_m", "0"}},
     "measured at the paper's values"},
    {experiment::kSweepSigmaAct,
     "experiment.readings",
     {{"experiment.sigma_act_values_m", "0"}},
     "measured at the paper's values"},
    // ura_ekf needs as many UAVs as BS antennas: the array and the swarm vary without it.
    {coevaluation::kSweepBeaconNoise,
     "scenario.bs_rows",
     {{"coevaluation.algorithms", "gd_gauss, gd_ekf, gd_pf, bf"}},
     "ura_ekf needs num_uavs = bs_rows * bs_cols"},
    {coevaluation::kSweepBeaconNoise,
     "scenario.bs_cols",
     {{"coevaluation.algorithms", "gd_gauss, gd_ekf, gd_pf, bf"}},
     "ura_ekf needs num_uavs = bs_rows * bs_cols"},
    {coevaluation::kSweepBeaconNoise,
     "scenario.num_uavs",
     {{"coevaluation.algorithms", "gd_gauss, gd_ekf, gd_pf, bf"}},
     "ura_ekf needs num_uavs = bs_rows * bs_cols"},
    // centralized needs a target ICN below 1, which the regimes set: without it.
    {coevaluation::kSweepBeaconNoise,
     "gd.stall_min_decrease",
     {{"coevaluation.algorithms", "gd_gauss, gd_ekf, gd_pf, bf"}},
     "the regimes' target ICN 1 is refused with centralized"},
    {coevaluation::kSweepBeaconNoise,
     "bf.min_step_m",
     {{"coevaluation.algorithms", "gd_gauss, gd_ekf, gd_pf, bf"}},
     "the regimes' target ICN 1 is refused with centralized"},
    {coevaluation::kSweepBeaconNoise,
     "bf.stall_min_decrease",
     {{"coevaluation.algorithms", "gd_gauss, gd_ekf, gd_pf, bf"}},
     "the regimes' target ICN 1 is refused with centralized"},
    // The closed loop's filter and refinement options act with that filter or refinement.
    {coevaluation::kSweepBeaconOutage,
     "closed_loop.num_particles",
     {{"coevaluation.outage_algorithms", "gd_pf"}},
     "the particle filter's size",
     true},
    {coevaluation::kSweepBeaconOutage,
     "closed_loop.window_epochs",
     {{"coevaluation.outage_algorithms", "gd_ekf_ceres"}},
     "the refinement's window",
     true},
    {coevaluation::kSweepBeaconOutage,
     "closed_loop.use_csi",
     {{"coevaluation.outage_algorithms", "gd_ekf_ceres"}},
     "the refinement's CSI rows",
     true},
    {"record", "closed_loop.num_particles", {{"closed_loop.filter", "pf"}}, "the particle filter's size", true},
    {"record", "closed_loop.window_epochs", {{"closed_loop.refine", "true"}}, "the refinement's window", true},
    {"record", "closed_loop.use_csi", {{"closed_loop.refine", "true"}}, "the refinement's CSI rows", true},
    {"record", "closed_loop.fallback", {{"closed_loop.outages", "0:1:30"}}, "BF for a UAV whose belief degrades"},
    {"record",
     "closed_loop.degraded_after_epochs",
     {{"closed_loop.outages", "0:1:30"}},
     "a belief degrades without beacons"},
    {"record",
     "closed_loop.filter_max_beacon_range_m",
     {{"scenario.cube_center_x_m", "3000"}},
     "beacons beyond the plausible range"},
    {"record", "bf.step", {{"closed_loop.outages", "0:1:30"}}, "the BF fallback of a degraded belief"},
    {"record", "bf.decay", {{"closed_loop.outages", "0:1:30"}}, "the BF fallback of a degraded belief"},
    {"record", "bf.contraction", {{"closed_loop.outages", "0:1:30"}}, "the BF fallback of a degraded belief"},
    {"record",
     "bf.min_step_m",
     {{"closed_loop.outages", "0:1:30"}, {"bf.step", "0.015"}},
     "the BF fallback of a degraded belief, at its smallest step"},
    {"record",
     "closed_loop.unresponsive_after_iterations",
     {{"closed_loop.faults", "unresponsive:0:2"}},
     "a UAV silent by an injected fault"},
};

// The value tried instead of the example: [experiment] sweeps adds a sweep to the context's
// (the example replaces it, leaving the context's sweep points unused).
struct Value {
  std::string context, key, value;
};
const std::vector<Value> kValues = {
    {experiment::kSweepSigmaLoc, "experiment.sweeps", "sigma_loc_m, sigma_act_m"},
    {"sigma_loc_m_gd_only", "experiment.sweeps", "sigma_loc_m, sigma_act_m"},
    {"sigma_loc_m_gd_and_cap", "experiment.sweeps", "sigma_loc_m, sigma_act_m"},
    {experiment::kSweepSigmaAct, "experiment.sweeps", "sigma_act_m, sigma_loc_m"},
    {experiment::kSweepRicianK, "experiment.sweeps", "rician_k_db, sigma_act_m"},
    {experiment::kSweepCsiSnr, "experiment.sweeps", "csi_snr_db, sigma_act_m"},
    {experiment::kSweepBsAntennas, "experiment.sweeps", "bs_antennas, sigma_act_m"},
    {experiment::kSweepNumUavs, "experiment.sweeps", "num_uavs, sigma_act_m"},
    {coevaluation::kSweepBeaconNoise, "experiment.sweeps", "beacon_noise_m, sigma_act_m"},
    {coevaluation::kSweepBeaconOutage, "experiment.sweeps", "beacon_outage, sigma_act_m"},
    {"beacon_noise_m_without_pf_ceres_ura", "experiment.sweeps", "beacon_noise_m, sigma_act_m"},
    // The example drops gd_pf, whose particle count the tiny configuration sets.
    {coevaluation::kSweepBeaconNoise, "coevaluation.algorithms", "gd_ekf, gd_pf, bf"},
};

enum class Verdict { kActs, kRefused, kAccepted, kIgnored, kFailed };

struct Judgement {
  Verdict verdict;
  std::string detail;
};

// `base` with `key` set to `value` (replacing base's own value of it), as --set assignments.
std::vector<std::string> overrides_of(const Assignments& base, const std::string& key = "",
                                      const std::string& value = "") {
  std::vector<std::string> sets;
  for (const auto& [k, v] : base) {
    if (k != key) sets.push_back(k + "=" + v);
  }
  if (!key.empty()) sets.push_back(key + "=" + value);
  return sets;
}

// `base` with `more` set (replacing base's values of those keys).
Assignments with(const Assignments& base, const Assignments& more) {
  Assignments out;
  for (const auto& [k, v] : base) {
    if (std::none_of(more.begin(), more.end(), [&](const auto& m) { return m.first == k; })) out.emplace_back(k, v);
  }
  out.insert(out.end(), more.begin(), more.end());
  return out;
}

// kValues' value, else the example, or the default's text when `base` already sets the example.
std::string value_to_try(const std::string& context, const Assignments& base, const TableKey& k) {
  for (const Value& v : kValues) {
    if (v.context == context && v.key == k.name) return v.value;
  }
  for (const auto& [key, value] : base) {
    if (key == k.name && value == k.example) return k.default_text;
  }
  return k.example;
}

bool is_experiment(const std::string& context) { return context != "eval" && context != "record" && context != "fake"; }

// What setting `k` does in context `c` on the configuration `base`, whose run is `before`; keys
// in `exempt` are only checked to be accepted.
Judgement judge(const Context& c, const Assignments& base, const Outcome& before, const TableKey& k,
                const Exemptions& exempt = kFigureOrLoggingOnly) {
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

// The result files of an experiment folder: every *.csv (trials, summary, positions, traces,
// paths, readings and the extensions'), by name. Not config.ini and the manifest (they echo the
// settings), not report.md (it holds the wall time), not the figures.
std::string experiment_results(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
    if (e.path().extension() == ".csv") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  std::string all;
  for (const fs::path& f : files) all += "== " + f.filename().string() + "\n" + test_support::read_file(f);
  return all;
}

// On tmpfs when there is one: the apps fsync every output (staged_output.h).
fs::path scratch(const std::string& context) {
  const fs::path root = fs::is_directory("/dev/shm") ? fs::path("/dev/shm") : fs::path(::testing::TempDir());
  const fs::path dir = root / ("losmimo-every-setting-" + std::to_string(::getpid())) / context;
  fs::create_directories(dir);
  return dir;
}

Context experiment_context(const std::string& sweep, const Assignments& tiny, const std::string& name = "") {
  // Common to every sweep: one trial, one thread, four UAVs, at most 40 iterations (GD stalls,
  // escapes and converges within them; so does BF, with bf.stall_window = 3 where BF runs), no
  // figures.
  Assignments all = {{"experiment.sweeps", sweep},  {"experiment.trials", "1"}, {"experiment.threads", "1"},
                     {"experiment.plots", "false"}, {"scenario.num_uavs", "4"}, {"placement.max_iterations", "40"},
                     {"gd.stall_window", "3"}};
  // The swarm-size sweep sets the swarm size itself (a --set scenario.num_uavs is refused there).
  if (sweep == experiment::kSweepNumUavs) {
    all.erase(std::remove_if(all.begin(), all.end(), [](const auto& a) { return a.first == "scenario.num_uavs"; }),
              all.end());
  }
  all.insert(all.end(), tiny.begin(), tiny.end());
  Context c;
  c.name = name.empty() ? sweep : name;
  c.tiny = all;
  c.run = [folder = c.name](const std::vector<std::string>& overrides) {
    static const experiment::ExperimentExtensions extensions = [] {
      experiment::ExperimentExtensions e = coevaluation::experiment_extensions();
      for (auto& x : experiment::channel_sweep_extensions()) e.push_back(std::move(x));
      e.push_back(experiment::num_uavs_extension());
      return e;
    }();
    apps::ExperimentOptions o;
    o.overrides = overrides;
    o.out_dir = (scratch(folder) / "run").string();
    o.replace = true;
    std::ostringstream out, err;
    Outcome r;
    r.code = apps::run_experiment_app(o, extensions, out, err);
    r.err = err.str();
    if (r.code == 0) r.result = experiment_results(*o.out_dir);
    return r;
  };
  return c;
}

Context eval_context() {
  Context c;
  c.name = "eval";
  c.run = [](const std::vector<std::string>& overrides) {
    apps::EvalOptions o;
    o.positions_path = std::string(LOSMIMO_SOURCE_DIR) + "/datasets/examples/random_start_16.csv";
    o.overrides = overrides;
    o.csv = true;
    std::ostringstream out, err;
    Outcome r;
    r.code = apps::run_eval_app(o, out, err);
    r.result = out.str();
    r.err = err.str();
    return r;
  };
  return c;
}

std::string vector_text(const Eigen::MatrixXd& m) {
  std::ostringstream s;
  s.precision(17);
  s << m.transpose();
  return s.str();
}

// The rawlog's records as text: every epoch's measurements, beliefs and modes, the final
// positions and the run's end. Not the CONFIG object (it echoes the settings).
std::string mission_records(const std::string& path) {
  rawlog_io::RawlogReader reader = rawlog_io::RawlogReader::open_file(path);
  const rawlog::MissionLog log = rawlog::load_mission_log(reader);
  std::ostringstream s;
  s.precision(17);
  for (const std::uint64_t seed : log.filter_seeds) s << "filter seed " << seed << "\n";
  for (std::size_t e = 0; e < log.epochs.size(); ++e) {
    s << "epoch " << e << " " << (e < log.modes.size() ? log.modes[e] : "") << "\n";
    for (const rawlog::LoggedUavEpoch& u : log.epochs[e]) {
      s << u.reported;
      if (u.truth_m) s << " truth " << vector_text(*u.truth_m);
      if (u.displacement_m) s << " dr " << vector_text(*u.displacement_m);
      if (u.beacon)
        s << " beacon " << u.beacon->range_m << " " << u.beacon->azimuth_rad << " " << u.beacon->elevation_rad;
      if (u.csi) s << " csi " << u.csi->y.transpose();
      for (const auto* b : {&u.filter_belief, &u.refined_belief}) {
        if (*b)
          s << " belief " << vector_text((*b)->mean_m) << " " << vector_text((*b)->cov_m2) << " " << (*b)->degraded;
      }
      s << "\n";
    }
  }
  if (log.final_truth_m) s << "final " << vector_text(*log.final_truth_m) << "\n";
  s << "end " << log.run_end.status << " " << log.run_end.fault_uav << " " << log.run_end.fault << "\n";
  return s.str();
}

Context record_context() {
  Context c;
  c.name = "record";
  c.tiny = {{"scenario.num_uavs", "4"},
            {"placement.max_iterations", "40"},
            {"errors.sigma_act_m", "0.05"},
            {"gd.stall_window", "3"}};
  c.run = [](const std::vector<std::string>& overrides) {
    apps::RecordAppOptions o;
    o.overrides = overrides;
    o.out_path = (scratch("record") / "mission.rawlog").string();
    o.replace = true;
    std::ostringstream out, err;
    Outcome r;
    r.code = apps::run_record_app(o, out, err);
    r.err = err.str();
    // A run ended by a fault (exit 3) has records too.
    if (r.code == 0 || r.code == 3) {
      r.result = mission_records(o.out_path);
      r.code = 0;
    }
    return r;
  };
  return c;
}

const std::vector<Context>& contexts() {
  // Each sweep's one point; nonzero errors where the sweep does not set them, so that the keys
  // that shape the errors act.
  static const std::vector<Context> all = {
      experiment_context(
          experiment::kSweepSigmaLoc,
          {{"experiment.sigma_loc_values_m", "0.05"}, {"errors.sigma_act_m", "0.05"}, {"bf.stall_window", "3"}}),
      // Only GD: the [bf] and [ura] keys are refused.
      experiment_context(
          experiment::kSweepSigmaLoc,
          {{"experiment.sigma_loc_values_m", "0.05"}, {"errors.sigma_act_m", "0.05"}, {"experiment.algorithms", "gd"}},
          "sigma_loc_m_gd_only"),
      // GD and the capacity planner: the [cap] keys act, [bf] and [ura]'s are refused.
      experiment_context(experiment::kSweepSigmaLoc,
                         {{"experiment.sigma_loc_values_m", "0.05"},
                          {"errors.sigma_act_m", "0.05"},
                          {"experiment.algorithms", "gd, cap"}},
                         "sigma_loc_m_gd_and_cap"),
      experiment_context(
          experiment::kSweepSigmaAct,
          {{"experiment.sigma_act_values_m", "0.1"}, {"errors.sigma_loc_m", "0.05"}, {"bf.stall_window", "3"}}),
      experiment_context(experiment::kSweepRicianK, {{"experiment.rician_k_db_values", "30"},
                                                     {"bf.stall_window", "3"},
                                                     {"errors.sigma_loc_m", "0.05"},
                                                     {"errors.sigma_act_m", "0.05"}}),
      experiment_context(experiment::kSweepCsiSnr, {{"experiment.csi_snr_db_values", "40"},
                                                    {"bf.stall_window", "3"},
                                                    {"errors.sigma_loc_m", "0.05"},
                                                    {"errors.sigma_act_m", "0.05"}}),
      experiment_context(experiment::kSweepBsAntennas, {{"experiment.bs_antennas_values", "16"},
                                                        {"bf.stall_window", "3"},
                                                        {"errors.sigma_loc_m", "0.05"},
                                                        {"errors.sigma_act_m", "0.05"}}),
      // Four UAVs on the smallest square array (2 x 2), GD and the capacity planner.
      experiment_context(experiment::kSweepNumUavs, {{"experiment.num_uavs_values", "4"},
                                                     {"experiment.algorithms", "gd, bf, ura, cap"},
                                                     {"bf.stall_window", "3"},
                                                     {"errors.sigma_loc_m", "0.05"},
                                                     {"errors.sigma_act_m", "0.05"}}),
      // ura_ekf needs as many UAVs as BS antennas; a 1 m array spacing makes the UAVs' ideal
      // spacing 5 m (lambda x / (n d)), which they reach within the tiny runs.
      experiment_context(coevaluation::kSweepBeaconNoise, {{"scenario.bs_rows", "2"},
                                                           {"bf.stall_window", "3"},
                                                           {"scenario.bs_cols", "2"},
                                                           {"scenario.bs_spacing_m", "1"},
                                                           {"coevaluation.beacon_noise_values_m", "0.05"},
                                                           {"errors.sigma_act_m", "0.05"},
                                                           {"closed_loop.num_particles", "50"}}),
      // Without gd_pf, gd_ekf_ceres and ura_ekf: their keys are refused. Without centralized too,
      // so that the regimes' target ICN 1 is accepted.
      experiment_context(coevaluation::kSweepBeaconNoise,
                         {{"scenario.bs_rows", "2"},
                          {"scenario.bs_cols", "2"},
                          {"scenario.bs_spacing_m", "1"},
                          {"bf.stall_window", "3"},
                          {"coevaluation.beacon_noise_values_m", "0.05"},
                          {"coevaluation.algorithms", "gd_gauss, gd_ekf, bf"},
                          {"errors.sigma_act_m", "0.05"}},
                         "beacon_noise_m_without_pf_ceres_ura"),
      experiment_context(coevaluation::kSweepBeaconOutage, {{"coevaluation.outage_values", "1"},
                                                            {"coevaluation.outage_first_epoch", "2"},
                                                            {"errors.sigma_act_m", "0.05"}}),
      eval_context(),
      record_context(),
  };
  return all;
}

const Context& context_named(const std::string& name) {
  for (const Context& c : contexts()) {
    if (c.name == name) return c;
  }
  throw std::out_of_range(name);
}

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

// The walker's own checks. A fake app reads a fake table: `gain` scales its result, `noop`'s
// setter does nothing, `refused` is refused naming it, `mute` is refused without naming it.
struct FakeSettings {
  double gain = 1.0;
  double refused = 0.0;
  double mute = 0.0;
};

const common::KeyTable<FakeSettings>& fake_keys() {
  using K = common::Key<FakeSettings>;
  static const common::KeyTable<FakeSettings> table({
      K::real("fake", "gain", &FakeSettings::gain, common::Range::at_least(0.0), "scales the result", "2"),
      K::real(
          "fake", "noop", [](const FakeSettings&) { return 0.0; }, [](FakeSettings&, double) {},
          common::Range::at_least(0.0), "does nothing", "3"),
      K::real("fake", "refused", &FakeSettings::refused, common::Range::at_least(0.0), "refused when set", "1"),
      K::real("fake", "mute", &FakeSettings::mute, common::Range::at_least(0.0), "refused namelessly", "1"),
  });
  return table;
}

Context fake_context() {
  Context c;
  c.name = "fake";
  c.run = [](const std::vector<std::string>& overrides) {
    Outcome r;
    try {
      common::IniConfig config;
      for (const std::string& o : overrides) config.set_override(o);
      config.require_known(fake_keys().known_keys());
      FakeSettings s;
      fake_keys().load(config, s);
      if (s.refused != 0.0) throw common::InputError(config.where("fake", "refused") + ": not used by the fake app");
      if (s.mute != 0.0) throw common::InputError("something is wrong");
      r.code = 0;
      r.result = std::to_string(10.0 * s.gain);
    } catch (const common::InputError& e) {
      r.code = 2;
      r.err = e.what();
    }
    return r;
  };
  return c;
}

Verdict verdict_of(const Context& c, const TableKey& k, const Exemptions& exempt = {}) {
  const Outcome tiny = c.run(overrides_of(c.tiny));
  EXPECT_EQ(tiny.code, 0) << tiny.err;
  return judge(c, c.tiny, tiny, k, exempt).verdict;
}

TEST(EverySettingActsWalker, FakeTable_FlagsTheKeyWhoseSetterDoesNothing) {
  // GIVEN: the fake app and its table's keys as the walker collects them.
  std::vector<TableKey> keys;
  collect(fake_keys(), keys);
  ASSERT_EQ(keys.size(), 4u);
  const Context c = fake_context();
  // THEN: each key gets the verdict its setter and the app earn.
  EXPECT_EQ(verdict_of(c, keys[0]), Verdict::kActs);
  EXPECT_EQ(verdict_of(c, keys[1]), Verdict::kIgnored);
  EXPECT_EQ(verdict_of(c, keys[2]), Verdict::kRefused);
  EXPECT_EQ(verdict_of(c, keys[3]), Verdict::kFailed);  // exit 2, but the message names no key
  // An exempt key is only checked to be accepted; a refused exempt key fails.
  EXPECT_EQ(verdict_of(c, keys[1], {{"fake.noop", {"fake", "no results"}}}), Verdict::kAccepted);
  EXPECT_EQ(verdict_of(c, keys[2], {{"fake.refused", {"fake", "no results"}}}), Verdict::kFailed);
}

TEST(EverySettingActsWalker, RealApp_FlagsAKeyThatLeavesTheResultsAlone) {
  // GIVEN: losmimo-experiment's sigma_loc_m run and [experiment] threads, whose results do not
  // depend on it.
  const Context& c = context_named(experiment::kSweepSigmaLoc);
  const auto threads = std::find_if(every_key().begin(), every_key().end(),
                                    [](const TableKey& k) { return k.name == "experiment.threads"; });
  ASSERT_NE(threads, every_key().end());
  // THEN: without its exemption the walker calls it ignored, with it accepted.
  EXPECT_EQ(verdict_of(c, *threads), Verdict::kIgnored);
  EXPECT_EQ(verdict_of(c, *threads, kFigureOrLoggingOnly), Verdict::kAccepted);
  fs::remove_all(scratch(c.name));
}

TEST(EverySettingActsWalker, ConfigFile_MayHoldKeysTheAppDoesNotUse) {
  // GIVEN: a config file for every app (an experiment's keys and [gd]) and losmimo-eval.
  const fs::path ini = scratch("config_file") / "shared.ini";
  std::ofstream(ini) << "[experiment]\ntrials = 3\n[gd]\nstep = 0.1\n";
  apps::EvalOptions o;
  o.positions_path = std::string(LOSMIMO_SOURCE_DIR) + "/datasets/examples/random_start_16.csv";
  o.config_path = ini.string();
  std::ostringstream out, err;
  // THEN: the file is accepted; the same key given with --set is refused, naming it and why.
  EXPECT_EQ(apps::run_eval_app(o, out, err), 0) << err.str();
  o.overrides = {"gd.step=0.2"};
  std::ostringstream err2;
  EXPECT_EQ(apps::run_eval_app(o, out, err2), 2);
  EXPECT_NE(err2.str().find("--set: [gd] step: not used by losmimo-eval: it evaluates given positions"),
            std::string::npos)
      << err2.str();
  fs::remove_all(scratch("config_file"));
}

}  // namespace
}  // namespace losmimo
