#pragma once
// Particle resampling with a caller-owned generator.
//
// Why not MRPT's: CParticleFilterCapable::computeResampling (and so performResampling and
// CParticleFilter's automatic resampling) draws from the process-wide getRandomGenerator(),
// which is neither thread-safe nor per-filter seeded. The particle filter therefore turns
// MRPT's automatic resampling off and calls this instead, with its own CRandomGenerator, then
// hands the indices to MRPT's performSubstitution().
//
// Given log-weights l_i (any offset), w_i = exp(l_i - max l) / sum_j exp(l_j - max l), and N
// output draws with cumulative weights Q_j = sum_{i<=j} w_i, index j is chosen for a point u
// when Q_{j-1} < u <= Q_j:
//   multinomial: u_k iid U(0, 1);
//   stratified:  u_k = (k + U_k) / N, U_k iid U(0, 1);
//   systematic:  u_k = (k + U) / N, one U ~ U(0, 1);
//   residual:    floor(N w_i) copies of i, then multinomial on the remainder with weights
//                proportional to N w_i - floor(N w_i).
// Every method is unbiased: E[copies of i] = N w_i. Output indices are sorted ascending.

#include <cstddef>
#include <vector>

#include <mrpt/random/RandomGenerators.h>

#include "losmimo/localization/filter_config.h"

namespace losmimo::localization {

// Normalised linear weights from log-weights; all-equal if none is finite and positive.
std::vector<double> normalized_weights(const std::vector<double>& log_weights);

// N = log_weights.size() indices. Throws std::invalid_argument on an empty input.
std::vector<std::size_t> resampling_indices(ResamplingMethod method, const std::vector<double>& log_weights,
                                            mrpt::random::CRandomGenerator& rng);

// Effective sample size over N, in (0, 1]: 1 / (N sum w_i^2).
double normalized_ess(const std::vector<double>& log_weights);

}  // namespace losmimo::localization
