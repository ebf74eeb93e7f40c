#pragma once
// The sensorLabel convention of the rawlogs losmimo writes and reads: "UAV<nn>_<suffix>", nn the
// UAV index, two digits or more (UAV07_BEACON, UAV123_DR). losmimo's own streams are the
// suffixes of rawlog/format.h; foreign logs and range-only logs are split by UAV with the same
// prefix, and stock rawlog-edit --keep-label selects by the whole label.

#include <optional>
#include <string>

namespace losmimo::rawlog_io {

// "UAV07_BEACON" for (7, "BEACON").
std::string uav_label(int uav, const std::string& suffix);

struct UavLabelParts {
  int uav = 0;
  std::string suffix;  // what follows "UAVnn_", not empty
};
// Splits "UAV<digits>_<suffix>" (uav < 100000); nullopt for anything else.
std::optional<UavLabelParts> split_uav_label(const std::string& label);

}  // namespace losmimo::rawlog_io
