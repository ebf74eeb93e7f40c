#pragma once
// A seeded single-UAV trial shared by the localization tests: a UAV near (1 km, 0, 0) flies a
// smooth commanded path, localization::SensorSimulator produces dead reckoning and beacons, and a filter,
// dead reckoning alone and the beacon-only fix are scored against the truth at every epoch.
//
// Path: c_k = step_m * (cos(0.1 k), sin(0.1 k), 0.3 sin(0.05 k)), true d_k = actuate(c_k).
// Initial belief: N(q_0 + e_0, sigma_0^2 I) with e_0 ~ N(0, sigma_0^2 I), so it is consistent.
// Seeds: trial seed s drives the simulator (2 s + 1) and the filter (2 s + 2).

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <vector>

#include "losmimo/localization/position/beacon_model.h"
#include "losmimo/localization/position/filter.h"
#include "losmimo/localization/position/simulator.h"

namespace losmimo::test_support {

struct TrialSpec {
  int num_epochs = 100;
  double step_m = 1.0;
  double initial_sigma_m = 0.2;
  Eigen::Vector3d start_m{1000.0, 5.0, 20.0};
  localization::SimulatorConfig sim = [] {
    localization::SimulatorConfig c;
    c.sigma_act_m = 0.05;
    return c;
  }();
  localization::FilterConfig filter;
  std::set<int> nan_beacon_epochs;        // these beacons are replaced by NaN
  std::set<int> inf_displacement_epochs;  // these displacements are replaced by +Inf
  // These beacons are replaced by the given measurement, or withheld (nullopt). The simulator
  // still draws them, so every other reading is the same as without the replacement.
  std::map<int, std::optional<localization::BeaconMeasurement>> replaced_beacons;
  // Overrides the initial belief's mean offset (else drawn from N(0, sigma_0^2 I)).
  std::optional<Eigen::Vector3d> initial_offset_m;
};

struct TrialResult {
  std::vector<Eigen::Vector3d> mean_m;   // filter mean, per epoch
  std::vector<Eigen::Vector3d> error_m;  // filter mean - truth, per epoch
  std::vector<Eigen::Matrix3d> cov_m2;
  std::vector<double> nees;
  std::vector<bool> degraded;
  std::vector<Eigen::Vector3d> dr_error_m;                  // dead reckoning alone
  std::vector<std::optional<Eigen::Vector3d>> fix_error_m;  // beacon-only fix, if a beacon
  localization::FilterCounters counters;
  int num_outliers = 0;
};

inline TrialResult run_trial(localization::FilterKind kind, const TrialSpec& spec, std::uint64_t seed) {
  localization::SensorSimulator sim(spec.sim, 2 * seed + 1);
  std::mt19937_64 init_rng(2 * seed + 1);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Vector3d offset_m;
  for (int a = 0; a < 3; ++a) offset_m(a) = spec.initial_sigma_m * normal(init_rng);
  if (spec.initial_offset_m) offset_m = *spec.initial_offset_m;

  localization::Belief initial;
  initial.mean_m = spec.start_m + offset_m;
  initial.cov_m2 = spec.initial_sigma_m * spec.initial_sigma_m * Eigen::Matrix3d::Identity();
  auto filter = localization::make_filter(kind, spec.filter, initial, 2 * seed + 2);

  TrialResult out;
  Eigen::Vector3d q_m = spec.start_m;
  Eigen::Vector3d dr_m = initial.mean_m;
  for (int k = 0; k < spec.num_epochs; ++k) {
    const double t = static_cast<double>(k);
    const Eigen::Vector3d commanded_m =
        spec.step_m * Eigen::Vector3d(std::cos(0.1 * t), std::sin(0.1 * t), 0.3 * std::sin(0.05 * t));
    const Eigen::Vector3d d_m = sim.actuate(commanded_m);
    q_m += d_m;
    Eigen::Vector3d d_meas_m = sim.measure_displacement(d_m);
    std::optional<localization::BeaconMeasurement> beacon = sim.measure_beacon(q_m, k);
    dr_m += d_meas_m;
    if (beacon) {
      out.fix_error_m.emplace_back(
          localization::beacon_fix(*beacon, spec.sim.sigma_range_m, spec.sim.sigma_angle_rad).mean_m - q_m);
    } else {
      out.fix_error_m.emplace_back(std::nullopt);
    }
    if (spec.nan_beacon_epochs.count(k) && beacon) {
      beacon->azimuth_rad = std::numeric_limits<double>::quiet_NaN();
    }
    if (const auto it = spec.replaced_beacons.find(k); it != spec.replaced_beacons.end()) {
      beacon = it->second;
    }
    if (spec.inf_displacement_epochs.count(k)) {
      d_meas_m.x() = std::numeric_limits<double>::infinity();
    }
    filter->step(d_meas_m, beacon);
    const localization::Belief b = filter->belief();
    const Eigen::Vector3d e = b.mean_m - q_m;
    out.mean_m.push_back(b.mean_m);
    out.error_m.push_back(e);
    out.cov_m2.push_back(b.cov_m2);
    out.nees.push_back(e.dot(b.cov_m2.llt().solve(e)));
    out.degraded.push_back(b.degraded);
    out.dr_error_m.push_back(dr_m - q_m);
  }
  out.counters = filter->counters();
  out.num_outliers = sim.num_outliers();
  return out;
}

inline std::vector<TrialResult> run_trials(localization::FilterKind kind, const TrialSpec& spec, int num_trials,
                                           std::uint64_t first_seed = 1) {
  std::vector<TrialResult> results;
  results.reserve(static_cast<std::size_t>(num_trials));
  for (int i = 0; i < num_trials; ++i) {
    results.push_back(run_trial(kind, spec, first_seed + static_cast<std::uint64_t>(i)));
  }
  return results;
}

// 3-D position RMSE over all trials and epochs from first_epoch on.
inline double rmse_m(const std::vector<TrialResult>& trials, int first_epoch = 0) {
  double sum = 0.0;
  int n = 0;
  for (const auto& t : trials) {
    for (std::size_t k = static_cast<std::size_t>(first_epoch); k < t.error_m.size(); ++k) {
      sum += t.error_m[k].squaredNorm();
      ++n;
    }
  }
  return std::sqrt(sum / n);
}

// Wilson-Hilferty approximation of the chi-square quantile with dof degrees of freedom at the
// standard-normal quantile z (accurate to ~0.1% for dof >= 50).
inline double chi2_quantile(double dof, double z) {
  const double c = 2.0 / (9.0 * dof);
  return dof * std::pow(1.0 - c + z * std::sqrt(c), 3);
}

// Fraction of epochs whose NEES averaged over the trials lies in the two-sided 95% band of
// chi2(3 N) / N, N the number of trials.
inline double fraction_of_epochs_in_nees_band(const std::vector<TrialResult>& trials) {
  constexpr double kZ975 = 1.959963985;
  const double n = static_cast<double>(trials.size());
  const double lo = chi2_quantile(3.0 * n, -kZ975) / n;
  const double hi = chi2_quantile(3.0 * n, kZ975) / n;
  const std::size_t epochs = trials.front().nees.size();
  int inside = 0;
  for (std::size_t k = 0; k < epochs; ++k) {
    double mean_nees = 0.0;
    for (const auto& t : trials) mean_nees += t.nees[k];
    mean_nees /= n;
    if (mean_nees >= lo && mean_nees <= hi) ++inside;
  }
  return static_cast<double>(inside) / static_cast<double>(epochs);
}

}  // namespace losmimo::test_support
