#include "losmimo/fusion/coevaluation/extensions.h"

#include <algorithm>

#include "losmimo/fusion/coevaluation/coevaluation.h"

namespace losmimo::coevaluation {

namespace {

// The conditions under which keys that only some rows read are unused (apps/unused_keys.h names
// them): "no <estimator> estimator in [coevaluation] <key>" for each estimator that has keys of its
// own (pf: num_particles; ekf_ceres: the refinement's) and "no <planner> planner in ..." for cap
// and the URAs ([cap], [ura]), when no listed row has it; "no ura_ekf in ..." for ura_variant.
std::vector<std::string> absent(const std::vector<CoevalRow>& listed, const std::string& key) {
  const auto has = [&](auto&& pred) { return std::any_of(listed.begin(), listed.end(), pred); };
  std::vector<std::string> conditions;
  for (const std::string& estimator : estimator_names()) {
    if (estimator_entry(estimator).keys.empty()) continue;
    if (!has([&](const CoevalRow& r) { return r.estimator == estimator; })) {
      conditions.push_back("no " + estimator + " estimator in [coevaluation] " + key);
    }
  }
  if (!has([](const CoevalRow& r) { return r.planner.rfind("ura", 0) == 0; })) {
    conditions.push_back("no URA planner in [coevaluation] " + key);
  }
  if (!has([](const CoevalRow& r) { return r.name == "ura_ekf"; })) {
    conditions.push_back("no ura_ekf in [coevaluation] " + key);
  }
  if (!has([](const CoevalRow& r) { return r.planner == "cap"; })) {
    conditions.push_back("no cap planner in [coevaluation] " + key);
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
  experiment::ExperimentExtension misalignment = misalignment_extension();
  misalignment.unused_conditions = [](const experiment::ExperimentSettings& s) {
    return absent(load_coevaluation_settings(s).misalignment_algorithms, "misalignment_algorithms");
  };
  return {noise, outage, misalignment};
}

}  // namespace losmimo::coevaluation
