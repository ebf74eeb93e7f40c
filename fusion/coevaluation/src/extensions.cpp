#include "losmimo/coevaluation/extensions.h"

#include "losmimo/coevaluation/coevaluation.h"

namespace losmimo::coevaluation {

experiment::ExperimentExtensions experiment_extensions() {
  return {beacon_noise_extension(), beacon_outage_extension()};
}

}  // namespace losmimo::coevaluation
