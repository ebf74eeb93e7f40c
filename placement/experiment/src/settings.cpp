#include "losmimo/placement/experiment/settings.h"
#include "losmimo/placement/common/text.h"

#include <algorithm>
#include <cctype>
#include <sstream>
#include <stdexcept>

#include "losmimo/placement/experiment/capacity_claims.h"
#include "losmimo/placement/experiment/extension.h"
#include "losmimo/placement/experiment/report.h"
#include "losmimo/placement/swarm.h"

namespace losmimo::experiment {

namespace {
const ExperimentExtension* find_extension(const ExperimentExtensions& extensions, const std::string& sweep) {
  for (const ExperimentExtension& e : extensions) {
    if (e.sweep == sweep) return &e;
  }
  return nullptr;
}

// The planners [experiment] algorithms may list: the iterative ones, in registration order.
std::vector<std::string> iterative_planner_names() {
  std::vector<std::string> names;
  for (const std::string& name : placement::planner_names()) {
    if (!placement::planner_entry(name).direct()) names.push_back(name);
  }
  return names;
}
}  // namespace

Algorithm algorithm_from_string(const std::string& name, const std::string& where) {
  const placement::PlannerEntry* e = placement::find_planner(name);
  if (e && e->direct()) {
    throw common::InputError(where + ": '" + name +
                             "' computes its placement at once: it runs in [coevaluation] algorithms only");
  }
  if (!e) {
    throw common::InputError(where + ": unknown algorithm '" + name +
                             "' (known: " + common::join(iterative_planner_names()) + ")");
  }
  return Algorithm(name);
}

std::string ReadingSpec::text() const {
  std::string out = name + ":";
  for (std::size_t i = 0; i < assignments.size(); ++i) {
    out += (i ? ", " : " ") + assignments[i].first + "=" + assignments[i].second;
  }
  return out;
}

const SweepPoints* ExperimentSettings::sweep(const std::string& name) const {
  for (const SweepPoints& s : sweeps) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

namespace {

// The values of a built-in sweep (sigma_loc_m, sigma_act_m) in s.sweeps.
template <typename Settings>
auto& builtin_values(Settings& s, const std::string& name) {
  for (auto& sweep : s.sweeps) {
    if (sweep.name == name) return sweep.values;
  }
  throw std::logic_error("no " + name + " sweep");
}

bool valid_reading_name(const std::string& name) {
  if (name.empty()) return false;
  for (const char c : name) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.')) return false;
  }
  return true;
}

// "name: section.key=value, ... | name: ..." (an empty text: none; ';' would start an INI comment). The keys are
// checked when the readings are applied (load_experiment_settings).
std::vector<ReadingSpec> parse_readings(const std::string& text, const std::string& where) {
  std::vector<ReadingSpec> readings;
  if (common::trim(text).empty()) return readings;
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, '|')) {
    if (common::trim(item).empty()) throw common::InputError(where + ": an empty reading in '" + text + "'");
    const std::size_t colon = item.find(':');
    if (colon == std::string::npos) {
      throw common::InputError(where + ": reading '" + common::trim(item) + "': expected name: section.key=value, ...");
    }
    ReadingSpec r;
    r.name = common::trim(item.substr(0, colon));
    if (!valid_reading_name(r.name)) {
      throw common::InputError(where + ": reading name '" + r.name + "': letters, digits, '-', '_', '.' only");
    }
    for (const ReadingSpec& seen : readings) {
      if (seen.name == r.name) throw common::InputError(where + ": reading '" + r.name + "' given twice");
    }
    for (const std::string& assignment : common::split_list(item.substr(colon + 1))) {
      const std::size_t eq = assignment.find('=');
      const std::size_t dot = assignment.find('.');
      if (eq == std::string::npos || dot == std::string::npos || dot > eq ||
          common::trim(assignment.substr(eq + 1)).empty()) {
        throw common::InputError(where + ": reading '" + r.name + "': '" + assignment +
                                 "': expected section.key=value");
      }
      r.assignments.emplace_back(common::trim(assignment.substr(0, eq)), common::trim(assignment.substr(eq + 1)));
    }
    if (r.assignments.empty()) throw common::InputError(where + ": reading '" + r.name + "' sets no key");
    readings.push_back(std::move(r));
  }
  return readings;
}

std::vector<common::Key<ExperimentSettings>> experiment_key_list() {
  using K = common::Key<ExperimentSettings>;
  return {
      K::integer("experiment", "trials", &ExperimentSettings::trials, 1, 1'000'000,
                 "random starts per sweep point (the paper: 500)", "3"),
      K::integer("experiment", "seed", &ExperimentSettings::seed, 0, (1LL << 62),
                 "base seed; every number of a trial derives from it", "7"),
      // Read before `sweeps`, which takes the built-in sweeps' values from here.
      K::real_list(
          "experiment", "sigma_loc_values_m", [](auto& s) -> auto& { return builtin_values(s, kSweepSigmaLoc); },
          placement::error_range::sigma_loc_m, "sweep points of sigma_loc_m [m]", "0, 0.1")
          .written_if([](const ExperimentSettings& s) { return s.sweep(kSweepSigmaLoc) != nullptr; }),
      K::real_list(
          "experiment", "sigma_act_values_m", [](auto& s) -> auto& { return builtin_values(s, kSweepSigmaAct); },
          placement::error_range::sigma_act_m, "sweep points of sigma_act_m [m]", "0.05")
          .written_if([](const ExperimentSettings& s) { return s.sweep(kSweepSigmaAct) != nullptr; }),
      K::text(
          "experiment", "sweeps",
          [](ExperimentSettings& s, const std::string& text, const std::string& where) {
            // Names other than the built-in ones are the extensions' (checked once they are known).
            std::vector<SweepPoints> sweeps;
            for (const std::string& name : common::split_list(text)) {
              for (const SweepPoints& seen : sweeps) {
                if (seen.name == name) throw common::InputError(where + ": sweep '" + name + "' listed twice");
              }
              const SweepPoints* builtin = s.sweep(name);
              sweeps.push_back(builtin ? *builtin : SweepPoints{name, {}});
            }
            if (sweeps.empty()) throw common::InputError(where + ": needs at least one sweep");
            s.sweeps = sweeps;
          },
          [](const ExperimentSettings& s) {
            return common::join_with(s.sweeps, [](const SweepPoints& p) { return p.name; });
          },
          "comma-separated sweep names",
          "the sweeps to run, in order (extensions add more, e.g. fusion's beacon_noise_m)", "sigma_act_m"),
      K::text(
          "experiment", "algorithms",
          [](ExperimentSettings& s, const std::string& text, const std::string& where) {
            s.algorithms.clear();
            for (const std::string& name : common::split_list(text)) {
              const Algorithm a = algorithm_from_string(name, where);
              if (std::find(s.algorithms.begin(), s.algorithms.end(), a) != s.algorithms.end()) {
                throw common::InputError(where + ": algorithm '" + name + "' listed twice");
              }
              s.algorithms.push_back(a);
            }
            if (s.algorithms.empty()) throw common::InputError(where + ": needs at least one algorithm");
          },
          [](const ExperimentSettings& s) {
            return common::join_with(s.algorithms, [](const Algorithm& a) { return to_string(a); });
          },
          "comma-separated: " + common::join(iterative_planner_names()),
          "the built-in sweeps' algorithms (default: all but ura_lattice_exact and cap)", "gd, bf"),
      K::integer("experiment", "fig1_trials", &ExperimentSettings::fig1_trials, 0, 10000,
                 "traced runs per algorithm for Fig 1 (no errors)", "2"),
      K::integer("experiment", "threads", &ExperimentSettings::threads, 0, 1024,
                 "worker threads, 0 = all cores; results do not depend on it", "1"),
      K::boolean("experiment", "plots", &ExperimentSettings::plots, "gnuplot figures", "false"),
      // Keys added later: written only when not at their default (existing config.ini files stay).
      K::boolean("experiment", "milestone_columns", &ExperimentSettings::milestone_columns,
                 "trials.csv / summary.csv columns iterations_to_icn050 and iterations_to_icn095", "true")
          .unless_default(),
      K::boolean("experiment", "capacity_columns", &ExperimentSettings::capacity_columns,
                 "trials.csv / summary.csv columns capacity_fraction and translation_* (capacity_claims.h), and "
                 "their report.md section",
                 "true")
          .unless_default(),
      K::boolean("experiment", "paths", &ExperimentSettings::paths,
                 "the path figure (paths.csv, paths.png) of the Fig 1 runs and under the largest sigma_act", "false")
          .unless_default(),
      K::text(
          "experiment", "readings",
          [](ExperimentSettings& s, const std::string& text, const std::string& where) {
            s.readings = parse_readings(text, where);
          },
          [](const ExperimentSettings& s) {
            std::string out;
            for (const ReadingSpec& r : s.readings) out += (out.empty() ? "" : " | ") + r.text();
            return out;
          },
          "name: section.key=value, ... | name: ... (none: empty)",
          "readings measured beside this run: report.md's Why lines and readings.csv (readings.h)",
          "gd-noescape: gd.escape=false, gd.stall_window=30 | bf-k: bf.contraction=1")
          .unless_default(),
      K::integer("experiment", "reading_trials", &ExperimentSettings::reading_trials, 2, 1'000'000,
                 "trials per reading (the first ones of this run's)", "20")
          .unless_default(),
  };
}

}  // namespace

const common::KeyTable<ExperimentSettings>& experiment_keys() {
  static const common::KeyTable<ExperimentSettings> table(experiment_key_list());
  return table;
}

std::map<std::string, std::set<std::string>> experiment_config_keys(const ExperimentExtensions& extensions) {
  auto keys = placement::placement_config_keys();
  const auto add = [&keys](const std::map<std::string, std::set<std::string>>& more) {
    for (const auto& [section, section_keys] : more) keys[section].insert(section_keys.begin(), section_keys.end());
  };
  add(experiment_keys().known_keys());
  for (const ExperimentExtension& e : extensions) add(e.config_keys);
  return keys;
}

ExperimentSettings load_experiment_settings(const common::IniConfig& cfg, const ExperimentExtensions& extensions) {
  cfg.require_known(experiment_config_keys(extensions));
  ExperimentSettings s;
  s.config = cfg;
  s.placement = placement::load_placement_settings(cfg);
  const common::KeyTable<ExperimentSettings>& keys = experiment_keys();
  keys.load(cfg, s);
  keys.check(cfg, "", [&] {
    for (const SweepPoints& sweep : s.sweeps) {
      const bool builtin = sweep.name == kSweepSigmaLoc || sweep.name == kSweepSigmaAct;
      if (builtin || find_extension(extensions, sweep.name)) continue;
      std::string known = kSweepSigmaLoc + ", " + kSweepSigmaAct;
      for (const ExperimentExtension& e : extensions) known += ", " + e.sweep;
      throw common::FieldError("sweeps", "unknown sweep '" + sweep.name + "' (known: " + known + ")");
    }
    // Readings are measured at the paper's values only (report.h): a run without any of their
    // sweep points and algorithms would measure nothing.
    const auto measurable = [&s](const PaperValue& p) {
      const SweepPoints* points = s.sweep(p.sweep);
      return points &&
             std::any_of(points->values.begin(), points->values.end(), [&](double v) { return v == p.value; }) &&
             std::any_of(s.algorithms.begin(), s.algorithms.end(),
                         [&](const Algorithm& a) { return to_string(a) == p.algorithm; });
    };
    const std::vector<PaperValue> paper = paper_values();
    if (!s.readings.empty() && std::none_of(paper.begin(), paper.end(), measurable)) {
      throw common::FieldError("readings",
                               "measured at the paper's values only (sweep sigma_loc_m or sigma_act_m at "
                               "a point such as 0, with random, gd, bf or ura): this run has none of them");
    }
    const bool builtin = s.sweep(kSweepSigmaLoc) || s.sweep(kSweepSigmaAct);
    const auto ura = std::find_if(s.algorithms.begin(), s.algorithms.end(), [](const Algorithm& a) {
      return a == Algorithm::kUra || a == Algorithm::kUraLattice || a == Algorithm::kUraLatticeExact;
    });
    const placement::Scenario& sc = s.placement.scenario;
    if (builtin && ura != s.algorithms.end() && sc.num_uavs > sc.num_bs_antennas()) {
      // Named as listed: the first of the URA baselines in `algorithms`.
      throw common::FieldError("algorithms", to_string(*ura) + " needs scenario.num_uavs <= bs_rows * bs_cols (" +
                                                 std::to_string(sc.num_bs_antennas()) + "), got " +
                                                 std::to_string(sc.num_uavs));
    }
  });
  for (SweepPoints& sweep : s.sweeps) {
    if (const ExperimentExtension* e = find_extension(extensions, sweep.name)) {
      sweep.values = e->load_values(s);
      if (sweep.values.empty()) throw common::InputError("sweep " + sweep.name + ": no sweep points");
    }
  }
  // Every reading must make a valid configuration too, before any work.
  for (const ReadingSpec& r : s.readings) {
    try {
      apply_reading(s, r, extensions);
    } catch (const common::InputError& e) {
      throw common::InputError(cfg.where("experiment", "readings") + ": " + e.what());
    }
  }
  return s;
}

ExperimentSettings apply_reading(const ExperimentSettings& base, const ReadingSpec& reading,
                                 const ExperimentExtensions& extensions) {
  common::IniConfig cfg = base.config;
  cfg.set("experiment", "readings", "");
  const auto known = placement::placement_config_keys();
  for (const auto& [name, value] : reading.assignments) {
    const std::size_t dot = name.find('.');
    const std::string section = name.substr(0, dot);
    const std::string key = name.substr(dot + 1);
    const auto s = known.find(section);
    if (s == known.end() || !s->second.count(key)) {
      throw common::InputError("reading '" + reading.name + "': " + name +
                               ": not a placement key (a reading sets [scenario], [errors], [placement], [gd], "
                               "[bf] or [ura] keys)");
    }
    cfg.set(section, key, value);
  }
  try {
    return load_experiment_settings(cfg, extensions);
  } catch (const common::InputError& e) {
    // The reading's keys were set like --set values: name the reading instead.
    std::string what = e.what();
    if (what.rfind("--set: ", 0) == 0) what.erase(0, 7);
    throw common::InputError("reading '" + reading.name + "': " + what);
  }
}

std::string to_ini(const ExperimentSettings& s) {
  // The whole config as read (extension sections included), with [experiment] and the
  // placement sections as resolved (defaults filled in), sorted.
  common::IniConfig resolved = s.config;
  placement::placement_keys().write_to(resolved, s.placement);
  experiment_keys().write_to(resolved, s);
  return resolved.to_string();
}

std::vector<std::string> extension_metric_names(const ExperimentSettings& settings,
                                                const ExperimentExtensions& extensions) {
  std::vector<std::string> names;
  for (const SweepPoints& sp : settings.sweeps) {
    if (const ExperimentExtension* e = find_extension(extensions, sp.name)) {
      for (const ExtensionMetric& m : e->metrics) {
        if (std::find(names.begin(), names.end(), m.name) == names.end()) names.emplace_back(m.name);
      }
    }
  }
  return names;
}

std::vector<std::string> extra_metric_names(const ExperimentSettings& settings,
                                            const ExperimentExtensions& extensions) {
  std::vector<std::string> names = extension_metric_names(settings, extensions);
  if (settings.milestone_columns) {
    for (const ExtensionMetric& m : milestone_metrics()) names.emplace_back(m.name);
  }
  if (settings.capacity_columns) {
    for (const ExtensionMetric& m : capacity_claim_metrics()) names.emplace_back(m.name);
  }
  return names;
}

}  // namespace losmimo::experiment
