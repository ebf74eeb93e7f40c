#pragma once
// A seeded range-and-odometry trial shared by the pose-filter tests: a vehicle with an offset
// range sensor drives a wobbling circle among four beacons at different heights, with 1 cm of
// vertical odometry noise per step;
// localization::RangeSensorSimulator produces robot-frame odometry (MRPT's Gaussian model) and
// ranges; a pose filter and dead reckoning alone are scored against the truth at every epoch.
//
// Path: true increment u_k = (step_m, 0, 0, turn_rad (1 + 0.6 sin(0.1 k))) in the robot frame.
// Prior: N(x_0 + e_0, P_0) with e_0 ~ N(0, P_0), P_0 = diag(s^2, s^2, s_z^2, s_yaw^2), so it is
// consistent; the filter starts from initial_pose() of the epoch-0 scan under that prior (a range
// fix, the heading from the prior), dead reckoning from the same start. Epochs 1..num_epochs are
// scored. Seeds: trial seed s drives the simulator (2 s + 1) and the filter (2 s + 2).

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "localization/position/trial_runner.h"
#include "losmimo/localization/position/beacon_model.h"
#include "losmimo/localization/pose/initial_pose.h"
#include "losmimo/localization/pose/filter.h"
#include "losmimo/localization/pose/simulator.h"

namespace losmimo::test_support {

inline localization::BeaconMap four_beacon_map() {
  localization::BeaconMap map;
  map.add(1, {0.0, 0.0, 2.5});
  map.add(2, {12.0, 0.0, 0.5});
  map.add(3, {12.0, 9.0, 3.0});
  map.add(4, {0.0, 9.0, 1.0});
  return map;
}

struct RangeTrialSpec {
  int num_epochs = 150;
  double step_m = 0.2;
  double turn_rad = 0.05;
  Eigen::Vector4d start{6.0, 0.5, 0.0, 0.0};
  double initial_sigma_m = 0.3;
  double initial_sigma_z_m = 0.05;
  double initial_sigma_yaw_rad = 0.1;
  localization::RangeSimulatorConfig sim = [] {
    localization::RangeSimulatorConfig c;
    c.sigma_range_m = 0.05;
    c.sensor_on_robot_m = Eigen::Vector3d(0.3, 0.1, 0.8);
    // The odometry measures height changes too, with 1 cm noise per step. Without vertical
    // process noise an uncertain height is a static parameter, which a 1000-particle filter
    // underestimates by genetic drift (z NEES ~1.5-1.8 instead of 1, measured; the EKF is fine).
    c.sigma_z_m = 0.01;
    return c;
  }();
  localization::PoseFilterConfig filter = [] {
    localization::PoseFilterConfig c;
    c.use_observation_std = true;  // the scans' stdError: the simulator's sigma
    return c;
  }();
  localization::BeaconMap beacons = four_beacon_map();
};

struct RangeTrialResult {
  std::vector<double> nees;            // 4 dof: x, y, z, yaw (wrapped)
  std::vector<double> sq_error_m2;     // position
  std::vector<double> dr_sq_error_m2;  // dead reckoning alone, position
  localization::FilterCounters counters;
  bool fixed_at_start = false;  // the epoch-0 scan gave a range fix
  double nis_sum = 0.0;         // of the fused readings (PoseFilter::last_innovations)
  long nis_count = 0;
};

inline Eigen::Vector4d pose_error(const Eigen::Vector4d& estimate, const Eigen::Vector4d& truth) {
  Eigen::Vector4d e = estimate - truth;
  e(localization::kPoseYaw) = localization::wrap_angle_rad(e(localization::kPoseYaw));
  return e;
}

inline RangeTrialResult run_range_trial(localization::FilterKind kind, const RangeTrialSpec& spec, std::uint64_t seed) {
  using namespace localization;
  RangeSensorSimulator sim(spec.sim, spec.beacons, 2 * seed + 1);
  std::mt19937_64 init_rng(2 * seed + 1);
  std::normal_distribution<double> normal(0.0, 1.0);
  PoseBelief prior;
  prior.cov = Eigen::Vector4d(spec.initial_sigma_m * spec.initial_sigma_m, spec.initial_sigma_m * spec.initial_sigma_m,
                              spec.initial_sigma_z_m * spec.initial_sigma_z_m,
                              spec.initial_sigma_yaw_rad * spec.initial_sigma_yaw_rad)
                  .asDiagonal();
  Eigen::Vector4d n;
  for (int a = 0; a < kPoseSize; ++a) n(a) = normal(init_rng);
  prior.mean = spec.start + prior.cov.cwiseSqrt() * n;
  Eigen::Vector4d truth = spec.start;
  // Epoch 0: the start as users run it, a range fix of the first scan under the prior.
  std::vector<BeaconRangeScan> scans0;
  if (auto scan = sim.measure_ranges(truth, 0)) scans0.push_back(*scan);
  const InitialPose initial = initial_pose(scans0, spec.beacons, spec.filter, prior);
  auto filter = make_pose_filter(kind, spec.filter, spec.beacons, initial, 2 * seed + 2);

  RangeTrialResult out;
  out.fixed_at_start = initial.fix.has_value();
  Eigen::Vector4d dr = moments(initial).mean;
  for (int k = 1; k <= spec.num_epochs; ++k) {
    const double t = static_cast<double>(k);
    const Eigen::Vector4d u_true(spec.step_m, 0.0, 0.0, spec.turn_rad * (1.0 + 0.6 * std::sin(0.1 * t)));
    truth = compose(truth, u_true);
    const OdometryIncrement reading = sim.measure_odometry(u_true);
    dr = compose(dr, reading.delta);
    std::vector<BeaconRangeScan> scans;
    if (auto scan = sim.measure_ranges(truth, k)) scans.push_back(*scan);
    filter->step(reading, scans);
    out.nis_sum += filter->last_innovations().nis_sum;
    out.nis_count += filter->last_innovations().fused;
    const PoseBelief b = filter->belief();
    const Eigen::Vector4d e = pose_error(b.mean, truth);
    out.nees.push_back(e.dot(b.cov.llt().solve(e)));
    out.sq_error_m2.push_back(e.head<3>().squaredNorm());
    out.dr_sq_error_m2.push_back((dr - truth).head<3>().squaredNorm());
  }
  out.counters = filter->counters();
  return out;
}

inline std::vector<RangeTrialResult> run_range_trials(localization::FilterKind kind, const RangeTrialSpec& spec,
                                                      int num_trials) {
  std::vector<RangeTrialResult> out;
  for (int i = 0; i < num_trials; ++i) out.push_back(run_range_trial(kind, spec, 1 + static_cast<std::uint64_t>(i)));
  return out;
}

// Fraction of epochs (from first_epoch on, 0-based in the scored epochs) whose run-averaged NEES
// lies in the two-sided 95% band of chi2(4 N) / N.
inline double fraction_in_pose_nees_band(const std::vector<RangeTrialResult>& trials, int first_epoch = 0) {
  constexpr double kZ975 = 1.959963985;
  constexpr double kDof = 4.0;
  const double n = static_cast<double>(trials.size());
  const double lo = chi2_quantile(kDof * n, -kZ975) / n;
  const double hi = chi2_quantile(kDof * n, kZ975) / n;
  const std::size_t epochs = trials.front().nees.size();
  int inside = 0;
  for (std::size_t k = static_cast<std::size_t>(first_epoch); k < epochs; ++k) {
    double mean = 0.0;
    for (const auto& t : trials) mean += t.nees[k] / n;
    if (mean >= lo && mean <= hi) ++inside;
  }
  return static_cast<double>(inside) / static_cast<double>(epochs - static_cast<std::size_t>(first_epoch));
}

// Average NIS per fused reading over all trials (1 for a consistent filter).
inline double mean_reading_nis(const std::vector<RangeTrialResult>& trials) {
  double sum = 0.0;
  long n = 0;
  for (const auto& t : trials) {
    sum += t.nis_sum;
    n += t.nis_count;
  }
  return sum / static_cast<double>(n);
}

inline double mean_nees(const std::vector<RangeTrialResult>& trials) {
  double sum = 0.0;
  int n = 0;
  for (const auto& t : trials) {
    for (const double v : t.nees) {
      sum += v;
      ++n;
    }
  }
  return sum / n;
}

// Position RMSE of the filter (or of dead reckoning) over all trials and epochs >= first_epoch.
inline double range_rmse_m(const std::vector<RangeTrialResult>& trials, bool dead_reckoning, int first_epoch = 0) {
  double sum = 0.0;
  int n = 0;
  for (const auto& t : trials) {
    const std::vector<double>& sq = dead_reckoning ? t.dr_sq_error_m2 : t.sq_error_m2;
    for (std::size_t k = static_cast<std::size_t>(first_epoch); k < sq.size(); ++k) {
      sum += sq[k];
      ++n;
    }
  }
  return std::sqrt(sum / n);
}

}  // namespace losmimo::test_support
