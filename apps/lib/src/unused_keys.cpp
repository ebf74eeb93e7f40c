#include "losmimo/apps/lib/unused_keys.h"

#include "losmimo/placement/planner_registry.h"

#include <algorithm>

#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/common/text.h"

namespace losmimo::apps {

namespace {

const std::string kEval = "losmimo-eval";
const std::string kRecord = "losmimo-record";
// losmimo-experiment's sweeps: built-in, channel (experiment/channel_sweeps.h), co-evaluation
// (coevaluation/coevaluation.h).
const std::string kSigmaLoc = "sigma_loc_m";
const std::string kSigmaAct = "sigma_act_m";
const std::string kRicianK = "rician_k_db";
const std::string kCsiSnr = "csi_snr_db";
const std::string kBsAntennas = "bs_antennas";
const std::string kBeaconNoise = "beacon_noise_m";
const std::string kBeaconOutage = "beacon_outage";
const std::string kMisalignment = "bs_misalignment_rad";
const std::string kNumUavs = "num_uavs";

// The sweeps other than `keep`.
std::vector<std::string> sweeps_but(const std::vector<std::string>& keep) {
  std::vector<std::string> out;
  for (const std::string& s :
       {kSigmaLoc, kSigmaAct, kRicianK, kCsiSnr, kBsAntennas, kBeaconNoise, kBeaconOutage, kMisalignment, kNumUavs}) {
    if (std::find(keep.begin(), keep.end(), s) == keep.end()) out.push_back(s);
  }
  return out;
}

std::vector<std::string> plus(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// The iterative planners owning `section`, in registration order.
std::vector<std::string> owners(const std::string& section) {
  std::vector<std::string> out;
  for (const std::string& name : placement::planner_names()) {
    const placement::PlannerEntry& e = placement::planner_entry(name);
    if (e.direct()) continue;
    if (std::find(e.sections.begin(), e.sections.end(), section) != e.sections.end()) out.push_back(name);
  }
  return out;
}

// "a", "a or b", "a, b or c".
std::string either(const std::vector<std::string>& names) {
  if (names.size() < 2) return common::join(names);
  return common::join(std::vector<std::string>(names.begin(), names.end() - 1)) + " or " + names.back();
}

bool key_matches(const std::string& pattern, const std::string& section, const std::string& key) {
  if (pattern == section + ".*") return true;
  return pattern == section + "." + key;
}

}  // namespace

std::vector<std::string> planner_sections() {
  std::vector<std::string> sections;
  for (const std::string& name : placement::planner_names()) {
    for (const std::string& s : placement::planner_entry(name).sections) {
      if (std::find(sections.begin(), sections.end(), s) == sections.end()) sections.push_back(s);
    }
  }
  return sections;
}

std::string no_planner_condition(const std::string& section) {
  return "no " + either(owners(section)) + " in [experiment] algorithms";
}

namespace {
// The planners' own sections: read by the built-in and channel sweeps only when a planner owning
// them runs (from the planner registry).
std::vector<UnusedKeys> planner_section_entries() {
  std::vector<UnusedKeys> entries;
  for (const std::string& section : planner_sections()) {
    entries.push_back({{section + ".*"},
                       {no_planner_condition(section)},
                       "the built-in and channel sweeps read [" + section +
                           "] only when [experiment] algorithms lists " + either(owners(section))});
  }
  return entries;
}
}  // namespace

const std::vector<UnusedKeys>& unused_keys() {
  static const std::vector<UnusedKeys> table = [] {
    std::vector<UnusedKeys> t = {
        // losmimo-eval: the metrics of given positions in the scenario.
        {{"scenario.num_uavs", "scenario.cube_side_m", "scenario.cube_center_x_m", "scenario.cube_center_y_m",
          "scenario.cube_center_z_m"},
         {kEval},
         "the UAVs are the positions file's"},
        {{"errors.*", "placement.*", "gd.*", "bf.*", "ura.*", "cap.*"},
         {kEval},
         "it evaluates given positions: no placement runs"},
        {{"channel.coherence_iterations", "channel.fading_eval_draws"},
         {kEval, kRecord, kBeaconNoise, kBeaconOutage, kMisalignment},
         "it models the LoS channel with perfect CSI (no fading to draw)"},
        {{"experiment.*"}, {kEval, kRecord}, "no experiment runs (an experiment's --config file is accepted as it is)"},
        {{"coevaluation.*"},
         plus({kRecord}, sweeps_but({kBeaconNoise, kBeaconOutage, kMisalignment})),
         "read by the co-evaluation sweeps beacon_noise_m, beacon_outage and bs_misalignment_rad only"},
        {{"coevaluation.beacon_noise_values_m", "coevaluation.algorithms"},
         {kBeaconOutage, kMisalignment},
         "read by the beacon_noise_m sweep only"},
        {{"coevaluation.ura_variant"}, {kBeaconOutage}, "the outage sweep runs gd's closed loop only (no URA)"},
        {{"coevaluation.outage_values", "coevaluation.outage_algorithms", "coevaluation.outage_first_epoch",
          "coevaluation.outage_epochs", "coevaluation.outage_degraded_after_epochs",
          "coevaluation.outage_beacon_noise_m"},
         {kBeaconNoise, kMisalignment},
         "read by the beacon_outage sweep only"},
        {{"coevaluation.misalignment_values_rad", "coevaluation.misalignment_algorithms",
          "coevaluation.misalignment_beacon_noise_m"},
         {kBeaconNoise, kBeaconOutage},
         "read by the bs_misalignment_rad sweep only"},
        // The co-evaluation's shared [closed_loop] keys (the experiment knows no other).
        {{"closed_loop.*"},
         sweeps_but({kBeaconNoise, kBeaconOutage, kMisalignment}),
         "the closed loop runs in losmimo-record and the co-evaluation sweeps only"},
        {{"closed_loop.bs_azimuth_bias_rad"},
         {kMisalignment},
         "the sweep sets it (coevaluation.misalignment_values_rad)"},
        // The sweep points of each sweep, and the keys a sweep replaces by its point.
        {{"experiment.sigma_loc_values_m"}, sweeps_but({kSigmaLoc}), "the sigma_loc_m sweep's points"},
        {{"experiment.sigma_act_values_m"}, sweeps_but({kSigmaAct}), "the sigma_act_m sweep's points"},
        {{"experiment.rician_k_db_values"}, sweeps_but({kRicianK}), "the rician_k_db sweep's points"},
        {{"experiment.csi_snr_db_values"}, sweeps_but({kCsiSnr}), "the csi_snr_db sweep's points"},
        {{"experiment.bs_antennas_values"}, sweeps_but({kBsAntennas}), "the bs_antennas sweep's points"},
        {{"experiment.num_uavs_values", "experiment.num_uavs_array", "experiment.num_uavs_cap_max"},
         sweeps_but({kNumUavs}),
         "the num_uavs sweep's points and array"},
        {{"scenario.num_uavs"}, {kNumUavs}, "the sweep sets it (experiment.num_uavs_values)"},
        {{"scenario.bs_rows", "scenario.bs_cols"},
         {"num_uavs_array = square"},
         "the num_uavs sweep sets the array (n x n, the smallest n with n^2 >= Nr)"},
        {{"experiment.num_uavs_cap_max"},
         {no_planner_condition("cap"), "no num_uavs point above num_uavs_cap_max"},
         "cap runs at every point of the num_uavs sweep (or not at all)"},
        {{"errors.sigma_loc_m"}, {kSigmaLoc}, "the sweep sets it (experiment.sigma_loc_values_m)"},
        {{"errors.sigma_act_m"}, {kSigmaAct}, "the sweep sets it (experiment.sigma_act_values_m)"},
        {{"channel.rician_k_db"}, {kRicianK}, "the sweep sets it (experiment.rician_k_db_values)"},
        {{"channel.csi_snr_db"}, {kCsiSnr}, "the sweep sets it (experiment.csi_snr_db_values)"},
        {{"scenario.bs_rows", "scenario.bs_cols"},
         {kBsAntennas},
         "the sweep sets the array (experiment.bs_antennas_values)"},
        {{"errors.sigma_loc_m"},
         {kBeaconNoise, kBeaconOutage, kMisalignment, kRecord},
         "the position estimates are the filters' (gd_gauss's sigma_loc_m is the point's beacon noise)"},
        {{"errors.sigma_loc_common_m"},
         {kBeaconOutage, kRecord},
         "the position estimates are the filters', not a Gaussian localization error"},
        {{"errors.sigma_loc_common_m"},
         {"no gauss estimator in [coevaluation] algorithms",
          "no gauss estimator in [coevaluation] "
          "misalignment_algorithms"},
         "in the co-evaluation only the gauss estimator (gd_gauss) reads it; the matched rows set their own"},
        {{"errors.loc_error"},
         {kBeaconOutage, kRecord},
         "the position estimates are the filters', not a Gaussian localization error"},
        // losmimo-experiment's keys of the built-in sweeps.
        {{"experiment.algorithms"},
         {kBeaconNoise, kBeaconOutage, kMisalignment},
         "the co-evaluation sweeps run [coevaluation] algorithms, outage_algorithms and misalignment_algorithms"},
        {{"experiment.fig1_trials", "experiment.paths", "experiment.readings", "experiment.reading_trials"},
         {kRicianK, kCsiSnr, kBsAntennas, kBeaconNoise, kBeaconOutage, kMisalignment, kNumUavs},
         "Fig 1's traces, the path figure and the readings belong to the built-in sweeps sigma_loc_m and sigma_act_m"},
        // Parts of a run that its other settings switch off.
        {{"placement.milestone_distance_includes_probes"}, {no_planner_condition("bf")}, "only BF flies probes"},
        {{"channel.coherence_iterations", "channel.fading_eval_draws"},
         {kLosChannel},
         "without fading there is no scattered component to draw (set a finite [channel] rician_k_db)"},
        {{"experiment.reading_trials"}, {kNoReadings}, "the trials of [experiment] readings, which has none"},
        {{"closed_loop.num_particles"}, {kEkfFilter}, "the particle filter's size (set [closed_loop] filter = pf)"},
        {{"closed_loop.window_epochs", "closed_loop.use_csi"},
         {kNoRefinement},
         "the Ceres refinement's settings (set [closed_loop] refine = true)"},
        // The co-evaluation's algorithms that some keys serve alone (coevaluation/extensions.cpp).
        {{"closed_loop.num_particles"},
         {"no pf estimator in [coevaluation] algorithms", "no pf estimator in [coevaluation] outage_algorithms",
          "no pf estimator in [coevaluation] misalignment_algorithms"},
         "the particle filter's size: only the pf estimator (gd_pf) runs one"},
        {{"closed_loop.window_epochs", "closed_loop.use_csi"},
         {"no ekf_ceres estimator in [coevaluation] algorithms",
          "no ekf_ceres estimator in [coevaluation] outage_algorithms",
          "no ekf_ceres estimator in [coevaluation] misalignment_algorithms"},
         "the refinement's settings: only the ekf_ceres estimator (gd_ekf_ceres) refines"},
        {{"ura.*"},
         {"no URA planner in [coevaluation] algorithms", "no URA planner in [coevaluation] misalignment_algorithms"},
         "the URA's settings: only a URA row (ura_ekf) runs one"},
        {{"coevaluation.ura_variant"},
         {"no ura_ekf in [coevaluation] algorithms", "no ura_ekf in [coevaluation] misalignment_algorithms"},
         "the URA variant of ura_ekf"},
        {{"cap.*"},
         {"no cap planner in [coevaluation] algorithms", "no cap planner in [coevaluation] misalignment_algorithms"},
         "the capacity planner's settings: only a cap row (cap_ekf) runs it"},
        {{"cap.*"}, {kRecord, kBeaconOutage}, "no capacity planner runs (the closed loop plans with GD and BF)"},
        // The closed loop (losmimo-record, and every beacon_outage row) plans with GD, and BF for a
        // UAV whose belief is degraded (fusion/closed_loop.h).
        {{"ura.*"}, {kRecord, kBeaconOutage}, "no URA runs (the closed loop plans with GD and BF)"},
        {{"gd.escape_half_grid", "gd.escape_uavs"},
         {kRecord, kBeaconOutage},
         "the closed loop's escape searches one lateral period of one UAV per stall (no grid)"},
        {{"bf.escape", "bf.stall_window", "bf.stall_min_decrease", "bf.probe_actuation"},
         {kRecord, kBeaconOutage},
         "the closed loop's BF fallback reads [bf] step, decay, contraction and min_step_m only"},
        {{"bf.target_icn", "bf.max_iterations"}, {kBeaconOutage}, "the sweep has no BF rows"},
        {{"bf.target_icn", "bf.max_iterations"},
         {kRecord},
         "the mission's BF is the closed loop's fallback: the run stops by the closed loop's (GD's) stop rule"},
        {{"placement.stop_on"},
         {kRecord, kBeaconOutage},
         "the closed loop's planner has no believed positions for the stop test: its runs stop on the measured "
         "channel's ICN"},
        {{"placement.distance", "placement.milestone_distance_includes_probes"},
         {kRecord},
         "the rawlog records positions and measurements, not distances"},
    };
    const std::vector<UnusedKeys> planners = planner_section_entries();
    t.insert(t.end(), planners.begin(), planners.end());
    return t;
  }();
  return table;
}

std::string unused_keys_markdown() {
  const auto join = [](const std::vector<std::string>& items, const std::string& quote) {
    return common::join_with(items, [&quote](const std::string& i) { return quote + i + quote; });
  };
  std::string out = "| keys | not used by | why |\n|---|---|---|\n";
  for (const UnusedKeys& e : unused_keys()) {
    out += "| " + join(e.keys, "`") + " | " + join(e.users, "") + " | " + e.reason + " |\n";
  }
  return out;
}

std::vector<KeyUser> experiment_users(const ExperimentUse& use) {
  const auto runs = [&use](const std::vector<std::string>& names) {
    return std::any_of(names.begin(), names.end(), [&use](const std::string& n) {
      return std::find(use.algorithms.begin(), use.algorithms.end(), n) != use.algorithms.end();
    });
  };
  std::vector<KeyUser> users;
  for (const std::string& sweep : use.sweeps) {
    KeyUser u{sweep, {}};
    // [experiment] algorithms: the built-in and channel sweeps' planners.
    if (sweep != kBeaconNoise && sweep != kBeaconOutage) {
      for (const std::string& section : planner_sections()) {
        if (!runs(owners(section))) u.conditions.push_back(no_planner_condition(section));
      }
    }
    if (!use.fading && sweep != kRicianK) u.conditions.push_back(kLosChannel);
    if (!use.readings) u.conditions.push_back(kNoReadings);
    if (const auto more = use.sweep_conditions.find(sweep); more != use.sweep_conditions.end()) {
      u.conditions.insert(u.conditions.end(), more->second.begin(), more->second.end());
    }
    users.push_back(std::move(u));
  }
  return users;
}

void refuse_unused_overrides(const common::IniConfig& config, const std::vector<std::string>& overrides,
                             const std::vector<KeyUser>& users) {
  if (users.empty()) return;
  for (const std::string& assignment : overrides) {
    // Already applied by IniConfig::set_override, which checked the form "section.key=value".
    const std::size_t dot = assignment.find('.');
    const std::size_t eq = assignment.find('=');
    if (dot == std::string::npos || eq == std::string::npos || dot > eq) continue;
    const std::string section = common::trim(assignment.substr(0, dot));
    const std::string key = common::trim(assignment.substr(dot + 1, eq - dot - 1));
    // Unused when every user is listed, by its name or a condition, by an entry of the key.
    std::vector<std::string> reasons;
    bool used = false;
    for (const KeyUser& user : users) {
      bool unused_here = false;
      for (const UnusedKeys& entry : unused_keys()) {
        const bool listed = std::any_of(entry.keys.begin(), entry.keys.end(),
                                        [&](const std::string& p) { return key_matches(p, section, key); });
        const auto names_user = [&](const std::string& u) {
          return u == user.name ||
                 std::find(user.conditions.begin(), user.conditions.end(), u) != user.conditions.end();
        };
        if (!listed || std::none_of(entry.users.begin(), entry.users.end(), names_user)) continue;
        unused_here = true;
        if (std::find(reasons.begin(), reasons.end(), entry.reason) == reasons.end()) reasons.push_back(entry.reason);
      }
      if (!unused_here) used = true;
    }
    if (used) continue;
    const std::string who = common::join_with(
        users, [](const KeyUser& u) { return u.name.rfind("losmimo-", 0) == 0 ? u.name : "the sweep " + u.name; });
    const std::string why = common::join(reasons, "; ");
    throw common::InputError(config.where(section, key) + ": not used by " + who + ": " + why);
  }
}

}  // namespace losmimo::apps
