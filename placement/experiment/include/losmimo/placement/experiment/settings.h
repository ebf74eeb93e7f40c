#pragma once
// What `losmimo-experiment` runs: the placement settings plus an [experiment] section (trials,
// seed, sweeps and their points, algorithms, Fig 1 runs, threads, plots), each key declared once
// in the key table in settings.cpp (experiment_keys(); common/key_table.h).
//
// Common random numbers: trial t starts from the same positions at every sweep point and for
// every algorithm, and sees the same error draws for every algorithm at a point.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/common/key_table.h"
#include "losmimo/placement/planner_registry.h"
#include "losmimo/placement/settings.h"

namespace losmimo::experiment {

// A placement algorithm of the experiment: a planner of the registry (placement/planner_registry.h)
// by its name. The constants name the builtin planners that the paper's figures and the reports
// refer to. Not in the default list, as the paper has no such algorithm: "ura_lattice_exact"
// (ura.h), for large arrays (256 UAVs), where the paraxial lattice stops below 0.95; "cap"
// (placement/capacity.h), the follow-up paper's capacity ascent.
class Algorithm {
 public:
  explicit Algorithm(std::string name) : name_(std::move(name)) {}
  const std::string& name() const { return name_; }
  // Its registry entry; std::invalid_argument when the name is not registered.
  const placement::PlannerEntry& entry() const { return placement::planner_entry(name_); }
  friend bool operator==(const Algorithm& a, const Algorithm& b) { return a.name_ == b.name_; }
  friend bool operator!=(const Algorithm& a, const Algorithm& b) { return a.name_ != b.name_; }
  friend bool operator<(const Algorithm& a, const Algorithm& b) { return a.name_ < b.name_; }

  static const Algorithm kRandom, kGd, kBf, kUra, kUraLattice, kUraLatticeExact, kCap;

 private:
  std::string name_;
};
inline const Algorithm Algorithm::kRandom{"random"};
inline const Algorithm Algorithm::kGd{"gd"};
inline const Algorithm Algorithm::kBf{"bf"};
inline const Algorithm Algorithm::kUra{"ura"};
inline const Algorithm Algorithm::kUraLattice{"ura_lattice"};
inline const Algorithm Algorithm::kUraLatticeExact{"ura_lattice_exact"};
inline const Algorithm Algorithm::kCap{"cap"};
inline const std::string& to_string(const Algorithm& a) { return a.name(); }
// The iterative planner `name` (direct ones run in the co-evaluation only); common::InputError
// naming `where` and the known names otherwise.
Algorithm algorithm_from_string(const std::string& name, const std::string& where);

// The built-in sweeps.
inline const std::string kSweepSigmaLoc = "sigma_loc_m";
inline const std::string kSweepSigmaAct = "sigma_act_m";

struct SweepPoints {
  std::string name;  // e.g. "sigma_loc_m": also the `sweep` column of trials.csv
  std::vector<double> values;
};

// A reading: a name and placement keys set on top of the run's configuration, written in
// [experiment] readings as "name: section.key=value, section.key=value | name2: ...".
struct ReadingSpec {
  std::string name;
  std::vector<std::pair<std::string, std::string>> assignments;  // ("gd.escape", "false")
  std::string text() const;                                      // "name: gd.escape=false, gd.step=0.8"
};

struct ExperimentSettings {
  placement::PlacementSettings placement;
  common::IniConfig config;  // the whole validated config: extensions read their own sections
  int trials = 12;
  std::uint64_t seed = 2018;
  std::vector<SweepPoints> sweeps = {{kSweepSigmaLoc, {0.0, 0.02, 0.04, 0.06, 0.08, 0.10, 0.12, 0.14, 0.16, 0.18}},
                                     {kSweepSigmaAct, {0.0, 0.02, 0.04, 0.06, 0.08, 0.10, 0.12, 0.14, 0.16, 0.18}}};
  std::vector<Algorithm> algorithms = {Algorithm("random"), Algorithm("gd"), Algorithm("bf"), Algorithm("ura"),
                                       Algorithm("ura_lattice")};
  int fig1_trials = 1;
  int threads = 0;
  bool plots = true;
  // trials.csv and summary.csv get the columns iterations_to_icn050 and iterations_to_icn095
  // (after any extension's), the iteration at which each run first reached that ICN.
  bool milestone_columns = false;
  // trials.csv and summary.csv get capacity_claim_metrics() (capacity_claims.h) after the
  // milestone columns, and report.md a section on them.
  bool capacity_columns = false;
  // The path figure (paths.csv, paths.png): the Fig 1 runs of trial 0 and, under the largest
  // sigma_act of the sweep, GD and BF from the same start.
  bool paths = true;
  // Readings (readings.h), each run beside this configuration at the paper values' sweep points,
  // reading_trials trials each, paired with the same seeds.
  std::vector<ReadingSpec> readings;
  int reading_trials = 50;

  // The sweep of that name, or nullptr.
  const SweepPoints* sweep(const std::string& name) const;
};

// The [experiment] keys: one entry per key (section, key, field, accepted values, meaning).
// Names in `sweeps` other than the built-in ones are checked by load_experiment_settings
// against the extensions (extension.h).
const common::KeyTable<ExperimentSettings>& experiment_keys();

}  // namespace losmimo::experiment
