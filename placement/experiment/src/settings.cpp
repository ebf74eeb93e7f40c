#include "losmimo/common/format.h"
#include "losmimo/common/ini_config.h"
#include "losmimo/experiment/settings.h"

#include <algorithm>
#include <iomanip>
#include <sstream>

#include "losmimo/experiment/extension.h"
#include "losmimo/placement/swarm.h"

namespace losmimo::experiment {

namespace {
constexpr Algorithm kAllAlgorithms[] = {Algorithm::kRandom, Algorithm::kGd, Algorithm::kBf,
                                        Algorithm::kUra, Algorithm::kUraLattice,
                                        Algorithm::kUraLatticeExact};

std::vector<double> parse_sigma_list(const common::IniConfig& cfg, const std::string& key,
                                     const std::vector<double>& fallback) {
  if (!cfg.has("experiment", key)) return fallback;
  const std::string where = cfg.where("experiment", key);
  std::vector<double> values;
  for (const std::string& item : common::split_list(cfg.get_string("experiment", key, ""))) {
    const double v = common::parse_double(item, where);
    if (!(v >= 0.0 && v <= placement::kMaxErrorSigma_m)) throw common::InputError(where + ": " + item + " must be in [0, 1e3] m");
    values.push_back(v);
  }
  if (values.empty()) throw common::InputError(where + ": needs at least one value");
  return values;
}

std::string join(const std::vector<double>& v) {
  std::ostringstream o;
  for (std::size_t i = 0; i < v.size(); ++i) o << (i ? ", " : "") << common::format_double(v[i]);
  return o.str();
}

const ExperimentExtension* find_extension(const ExperimentExtensions& extensions, const std::string& sweep) {
  for (const ExperimentExtension& e : extensions) {
    if (e.sweep == sweep) return &e;
  }
  return nullptr;
}
}  // namespace

std::string to_string(Algorithm a) {
  switch (a) {
    case Algorithm::kRandom: return "random";
    case Algorithm::kGd: return "gd";
    case Algorithm::kBf: return "bf";
    case Algorithm::kUra: return "ura";
    case Algorithm::kUraLattice: return "ura_lattice";
    case Algorithm::kUraLatticeExact: return "ura_lattice_exact";
  }
  return "?";
}

Algorithm algorithm_from_string(const std::string& name, const std::string& where) {
  for (const Algorithm a : kAllAlgorithms) {
    if (to_string(a) == name) return a;
  }
  throw common::InputError(where + ": unknown algorithm '" + name + "' (known: random, gd, bf, ura, ura_lattice, ura_lattice_exact)");
}

const SweepPoints* ExperimentSettings::sweep(const std::string& name) const {
  for (const SweepPoints& s : sweeps) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

std::map<std::string, std::set<std::string>> experiment_config_keys(const ExperimentExtensions& extensions) {
  auto keys = placement::placement_config_keys();
  keys["experiment"] = {"trials",     "seed",        "sweeps",  "sigma_loc_values_m", "sigma_act_values_m",
                        "algorithms", "fig1_trials", "threads", "plots"};
  for (const ExperimentExtension& e : extensions) {
    for (const auto& [section, section_keys] : e.config_keys) keys[section].insert(section_keys.begin(), section_keys.end());
  }
  return keys;
}

ExperimentSettings load_experiment_settings(const common::IniConfig& cfg, const ExperimentExtensions& extensions) {
  cfg.require_known(experiment_config_keys(extensions));
  ExperimentSettings s;
  s.config = cfg;
  s.placement = placement::load_placement_settings(cfg);
  s.trials = static_cast<int>(cfg.get_integer("experiment", "trials", s.trials, 1, 1'000'000));
  s.seed = static_cast<std::uint64_t>(
      cfg.get_integer("experiment", "seed", static_cast<long long>(s.seed), 0, (1LL << 62)));
  s.fig1_trials = static_cast<int>(cfg.get_integer("experiment", "fig1_trials", s.fig1_trials, 0, 10000));
  s.threads = static_cast<int>(cfg.get_integer("experiment", "threads", s.threads, 0, 1024));
  s.plots = cfg.get_bool("experiment", "plots", s.plots);

  if (cfg.has("experiment", "algorithms")) {
    const std::string where = cfg.where("experiment", "algorithms");
    s.algorithms.clear();
    for (const std::string& name : common::split_list(cfg.get_string("experiment", "algorithms", ""))) {
      const Algorithm a = algorithm_from_string(name, where);
      for (const Algorithm seen : s.algorithms) {
        if (seen == a) throw common::InputError(where + ": algorithm '" + name + "' listed twice");
      }
      s.algorithms.push_back(a);
    }
    if (s.algorithms.empty()) throw common::InputError(where + ": needs at least one algorithm");
  }

  const std::vector<double> loc = parse_sigma_list(cfg, "sigma_loc_values_m", s.sweeps[0].values);
  const std::vector<double> act = parse_sigma_list(cfg, "sigma_act_values_m", s.sweeps[1].values);
  std::vector<std::string> names = {kSweepSigmaLoc, kSweepSigmaAct};
  if (cfg.has("experiment", "sweeps")) names = common::split_list(cfg.get_string("experiment", "sweeps", ""));
  const std::string where = cfg.where("experiment", "sweeps");
  if (names.empty()) throw common::InputError(where + ": needs at least one sweep");
  s.sweeps.clear();
  for (const std::string& name : names) {
    if (s.sweep(name)) throw common::InputError(where + ": sweep '" + name + "' listed twice");
    if (name == kSweepSigmaLoc) {
      s.sweeps.push_back({name, loc});
    } else if (name == kSweepSigmaAct) {
      s.sweeps.push_back({name, act});
    } else if (find_extension(extensions, name)) {
      s.sweeps.push_back({name, {}});  // values below, once the settings are complete
    } else {
      std::string known = kSweepSigmaLoc + ", " + kSweepSigmaAct;
      for (const ExperimentExtension& e : extensions) known += ", " + e.sweep;
      throw common::InputError(where + ": unknown sweep '" + name + "' (known: " + known + ")");
    }
  }

  const bool builtin = s.sweep(kSweepSigmaLoc) || s.sweep(kSweepSigmaAct);
  const bool has_ura = [&] {
    for (const Algorithm a : s.algorithms) {
      if (a == Algorithm::kUra || a == Algorithm::kUraLattice || a == Algorithm::kUraLatticeExact) return true;
    }
    return false;
  }();
  if (builtin && has_ura && s.placement.scenario.num_uavs != s.placement.scenario.num_bs_antennas()) {
    throw common::InputError("[experiment] algorithms: ura needs scenario.num_uavs = bs_rows * bs_cols (" +
                     std::to_string(s.placement.scenario.num_bs_antennas()) + "), got " +
                     std::to_string(s.placement.scenario.num_uavs));
  }
  for (SweepPoints& sweep : s.sweeps) {
    if (const ExperimentExtension* e = find_extension(extensions, sweep.name)) {
      sweep.values = e->load_values(s);
      if (sweep.values.empty()) throw common::InputError("sweep " + sweep.name + ": no sweep points");
    }
  }
  return s;
}

std::string to_ini(const ExperimentSettings& s) {
  // The whole config as read (extension sections included), with [experiment] and the
  // placement sections as resolved (defaults filled in).
  common::IniConfig resolved = s.config;
  const common::IniConfig placement = common::IniConfig::from_string(to_ini(s.placement));
  for (const auto& [section, keys] : placement::placement_config_keys()) {
    for (const std::string& key : keys) {
      if (placement.has(section, key)) resolved.set(section, key, placement.get_string(section, key, ""));
    }
  }
  std::ostringstream alg;
  for (std::size_t i = 0; i < s.algorithms.size(); ++i) alg << (i ? ", " : "") << to_string(s.algorithms[i]);
  std::ostringstream sweeps;
  for (std::size_t i = 0; i < s.sweeps.size(); ++i) sweeps << (i ? ", " : "") << s.sweeps[i].name;
  resolved.set("experiment", "trials", std::to_string(s.trials));
  resolved.set("experiment", "seed", std::to_string(s.seed));
  resolved.set("experiment", "sweeps", sweeps.str());
  for (const SweepPoints& sp : s.sweeps) {
    if (sp.name == kSweepSigmaLoc) resolved.set("experiment", "sigma_loc_values_m", join(sp.values));
    if (sp.name == kSweepSigmaAct) resolved.set("experiment", "sigma_act_values_m", join(sp.values));
  }
  resolved.set("experiment", "algorithms", alg.str());
  resolved.set("experiment", "fig1_trials", std::to_string(s.fig1_trials));
  resolved.set("experiment", "threads", std::to_string(s.threads));
  resolved.set("experiment", "plots", s.plots ? "true" : "false");
  return resolved.to_string();
}

std::vector<std::string> extra_metric_names(const ExperimentSettings& settings,
                                            const ExperimentExtensions& extensions) {
  std::vector<std::string> names;
  for (const SweepPoints& sp : settings.sweeps) {
    if (const ExperimentExtension* e = find_extension(extensions, sp.name)) {
      for (const std::string& m : e->extra_metrics) {
        if (std::find(names.begin(), names.end(), m) == names.end()) names.push_back(m);
      }
    }
  }
  return names;
}

}  // namespace losmimo::experiment
