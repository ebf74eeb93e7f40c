#pragma once
// What both filter families count: every epoch, every input received, fused or rejected (for
// exactly one reason), every reset, repair and resampling. The beacon fields are the position
// filters' (position/filter.h), the range fields the pose filters' (pose/filter.h).

#include <cstdint>

namespace losmimo::localization {

struct FilterCounters {
  std::int64_t epochs = 0;
  std::int64_t beacons_received = 0;  // step() calls with a beacon
  std::int64_t beacons_fused = 0;
  std::int64_t rejected_non_finite_displacement = 0;
  std::int64_t rejected_non_finite_beacon = 0;  // non-finite, or range_m <= 0
  // Finite but physically implausible: range_m > max_beacon_range_m, or elevation outside
  // [-pi/2, pi/2] after wrapping. Not gate rejections: they never lead to a reset.
  std::int64_t rejected_out_of_range_beacon = 0;
  std::int64_t rejected_geometry = 0;  // prediction too close to the array's z axis
  std::int64_t rejected_gate = 0;
  std::int64_t resets = 0;              // re-initialisations from a beacon fix
  std::int64_t covariance_repairs = 0;  // eigenvalues raised to min_variance_m2
  std::int64_t resamplings = 0;         // particle filter only
  // Epochs in which the state became non-finite (the covariance was reset, see above).
  std::int64_t non_finite_state = 0;

  // Ranges to mapped beacons (the pose filters, pose/filter.h): every reading of every scan is
  // counted once in ranges_received, then either fused (ranges_fused, which includes the
  // readings of a reset's fix) or rejected for exactly one reason (range_model.h's screen,
  // then the filter's geometry and gate checks).
  std::int64_t ranges_received = 0;
  std::int64_t ranges_fused = 0;
  std::int64_t rejected_non_finite_range = 0;       // non-finite or <= 0 (or its scan's stdError)
  std::int64_t rejected_unknown_beacon = 0;         // ID not in the beacon map
  std::int64_t rejected_outside_sensor_limits = 0;  // outside [min, max]SensorDistance
  std::int64_t rejected_implausible_range = 0;      // above max_beacon_range_m
  std::int64_t rejected_range_geometry = 0;         // predicted sensor-beacon distance ~ 0
  std::int64_t rejected_range_gate = 0;

  std::int64_t rejected_ranges() const {
    return rejected_non_finite_range + rejected_unknown_beacon + rejected_outside_sensor_limits +
           rejected_implausible_range + rejected_range_geometry + rejected_range_gate;
  }
  std::int64_t rejected_total() const {
    return rejected_non_finite_displacement + rejected_non_finite_beacon + rejected_out_of_range_beacon +
           rejected_geometry + rejected_gate + rejected_ranges();
  }

  // Field by field: the counts of several filter runs (e.g. a start fix and the filter after it).
  FilterCounters& operator+=(const FilterCounters& other);
};

}  // namespace losmimo::localization
