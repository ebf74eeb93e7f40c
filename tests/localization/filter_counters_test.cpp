// FilterCounters::operator+= (filter_counters.h) adds every count, each into its own field.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "losmimo/localization/filter_counters.h"

namespace losmimo::localization {
namespace {

// Every field of FilterCounters, in declaration order. A new field must be added here and to
// operator+=; the size check below fails until it is.
std::vector<std::int64_t FilterCounters::*> all_fields() {
  return {&FilterCounters::epochs,
          &FilterCounters::beacons_received,
          &FilterCounters::beacons_fused,
          &FilterCounters::rejected_non_finite_displacement,
          &FilterCounters::rejected_non_finite_beacon,
          &FilterCounters::rejected_out_of_range_beacon,
          &FilterCounters::rejected_geometry,
          &FilterCounters::rejected_gate,
          &FilterCounters::resets,
          &FilterCounters::covariance_repairs,
          &FilterCounters::resamplings,
          &FilterCounters::non_finite_state,
          &FilterCounters::ranges_received,
          &FilterCounters::ranges_fused,
          &FilterCounters::rejected_non_finite_range,
          &FilterCounters::rejected_unknown_beacon,
          &FilterCounters::rejected_outside_sensor_limits,
          &FilterCounters::rejected_implausible_range,
          &FilterCounters::rejected_range_geometry,
          &FilterCounters::rejected_range_gate};
}

TEST(FilterCounters, PlusEquals_AddsEveryFieldIntoItself) {
  const auto fields = all_fields();
  ASSERT_EQ(sizeof(FilterCounters), fields.size() * sizeof(std::int64_t));
  FilterCounters a, b;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    a.*fields[i] = static_cast<std::int64_t>(i + 1);
    b.*fields[i] = static_cast<std::int64_t>(100 * (i + 1));
  }
  a += b;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    EXPECT_EQ(a.*fields[i], static_cast<std::int64_t>(101 * (i + 1))) << "field " << i;
    EXPECT_EQ(b.*fields[i], static_cast<std::int64_t>(100 * (i + 1))) << "field " << i;
  }
}

}  // namespace
}  // namespace losmimo::localization
