#include "losmimo/coevaluation/extensions.h"

#include <algorithm>

#include "losmimo/coevaluation/coevaluation.h"

namespace losmimo::coevaluation {

namespace {

// "no <algorithm> in [coevaluation] <key>" for each of the algorithms that some keys serve alone
// (gd_pf: num_particles; gd_ekf_ceres: the refinement's; ura_ekf: [ura] and ura_variant; cap_ekf: [cap]) that the
// run does not list.
std::vector<std::string> absent(const std::vector<CoevalAlgorithm>& listed, const std::string& key) {
  std::vector<std::string> conditions;
  for (const CoevalAlgorithm a :
       {CoevalAlgorithm::kGdPf, CoevalAlgorithm::kGdEkfCeres, CoevalAlgorithm::kUraEkf, CoevalAlgorithm::kCapEkf}) {
    if (std::find(listed.begin(), listed.end(), a) == listed.end()) {
      conditions.push_back("no " + to_string(a) + " in [coevaluation] " + key);
    }
  }
  return conditions;
}

}  // namespace

experiment::ExperimentExtensions experiment_extensions() {
  experiment::ExperimentExtension noise = beacon_noise_extension();
  noise.unused_conditions = [](const experiment::ExperimentSettings& s) {
    return absent(load_coevaluation_settings(s).algorithms, "algorithms");
  };
  experiment::ExperimentExtension outage = beacon_outage_extension();
  outage.unused_conditions = [](const experiment::ExperimentSettings& s) {
    return absent(load_coevaluation_settings(s).outage_algorithms, "outage_algorithms");
  };
  return {noise, outage};
}

}  // namespace losmimo::coevaluation
