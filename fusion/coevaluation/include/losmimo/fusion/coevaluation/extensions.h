#pragma once
// The sweep kinds fusion adds to `losmimo-experiment` (experiment/extension.h): the
// co-evaluation of estimators and placement (coevaluation.h: the sweeps beacon_noise_m,
// beacon_outage and bs_misalignment_rad). The app passes these to run_experiment_app.

#include "losmimo/placement/experiment/extension.h"

namespace losmimo::coevaluation {

experiment::ExperimentExtensions experiment_extensions();

}  // namespace losmimo::coevaluation
