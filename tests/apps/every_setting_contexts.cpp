// The settings walker's contexts (every_setting_walker.h): each app, and losmimo-experiment with
// each sweep, with its tiny configuration and how its results are read.
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "apps/every_setting_walker.h"
#include "losmimo/apps/lib/eval_app.h"
#include "losmimo/apps/lib/experiment_app.h"
#include "losmimo/apps/lib/record_app.h"
#include "losmimo/fusion/coevaluation/coevaluation.h"
#include "losmimo/fusion/coevaluation/extensions.h"
#include "losmimo/placement/experiment/channel_sweeps.h"
#include "losmimo/placement/experiment/num_uavs_sweep.h"
#include "losmimo/fusion/rawlog/mission/log.h"
#include "support/files.h"

namespace losmimo::every_setting {

namespace fs = std::filesystem;

namespace {

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

}  // namespace

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
      // The misalignment sweep's default rows (the Gaussian model and its matched forms, gd_ekf)
      // at one misalignment of ~1 mrad.
      experiment_context(coevaluation::kSweepMisalignment, {{"scenario.bs_rows", "2"},
                                                            {"scenario.bs_cols", "2"},
                                                            {"scenario.bs_spacing_m", "1"},
                                                            {"bf.stall_window", "3"},
                                                            {"coevaluation.misalignment_values_rad", "0.0009765625"},
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

}  // namespace losmimo::every_setting
