#include "losmimo/localization/filter_counters.h"

namespace losmimo::localization {

FilterCounters& FilterCounters::operator+=(const FilterCounters& o) {
  epochs += o.epochs;
  beacons_received += o.beacons_received;
  beacons_fused += o.beacons_fused;
  rejected_non_finite_displacement += o.rejected_non_finite_displacement;
  rejected_non_finite_beacon += o.rejected_non_finite_beacon;
  rejected_out_of_range_beacon += o.rejected_out_of_range_beacon;
  rejected_geometry += o.rejected_geometry;
  rejected_gate += o.rejected_gate;
  resets += o.resets;
  covariance_repairs += o.covariance_repairs;
  resamplings += o.resamplings;
  non_finite_state += o.non_finite_state;
  ranges_received += o.ranges_received;
  ranges_fused += o.ranges_fused;
  rejected_non_finite_range += o.rejected_non_finite_range;
  rejected_unknown_beacon += o.rejected_unknown_beacon;
  rejected_outside_sensor_limits += o.rejected_outside_sensor_limits;
  rejected_implausible_range += o.rejected_implausible_range;
  rejected_range_geometry += o.rejected_range_geometry;
  rejected_range_gate += o.rejected_range_gate;
  return *this;
}

}  // namespace losmimo::localization
