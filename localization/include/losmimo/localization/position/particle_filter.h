#pragma once
// Position particle filter through mrpt::bayes::CParticleFilter (standard proposal) over a
// custom particle set (CParticleFilterData<Eigen::Vector3d>). Models and robustness rules:
// filter.h and beacon_model.h.
//
// Particles q_i with log-weights l_i, i = 1..N (N = config.num_particles).
// Epoch with a fused beacon: each particle is drawn from the locally linearised optimal proposal
// (optimal_proposal.h) with qbar_i = q_i + d, Q = sigma_d(|d|)^2 I and the beacon as whitened
// residuals (z - h(q)) / sigma (angles wrapped); l_i gets the exact importance weight. This is the
// fix for the smallest beacon noises: with the motion model as the proposal, a beacon whose
// lateral 1-sigma (1 mm at 1 km for sigma_angle 1e-6) is far below the dead-reckoning spread
// leaves a few particles with all the weight, and the moment-matched covariance collapses (NEES
// ~1e6 in the co-evaluation at beacon noise 0); drawn from the optimal proposal, every particle
// lands inside the likelihood and the weights only reflect the predictive likelihood.
// Measured (seeded; before -> after): co-evaluation at beacon noise 0 (2 trials, 1000 particles)
// NEES 2.5e6 / 6.6e5 -> 0.97 / 0.82 (the EKF: 0.96 / 0.82), RMSE 0.087 / 0.068 -> 0.036 m;
// tests/localization/position/consistency_test.cpp (50 runs x 200 epochs, 2000 particles): at
// sigma_angle_rad = 1e-6 in truth and model, mean NEES 1.1e7 -> 4.6 (3 dof; epochs in the 95%
// band 0 -> 0.94), and with a noise-free angle 1.2e7 -> 1.44 (the EKF: 1.04). Cost: each particle
// takes two to three 3x3 Gauss-Newton steps instead of one draw (bench_localization).
// Epoch without one (none, rejected, or a reset): the motion model is the proposal,
// q_i = q_i + d + sigma_d(|d|) n_i, n_i ~ N(0, I).
// Gate and health use the predicted moments (the weighted mean and covariance of the q_i, moved
// by d, plus sigma_d^2 I), so both filters apply the same rules to the same kind of belief.
// Resampling when ESS / N < config.ess_threshold, with config.resampling (resampling.h): MRPT's
// own automatic resampling is switched off (BETA = 0) because it draws from the global
// getRandomGenerator(). After resampling, a Liu-West kernel jitter with bandwidth
// h = config.regularization_bandwidth moves each particle to a q_i + (1 - a) mean + h L n_i,
// a = sqrt(1 - h^2), L L^T the pre-resampling covariance: mean and covariance are kept, the
// duplicates become distinct (h = 0 turns it off).
// Every random number comes from the filter's own CRandomGenerator,
// seeded from `seed` (fold_seed(), particles.h: MRPT's generator takes a uint32_t).
// Belief: weighted mean and covariance of the particles, made SPD (make_spd).

#include <cstdint>
#include <memory>

#include "losmimo/localization/particles.h"
#include "losmimo/localization/position/filter.h"

namespace losmimo::localization {

class ParticlePositionFilter final : public PositionFilter {
 public:
  ParticlePositionFilter(const FilterConfig& config, const Belief& initial, std::uint64_t seed);
  ~ParticlePositionFilter() override;
  ParticlePositionFilter(const ParticlePositionFilter&) = delete;
  ParticlePositionFilter& operator=(const ParticlePositionFilter&) = delete;

  void step(const Eigen::Vector3d& measured_displacement_m, const std::optional<BeaconMeasurement>& beacon) override;
  Belief belief() const override;
  const FilterCounters& counters() const override;
  FilterKind kind() const override { return FilterKind::kParticle; }

  int num_particles() const;
  // ESS / N after the last update, before any resampling (1 before the first step).
  double last_normalized_ess() const;

 private:
  class Mrpt;
  std::unique_ptr<Mrpt> pf_;
};

}  // namespace losmimo::localization
