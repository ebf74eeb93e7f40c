#include "losmimo/fusion/experiment_extensions.h"

namespace losmimo::fusion {

placement::ExperimentExtensions experiment_extensions() { return {}; }

}  // namespace losmimo::fusion
