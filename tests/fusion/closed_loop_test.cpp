// The closed loop: GD placement on filtered beliefs, BF fallback when a belief is
// degraded. Paper scenario (16 UAVs, 4 x 4 BS, 1 km), actuation error 0.02 m. Seeded, never
// retried.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <iostream>
#include <thread>

#include "losmimo/fusion/closed_loop.h"
#include "fusion/closed_loop_fixtures.h"
#include "support/shape_nees.h"

namespace losmimo::fusion {
namespace {

using test_support::nominal_config;
using test_support::paper_settings;
using test_support::start_positions;

constexpr int kMaxIterations = 600;

void print(const std::string& label, const ClosedLoopRun& r) {
  const ClosedLoopStats& s = r.stats;
  int bf = 0;
  for (int n : s.bf_fallback_iterations) bf += n;
  std::cout << "[closed_loop] " << label << ": " << placement::to_string(r.run.status) << " in " << r.run.iterations
            << " it, travel to 0.95 " << r.run.icn095.placement_dist_m << " m; rmse " << s.rmse_m << " m (lateral "
            << s.lateral_rmse_m << "), filter " << s.filter_rmse_m << " (lateral " << s.filter_lateral_rmse_m
            << "), beacon-only " << s.beacon_only_rmse_m << " (lateral " << s.beacon_only_lateral_rmse_m << "); NEES "
            << s.average_nees << " (filter " << s.filter_average_nees << "); BF iterations " << bf << ", escapes "
            << s.escapes << "\n";
}

TEST(ClosedLoop, NominalEkf_ConvergesFromMostStartsAndBeatsTheBeaconAlone) {
  // GIVEN: the paper scenario, the default beacon (0.1 m per axis at 1 km), matched EKF.
  const placement::PlacementSettings settings = paper_settings(kMaxIterations);
  const ClosedLoopConfig config = nominal_config(settings.scenario);
  constexpr int kStarts = 5;
  int converged = 0;
  for (int i = 0; i < kStarts; ++i) {
    // WHEN
    const ClosedLoopRun r = run_closed_loop(settings, start_positions(settings.scenario, 100 + i), config, 200 + i);
    print("nominal ekf start " + std::to_string(i), r);
    // THEN: the belief beats a single beacon fix, and nobody needed the fallback.
    if (r.run.converged()) ++converged;
    EXPECT_LT(r.stats.rmse_m, r.stats.beacon_only_rmse_m);
    EXPECT_LT(r.stats.lateral_rmse_m, r.stats.beacon_only_lateral_rmse_m);
    for (int n : r.stats.bf_fallback_iterations) EXPECT_EQ(n, 0);
  }
  EXPECT_GE(converged, 4);
}

TEST(ClosedLoop, BeaconRemovedForOneUavFromTheStart_ThatUavRunsBfAndTheRunConverges) {
  // GIVEN: UAV 3 never receives the beacon; the others are nominal.
  const placement::PlacementSettings settings = paper_settings(kMaxIterations);
  ClosedLoopConfig config = nominal_config(settings.scenario);
  constexpr int kLost = 3;
  config.outages.push_back({kLost, {0, 1'000'000}});
  // WHEN
  const ClosedLoopRun r = run_closed_loop(settings, start_positions(settings.scenario, 100), config, 200);
  print("one UAV without beacon", r);
  // THEN
  EXPECT_TRUE(r.run.converged());
  EXPECT_EQ(r.stats.bf_fallback_iterations[kLost], r.run.iterations);
  EXPECT_EQ(r.stats.gd_iterations[kLost], 0);
  for (int m = 0; m < settings.scenario.num_uavs; ++m) {
    if (m != kLost) {
      EXPECT_EQ(r.stats.bf_fallback_iterations[m], 0) << "UAV " << m;
    }
  }
}

TEST(ClosedLoop, BeaconOutageForFourUavsMidMission_TheyFallBackAndReturnToGd) {
  // GIVEN: UAVs 0, 5, 10, 15 lose the beacon for epochs 10..39; degraded after 5 epochs.
  const placement::PlacementSettings settings = paper_settings(kMaxIterations);
  ClosedLoopConfig config = nominal_config(settings.scenario);
  config.filter.degraded_after_epochs = 5;
  constexpr int kFirst = 10, kEpochs = 30;
  const std::vector<int> lost = {0, 5, 10, 15};
  for (int m : lost) config.outages.push_back({m, {kFirst, kEpochs}});
  // WHEN
  const ClosedLoopRun r = run_closed_loop(settings, start_positions(settings.scenario, 101), config, 201);
  print("outage of 4 UAVs", r);
  // THEN: the swarm converges after the outage, so the return to GD is observable.
  ASSERT_TRUE(r.run.converged());
  const int outage_end_iteration = kFirst + kEpochs + 1;  // epoch k is iteration k + 1
  ASSERT_GT(r.run.iterations, outage_end_iteration + 5);
  for (int m = 0; m < settings.scenario.num_uavs; ++m) {
    const bool is_lost = std::find(lost.begin(), lost.end(), m) != lost.end();
    if (!is_lost) {
      EXPECT_EQ(r.stats.bf_fallback_iterations[m], 0) << "UAV " << m;
      continue;
    }
    // Degraded from the 5th epoch without beacon to the first epoch with one again.
    EXPECT_GE(r.stats.bf_fallback_iterations[m], kEpochs - 5) << "UAV " << m;
    EXPECT_LE(r.stats.bf_fallback_iterations[m], kEpochs) << "UAV " << m;
    EXPECT_LE(r.stats.last_fallback_iteration[m], outage_end_iteration) << "UAV " << m;
    for (int it = outage_end_iteration + 1; it <= r.run.iterations; ++it) {
      EXPECT_EQ(r.stats.mode_trace[it - 1][m], static_cast<char>(UavMode::kGd)) << "UAV " << m << " iteration " << it;
    }
  }
}

TEST(ClosedLoop, CeresRefinementAtTheLargestBeaconNoise_NotWorseThanTheFilterAlone) {
  // GIVEN: the paper's largest localization error (beacon 0.18 m cross-range), same seeds
  // with and without refinement.
  const placement::PlacementSettings settings = paper_settings(kMaxIterations);
  localization::SimulatorConfig sim;
  sim.sigma_angle_rad = 1.8e-4;
  ClosedLoopConfig off = matched_closed_loop_config(sim, settings.scenario);
  ClosedLoopConfig on = off;
  on.refine = true;
  constexpr int kStarts = 3;
  double sq_off = 0.0, sq_on = 0.0, lat_off = 0.0, lat_on = 0.0;
  for (int i = 0; i < kStarts; ++i) {
    const Eigen::Matrix3Xd start = start_positions(settings.scenario, 100 + i);
    // WHEN
    const ClosedLoopRun r_off = run_closed_loop(settings, start, off, 200 + i);
    const ClosedLoopRun r_on = run_closed_loop(settings, start, on, 200 + i);
    print("0.18 m beacon, filter only, start " + std::to_string(i), r_off);
    print("0.18 m beacon, ceres, start " + std::to_string(i), r_on);
    EXPECT_TRUE(r_off.run.converged());
    EXPECT_TRUE(r_on.run.converged());
    // THEN (same trajectory): the refined beliefs beat the filter that feeds them laterally,
    // where CSI carries the position.
    EXPECT_LT(r_on.stats.lateral_rmse_m, r_on.stats.filter_lateral_rmse_m);
    EXPECT_EQ(r_on.stats.refinement_covariance_fallbacks, 0);
    EXPECT_GT(r_on.stats.average_nees, 2.0);  // consistent, not inflated nor optimistic
    EXPECT_LT(r_on.stats.average_nees, 4.5);
    sq_off += r_off.stats.rmse_m * r_off.stats.rmse_m;
    sq_on += r_on.stats.rmse_m * r_on.stats.rmse_m;
    lat_off += r_off.stats.lateral_rmse_m * r_off.stats.lateral_rmse_m;
    lat_on += r_on.stats.lateral_rmse_m * r_on.stats.lateral_rmse_m;
  }
  // THEN (same seeds): refinement is not worse in 3-D and better laterally.
  EXPECT_LE(sq_on, sq_off);
  EXPECT_LT(lat_on, 0.9 * lat_off);
}

TEST(ClosedLoop, ParticleFilter_ConvergesWithConsistentBeliefs) {
  const placement::PlacementSettings settings = paper_settings(kMaxIterations);
  ClosedLoopConfig config = nominal_config(settings.scenario);
  config.filter_kind = localization::FilterKind::kParticle;
  const ClosedLoopRun r = run_closed_loop(settings, start_positions(settings.scenario, 102), config, 202);
  print("nominal pf", r);
  EXPECT_TRUE(r.run.converged());
  EXPECT_LT(r.stats.lateral_rmse_m, r.stats.beacon_only_lateral_rmse_m);
  EXPECT_GT(r.stats.average_nees, 2.0);
  EXPECT_LT(r.stats.average_nees, 4.5);
}

TEST(ClosedLoop, FallbackOff_TheUavWithoutBeaconNeverRunsBf) {
  const placement::PlacementSettings settings = paper_settings(kMaxIterations);
  ClosedLoopConfig config = nominal_config(settings.scenario);
  config.fallback_to_bf = false;
  config.outages.push_back({3, {0, 1'000'000}});
  const ClosedLoopRun r = run_closed_loop(settings, start_positions(settings.scenario, 100), config, 200);
  print("one UAV without beacon, fallback off", r);
  for (int n : r.stats.bf_fallback_iterations) EXPECT_EQ(n, 0);
  EXPECT_EQ(r.stats.gd_iterations[3], r.run.iterations);
}

// Final positions of one run: particle filter and refinement on, so that every generator
// (actuation, sensors, particles, CSI) is exercised.
Eigen::Matrix3Xd final_positions(std::uint64_t seed) {
  placement::PlacementSettings settings = paper_settings(kMaxIterations);
  settings.run.max_iterations = 40;
  ClosedLoopConfig config = nominal_config(settings.scenario);
  config.filter_kind = localization::FilterKind::kParticle;
  config.filter.num_particles = 300;
  config.refine = true;
  config.outages.push_back({1, {5, 20}});  // and the BF fallback
  return run_closed_loop(settings, start_positions(settings.scenario, 103), config, seed).run.final_m;
}

bool bitwise_equal(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) {
  return a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}

TEST(ClosedLoop, SameSeed_BitwiseIdenticalSequentiallyAndInTwoThreads) {
  const Eigen::Matrix3Xd first = final_positions(7);
  const Eigen::Matrix3Xd second = final_positions(7);
  EXPECT_TRUE(bitwise_equal(first, second));
  Eigen::Matrix3Xd in_a, in_b;
  std::thread a([&] { in_a = final_positions(7); });
  std::thread b([&] { in_b = final_positions(7); });
  a.join();
  b.join();
  EXPECT_TRUE(bitwise_equal(first, in_a));
  EXPECT_TRUE(bitwise_equal(first, in_b));
  EXPECT_FALSE(bitwise_equal(first, final_positions(8)));  // the seed does matter
}

TEST(ClosedLoop, BadConfig_ThrowsNamingFieldAndValue) {
  const placement::PlacementSettings settings = paper_settings(kMaxIterations);
  const Eigen::Matrix3Xd start = start_positions(settings.scenario, 100);
  const auto message = [&](const ClosedLoopConfig& config) -> std::string {
    try {
      run_closed_loop(settings, start, config, 1);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "no exception";
  };
  ClosedLoopConfig config = nominal_config(settings.scenario);
  config.outages.push_back({-2, {0, 5}});
  EXPECT_NE(message(config).find("outages[0].uav = -2"), std::string::npos) << message(config);
  config.outages = {{0, {0, 5}}, {16, {0, 5}}};
  // The rule and message of the INI loader (require_uavs_in_swarm).
  EXPECT_EQ(message(config), "closed_loop.outages[1].uav = 16: must be < the number of UAVs (16)");
  config.outages = {{0, {-1, 5}}};
  EXPECT_NE(message(config).find("outages[0].first_epoch = -1"), std::string::npos);
  config.outages.clear();
  config.filter.degraded_after_epochs = 0;
  EXPECT_NE(message(config).find("degraded_after_epochs"), std::string::npos) << message(config);
  config = nominal_config(settings.scenario);
  config.refinement.window_epochs = 0;
  EXPECT_NE(message(config).find("window_epochs"), std::string::npos) << message(config);
  EXPECT_THROW(gd_belief_mode_from_string("median"), std::invalid_argument);
  EXPECT_EQ(gd_belief_mode_from_string(to_string(GdBeliefMode::kSigmaPoints)), GdBeliefMode::kSigmaPoints);
}

}  // namespace
}  // namespace losmimo::fusion

namespace losmimo::fusion {
namespace {

using test_support::nominal_config;
using test_support::paper_settings;
using test_support::start_positions;

// Every epoch's beliefs and truths, as the observer sees them.
class EpochRecorder : public ClosedLoopObserver {
 public:
  void on_epoch(const EpochObservation& o) override {
    if (static_cast<int>(truth.size()) <= o.epoch) {
      truth.resize(o.epoch + 1, Eigen::Matrix3Xd::Constant(3, 16, std::nan("")));
      mean.resize(o.epoch + 1, Eigen::Matrix3Xd::Constant(3, 16, std::nan("")));
    }
    truth[o.epoch].col(o.uav) = o.true_position_m;
    mean[o.epoch].col(o.uav) = o.belief.mean_m;
    if (static_cast<int>(cov.size()) <= o.epoch) cov.resize(o.epoch + 1, std::vector<Eigen::Matrix2d>(16));
    cov[o.epoch][static_cast<std::size_t>(o.uav)] = o.belief.cov_m2.bottomRightCorner<2, 2>();
  }
  std::vector<Eigen::Matrix3Xd> truth, mean;
  std::vector<std::vector<Eigen::Matrix2d>> cov;
};

TEST(ClosedLoop, ShapeStats_AreTheEpochsCommonOffsetAndShapeResidual_RecomputedFromTheObservedBeliefs) {
  const placement::PlacementSettings settings = paper_settings(60);
  ClosedLoopConfig config = nominal_config(settings.scenario);
  config.simulator.sigma_angle_rad = 5e-4;  // 0.5 m cross-range at 1 km: a visible common offset and shape
  config.filter.noise.sigma_angle_rad = 5e-4;
  EpochRecorder seen;
  const ClosedLoopRun r = run_closed_loop(settings, start_positions(settings.scenario, 100), config, 200, &seen);
  ASSERT_FALSE(seen.truth.empty());
  // Recomputed here: per epoch, the mean lateral error c and the residual after c and the best
  // rotation about boresight through the true lateral centroid (closed-form 1-D least squares).
  double common_sq = 0.0, shape_sq = 0.0, nees_sum = 0.0;
  int epochs = 0, uav_epochs = 0;
  for (std::size_t e = 0; e < seen.truth.size(); ++e) {
    ASSERT_TRUE(seen.truth[e].allFinite()) << "epoch " << e;
    nees_sum += test_support::shape_nees_by_pseudo_inverse(seen.truth[e], seen.mean[e], seen.cov[e]);
    const Eigen::Matrix2Xd err = (seen.mean[e] - seen.truth[e]).bottomRows<2>();
    const Eigen::Vector2d c = err.rowwise().mean();
    const Eigen::Vector2d centroid = seen.truth[e].bottomRows<2>().rowwise().mean();
    double num = 0.0, den = 0.0;
    for (Eigen::Index n = 0; n < err.cols(); ++n) {
      const Eigen::Vector2d r_n = seen.truth[e].col(n).tail<2>() - centroid;
      const Eigen::Vector2d jr(-r_n.y(), r_n.x());
      num += jr.dot(err.col(n) - c);
      den += jr.squaredNorm();
    }
    const double theta = num / den;
    for (Eigen::Index n = 0; n < err.cols(); ++n) {
      const Eigen::Vector2d r_n = seen.truth[e].col(n).tail<2>() - centroid;
      shape_sq += (err.col(n) - c - theta * Eigen::Vector2d(-r_n.y(), r_n.x())).squaredNorm();
      ++uav_epochs;
    }
    common_sq += c.squaredNorm();
    ++epochs;
  }
  EXPECT_EQ(epochs, r.stats.num_epochs);
  EXPECT_NEAR(r.stats.common_lateral_rms_m, std::sqrt(common_sq / epochs), 1e-12);
  EXPECT_NEAR(r.stats.shape_lateral_rmse_m, std::sqrt(shape_sq / uav_epochs), 1e-12);
  EXPECT_NEAR(r.stats.shape_nees_per_dof, nees_sum / epochs, 1e-9 * nees_sum / epochs);
  // The split is not degenerate: both parts are there, and the shape is below the whole lateral error.
  EXPECT_GT(r.stats.common_lateral_rms_m, 0.0);
  EXPECT_GT(r.stats.shape_lateral_rmse_m, 0.0);
  EXPECT_LT(r.stats.shape_lateral_rmse_m, r.stats.lateral_rmse_m);
  std::cout << "lateral RMSE " << r.stats.lateral_rmse_m << " m: common offset RMS " << r.stats.common_lateral_rms_m
            << " m, shape residual RMSE " << r.stats.shape_lateral_rmse_m << " m, shape NEES/dof "
            << r.stats.shape_nees_per_dof << "\n";
}

TEST(ClosedLoop, BsArrayMisalignment_MovesTheBeliefsTogether_ShapeStays_ButThePapersGdSeesTheOffset) {
  // GIVEN: the paper scenario and a BS array mounted 1 mrad off in azimuth (1 m at 1 km), which
  // no filter knows: every UAV's beacon is wrong by nearly the same lateral metre.
  const placement::PlacementSettings settings = paper_settings(kMaxIterations);
  const ClosedLoopConfig nominal = nominal_config(settings.scenario);
  ClosedLoopConfig misaligned = nominal;
  misaligned.simulator.bs_azimuth_bias_rad = 1e-3;
  const Eigen::Matrix3Xd start = start_positions(settings.scenario, 104);
  // WHEN: the same start and seed with and without it.
  const ClosedLoopRun a = run_closed_loop(settings, start, nominal, 204);
  const ClosedLoopRun b = run_closed_loop(settings, start, misaligned, 204);
  print("nominal", a);
  print("azimuth bias 1 mrad", b);
  double best_icn = 0.0;
  for (const placement::IterationRecord& it : b.run.trace) best_icn = std::max(best_icn, it.icn_los);
  std::cout << "[closed_loop] common offset " << a.stats.common_lateral_rms_m << " -> " << b.stats.common_lateral_rms_m
            << " m, shape " << a.stats.shape_lateral_rmse_m << " -> " << b.stats.shape_lateral_rmse_m
            << " m; misaligned best ICN " << best_icn << "\n";
  // THEN: the absolute lateral error is the bias's metre, all of it common ...
  const double bias_m = 1e-3 * settings.scenario.range_m();
  EXPECT_GT(b.stats.lateral_rmse_m, 0.8 * bias_m);
  EXPECT_GT(b.stats.lateral_rmse_m, 5.0 * a.stats.lateral_rmse_m);
  EXPECT_NEAR(b.stats.common_lateral_rms_m, bias_m, 0.2 * bias_m);
  // ... and the shape is (nearly) the nominal one ...
  EXPECT_LT(b.stats.shape_lateral_rmse_m, 1.5 * a.stats.shape_lateral_rmse_m + 0.01);
  // ... yet the paper's GD does not reach the target: UAV m evaluates its own channel row at its
  // belief against the other UAVs' measured rows, so a common offset is not common in that mix
  // (a lateral shift t tilts UAV m's row by 2 pi t a_k / (lambda R) per antenna against the
  // others'). Measured: nominal converges in 103 iterations; misaligned plateaus at ICN 0.8-0.9.
  EXPECT_TRUE(a.run.converged());
  EXPECT_FALSE(b.run.converged());
  EXPECT_LT(best_icn, 0.95);
}

}  // namespace
}  // namespace losmimo::fusion
