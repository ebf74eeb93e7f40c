#include "losmimo/fusion/experiment_extensions.h"

#include "losmimo/fusion/coevaluation.h"

namespace losmimo::fusion {

placement::ExperimentExtensions experiment_extensions() {
  return {beacon_noise_extension(), beacon_outage_extension()};
}

}  // namespace losmimo::fusion
