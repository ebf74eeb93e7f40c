#pragma once
// Position particle filter through mrpt::bayes::CParticleFilter (standard proposal) over a
// custom particle set (CParticleFilterData<Eigen::Vector3d>). Models and robustness rules:
// filter.h and beacon_model.h.
//
// Particles q_i with log-weights l_i, i = 1..N (N = config.num_particles).
// Prediction (the proposal): q_i = q_i + d + sigma_d(|d|) n_i, n_i ~ N(0, I).
// Update: l_i += -1/2 y_i^T R^-1 y_i, y_i = z - h(q_i) with wrapped angles.
// Gate and health use the moment-matched prediction (weighted mean and covariance), so both
// filters apply the same rules to the same kind of belief.
// Resampling when ESS / N < config.ess_threshold, with config.resampling (resampling.h): MRPT's
// own automatic resampling is switched off (BETA = 0) because it draws from the global
// getRandomGenerator(). After resampling, a Liu-West kernel jitter with bandwidth
// h = config.regularization_bandwidth moves each particle to a q_i + (1 - a) mean + h L n_i,
// a = sqrt(1 - h^2), L L^T the pre-resampling covariance: mean and covariance are kept, the
// duplicates become distinct (h = 0 turns it off).
// Every random number comes from the filter's own CRandomGenerator,
// seeded from `seed` (folded to 32 bits by splitmix64: MRPT's generator takes a uint32_t).
// Belief: weighted mean and covariance of the particles, made SPD (make_spd).

#include <cstdint>
#include <memory>

#include "losmimo/localization/filter.h"

namespace losmimo::localization {

class ParticlePositionFilter final : public PositionFilter {
 public:
  ParticlePositionFilter(const FilterConfig& config, const Belief& initial, std::uint64_t seed);
  ~ParticlePositionFilter() override;
  ParticlePositionFilter(const ParticlePositionFilter&) = delete;
  ParticlePositionFilter& operator=(const ParticlePositionFilter&) = delete;

  void step(const Eigen::Vector3d& measured_displacement_m,
            const std::optional<BeaconMeasurement>& beacon) override;
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

// The 32-bit seed the filter gives MRPT's generator for a 64-bit seed (splitmix64, folded).
std::uint32_t fold_seed(std::uint64_t seed);

}  // namespace losmimo::localization
