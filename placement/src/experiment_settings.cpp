#include "losmimo/placement/experiment_settings.h"

#include <iomanip>
#include <sstream>

namespace losmimo::placement {

namespace {
constexpr Algorithm kAllAlgorithms[] = {Algorithm::kRandom, Algorithm::kGd, Algorithm::kBf,
                                        Algorithm::kUra, Algorithm::kUraLattice};

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> items;
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    const std::size_t b = item.find_first_not_of(" \t");
    const std::size_t e = item.find_last_not_of(" \t");
    items.push_back(b == std::string::npos ? std::string() : item.substr(b, e - b + 1));
  }
  return items;
}

std::vector<double> parse_sigma_list(const IniConfig& cfg, const std::string& key,
                                     const std::vector<double>& fallback) {
  if (!cfg.has("experiment", key)) return fallback;
  const std::string where = cfg.where("experiment", key);
  std::vector<double> values;
  for (const std::string& item : split_list(cfg.get_string("experiment", key, ""))) {
    const double v = parse_double(item, where);
    if (v < 0.0) throw InputError(where + ": " + item + " must be >= 0");
    values.push_back(v);
  }
  if (values.empty()) throw InputError(where + ": needs at least one value");
  return values;
}

std::string join(const std::vector<double>& v) {
  std::ostringstream o;
  o << std::setprecision(17);
  for (std::size_t i = 0; i < v.size(); ++i) o << (i ? ", " : "") << v[i];
  return o.str();
}
}  // namespace

std::string to_string(Algorithm a) {
  switch (a) {
    case Algorithm::kRandom: return "random";
    case Algorithm::kGd: return "gd";
    case Algorithm::kBf: return "bf";
    case Algorithm::kUra: return "ura";
    case Algorithm::kUraLattice: return "ura_lattice";
  }
  return "?";
}

Algorithm algorithm_from_string(const std::string& name, const std::string& where) {
  for (const Algorithm a : kAllAlgorithms) {
    if (to_string(a) == name) return a;
  }
  throw InputError(where + ": unknown algorithm '" + name + "' (known: random, gd, bf, ura, ura_lattice)");
}

std::string to_string(Sweep s) { return s == Sweep::kSigmaLoc ? "sigma_loc_m" : "sigma_act_m"; }

std::map<std::string, std::set<std::string>> experiment_config_keys() {
  auto keys = placement_config_keys();
  keys["experiment"] = {"trials", "seed", "sigma_loc_values_m", "sigma_act_values_m", "algorithms",
                        "fig1_trials", "threads", "plots"};
  return keys;
}

ExperimentSettings load_experiment_settings(const IniConfig& cfg) {
  cfg.require_known(experiment_config_keys());
  ExperimentSettings s;
  s.placement = load_placement_settings(cfg);
  s.trials = static_cast<int>(cfg.get_integer("experiment", "trials", s.trials, 1, 1'000'000));
  s.seed = static_cast<std::uint64_t>(
      cfg.get_integer("experiment", "seed", static_cast<long long>(s.seed), 0, (1LL << 62)));
  s.sigma_loc_values_m = parse_sigma_list(cfg, "sigma_loc_values_m", s.sigma_loc_values_m);
  s.sigma_act_values_m = parse_sigma_list(cfg, "sigma_act_values_m", s.sigma_act_values_m);
  if (cfg.has("experiment", "algorithms")) {
    const std::string where = cfg.where("experiment", "algorithms");
    s.algorithms.clear();
    for (const std::string& name : split_list(cfg.get_string("experiment", "algorithms", ""))) {
      const Algorithm a = algorithm_from_string(name, where);
      for (const Algorithm seen : s.algorithms) {
        if (seen == a) throw InputError(where + ": algorithm '" + name + "' listed twice");
      }
      s.algorithms.push_back(a);
    }
    if (s.algorithms.empty()) throw InputError(where + ": needs at least one algorithm");
  }
  const bool has_ura = [&] {
    for (const Algorithm a : s.algorithms) {
      if (a == Algorithm::kUra || a == Algorithm::kUraLattice) return true;
    }
    return false;
  }();
  if (has_ura && s.placement.scenario.num_uavs != s.placement.scenario.num_bs_antennas()) {
    throw InputError("[experiment] algorithms: ura needs scenario.num_uavs = bs_rows * bs_cols (" +
                     std::to_string(s.placement.scenario.num_bs_antennas()) + "), got " +
                     std::to_string(s.placement.scenario.num_uavs));
  }
  s.fig1_trials = static_cast<int>(cfg.get_integer("experiment", "fig1_trials", s.fig1_trials, 0, 10000));
  s.threads = static_cast<int>(cfg.get_integer("experiment", "threads", s.threads, 0, 1024));
  s.plots = cfg.get_bool("experiment", "plots", s.plots);
  return s;
}

std::string to_ini(const ExperimentSettings& s) {
  std::ostringstream o;
  o << to_ini(s.placement) << "\n[experiment]\ntrials = " << s.trials << "\nseed = " << s.seed
    << "\nsigma_loc_values_m = " << join(s.sigma_loc_values_m)
    << "\nsigma_act_values_m = " << join(s.sigma_act_values_m) << "\nalgorithms = ";
  for (std::size_t i = 0; i < s.algorithms.size(); ++i) o << (i ? ", " : "") << to_string(s.algorithms[i]);
  o << "\nfig1_trials = " << s.fig1_trials << "\nthreads = " << s.threads
    << "\nplots = " << (s.plots ? "true" : "false") << "\n";
  return o.str();
}

std::uint64_t derive_seed(std::uint64_t base, std::initializer_list<std::uint64_t> path) {
  const auto mix = [](std::uint64_t z) {
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  };
  std::uint64_t h = mix(base);
  for (const std::uint64_t p : path) h = mix(h ^ mix(p + 0x632be59bd9b4e019ULL));
  return h;
}

}  // namespace losmimo::placement
