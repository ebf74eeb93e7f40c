#pragma once
// What `losmimo-experiment` runs: the placement settings plus an [experiment] section.
//
//   [experiment] trials          random starts per sweep point (quick default 12; paper 500)
//                seed            base seed; every number of a trial derives from it
//                sweeps          comma-separated sweeps to run, in order (default
//                                sigma_loc_m, sigma_act_m; extensions add more, e.g. fusion's)
//                sigma_loc_values_m, sigma_act_values_m   comma-separated sweep points
//                algorithms      built-in sweeps' algorithms: subset of random,gd,bf,ura,ura_lattice,
//                                ura_lattice_exact (default: all but the last)
//                fig1_trials     traced runs per algorithm for Fig 1 (no errors)
//                threads         0 = all cores; results do not depend on it
//                plots           gnuplot figures (true/false)
//
// Common random numbers: trial t starts from the same positions at every sweep point and for
// every algorithm, and sees the same error draws for every algorithm at a point.

#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

#include "losmimo/common/ini_config.h"
#include "losmimo/placement/settings.h"

namespace losmimo::experiment {

// The built-in placement algorithms.
// kUraLatticeExact ("ura_lattice_exact", ura.h) is not in the default list: the paper has no such
// baseline; it is there for large arrays (256 UAVs), where the paraxial lattice stops below 0.95.
enum class Algorithm { kRandom, kGd, kBf, kUra, kUraLattice, kUraLatticeExact };
std::string to_string(Algorithm a);
// Throws common::InputError naming `where` for an unknown name.
Algorithm algorithm_from_string(const std::string& name, const std::string& where);

// The built-in sweeps.
inline const std::string kSweepSigmaLoc = "sigma_loc_m";
inline const std::string kSweepSigmaAct = "sigma_act_m";

struct SweepPoints {
  std::string name;  // e.g. "sigma_loc_m": also the `sweep` column of trials.csv
  std::vector<double> values;
};

struct ExperimentSettings {
  placement::PlacementSettings placement;
  common::IniConfig config;  // the whole validated config: extensions read their own sections
  int trials = 12;
  std::uint64_t seed = 2018;
  std::vector<SweepPoints> sweeps = {
      {kSweepSigmaLoc, {0.0, 0.02, 0.04, 0.06, 0.08, 0.10, 0.12, 0.14, 0.16, 0.18}},
      {kSweepSigmaAct, {0.0, 0.02, 0.04, 0.06, 0.08, 0.10, 0.12, 0.14, 0.16, 0.18}}};
  std::vector<Algorithm> algorithms = {Algorithm::kRandom, Algorithm::kGd, Algorithm::kBf,
                                       Algorithm::kUra, Algorithm::kUraLattice};
  int fig1_trials = 1;
  int threads = 0;
  bool plots = true;

  // The sweep of that name, or nullptr.
  const SweepPoints* sweep(const std::string& name) const;
};

}  // namespace losmimo::experiment
