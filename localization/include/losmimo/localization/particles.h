#pragma once
// What both particle filters (position/particle_filter.h, pose/particle_filter.h) share around
// MRPT's CParticleFilter: their generator's seed, MRPT's options, and the resampling step.
//
// Options: the standard proposal hook (each filter draws its own proposal in it), a fixed
// sample size, and MRPT's automatic resampling off (BETA = 0: ESS() is never < 0), because MRPT
// resamples from the process-wide getRandomGenerator() (resampling.h). The filters resample
// themselves with resample_particles() when ESS / N < FilterConfig::ess_threshold.

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <mrpt/bayes/CParticleFilter.h>
#include <mrpt/random/RandomGenerators.h>

#include "losmimo/localization/filter_config.h"
#include "losmimo/localization/filter_counters.h"
#include "losmimo/localization/resampling.h"

namespace losmimo::localization {

// The 32-bit seed a filter gives MRPT's generator for a 64-bit seed (splitmix64, folded).
std::uint32_t fold_seed(std::uint64_t seed);

// MRPT's options as above, config.num_particles particles.
void configure_particle_filter(mrpt::bayes::CParticleFilter& pf, const FilterConfig& config);

// The log-weights of an MRPT particle list, in order.
template <class ParticleList>
std::vector<double> log_weights(const ParticleList& particles) {
  std::vector<double> log_w;
  log_w.reserve(particles.size());
  for (const auto& p : particles) log_w.push_back(p.log_w);
  return log_w;
}

// Resamples an MRPT particle set (CParticleFilterDataImpl) with `method` and the filter's own
// generator: MRPT's performSubstitution() with resampling_indices(), equal weights after it,
// counted in FilterCounters::resamplings. The caller jitters the copies (Liu-West, its state).
template <class ParticleSet>
void resample_particles(ParticleSet& set, ResamplingMethod method, mrpt::random::CRandomGenerator& rng,
                        FilterCounters& counters) {
  set.performSubstitution(resampling_indices(method, log_weights(set.m_particles), rng));
  for (auto& p : set.m_particles) p.log_w = 0.0;
  ++counters.resamplings;
}

// The Liu-West kernel jitter of a resampled, equally weighted cloud of 3-D particles (`.d`, an
// Eigen::Vector3d): each moves to a d + (1 - a) mean_m + h L n, a = sqrt(1 - h^2), n ~ N(0, I)
// (three draws from rng per particle, in order), where mean_m and L L^T are the mean and
// covariance of the cloud before resampling. Since a^2 + h^2 = 1, a cloud with those moments
// keeps them in expectation; duplicates become distinct. h in [0, 1).
template <class Particles>
void liu_west_jitter(Particles& particles, const Eigen::Vector3d& mean_m, const Eigen::Matrix3d& L, double h,
                     mrpt::random::CRandomGenerator& rng) {
  const double a = std::sqrt(1.0 - h * h);
  for (auto& p : particles) {
    Eigen::Vector3d n;
    for (int k = 0; k < 3; ++k) n(k) = rng.drawGaussian1D_normalized();
    p.d = a * p.d + (1.0 - a) * mean_m + h * (L * n);
  }
}

}  // namespace losmimo::localization
