// The bs_misalignment_rad sweep (coevaluation.h): the co-evaluation's rows under a BS array turned
// off its bearing, a common-mode error no filter knows.
#include <stdexcept>

#include "losmimo/fusion/coevaluation/coevaluation.h"
#include "losmimo/fusion/coevaluation/report.h"
#include "trial_parts.h"

namespace losmimo::coevaluation {

std::vector<experiment::TrialRecord> run_misalignment_trial(const experiment::ExperimentSettings& s,
                                                            const CoevaluationSettings& c, int point, int trial) {
  const experiment::SweepPoints* sweep = s.sweep(kSweepMisalignment);
  if (!sweep) throw std::invalid_argument("run_misalignment_trial: the settings have no bs_misalignment_rad sweep");
  // The point's misalignment replaces [closed_loop] bs_azimuth_bias_rad in every sensor model
  // (detail::simulator_config reads it there).
  CoevaluationSettings at_point = c;
  at_point.closed_loop.simulator.bs_azimuth_bias_rad = sweep->values.at(static_cast<std::size_t>(point));
  return detail::run_rows(s, at_point, c.misalignment_algorithms, kSweepMisalignment, point, trial,
                          c.misalignment_beacon_noise_m);
}

experiment::ExperimentExtension misalignment_extension() {
  return detail::make_extension(
      kSweepMisalignment, [](const CoevaluationSettings& c) { return c.misalignment_values_rad; },
      &run_misalignment_trial, write_misalignment_figures, misalignment_report_section);
}

}  // namespace losmimo::coevaluation
