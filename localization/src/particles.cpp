#include "losmimo/localization/particles.h"

#include "losmimo/placement/common/seed.h"

namespace losmimo::localization {

namespace {

mrpt::bayes::CParticleFilter::TParticleResamplingAlgorithm to_mrpt(ResamplingMethod method) {
  switch (method) {
    case ResamplingMethod::kMultinomial:
      return mrpt::bayes::CParticleFilter::prMultinomial;
    case ResamplingMethod::kResidual:
      return mrpt::bayes::CParticleFilter::prResidual;
    case ResamplingMethod::kStratified:
      return mrpt::bayes::CParticleFilter::prStratified;
    case ResamplingMethod::kSystematic:
      return mrpt::bayes::CParticleFilter::prSystematic;
  }
  return mrpt::bayes::CParticleFilter::prSystematic;
}

}  // namespace

std::uint32_t fold_seed(std::uint64_t seed) {
  // splitmix64: nearby seeds (trial 0, 1, 2...) give unrelated generator states.
  const std::uint64_t z = common::splitmix64(seed);
  return static_cast<std::uint32_t>(z ^ (z >> 32U));
}

void configure_particle_filter(mrpt::bayes::CParticleFilter& pf, const FilterConfig& config) {
  pf.m_options.PF_algorithm = mrpt::bayes::CParticleFilter::pfStandardProposal;
  pf.m_options.sampleSize = static_cast<unsigned int>(config.num_particles);
  pf.m_options.adaptiveSampleSize = false;
  pf.m_options.resamplingMethod = to_mrpt(config.resampling);
  pf.m_options.BETA = 0.0;  // ESS() is never < 0: MRPT's own (global-generator) resampling never runs
}

}  // namespace losmimo::localization
