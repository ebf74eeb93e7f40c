#pragma once
// A plain beacon list file, as MRPT's ground-truth beacon files (RO-SLAM_demo_ground_truth.txt):
// one beacon per line, `ID x y z` [m, map frame], whitespace-separated; further columns are
// ignored, as are empty lines and lines starting with '#', '%' or "//".

#include <string>

#include "losmimo/localization/pose/range_model.h"

namespace losmimo::mrpt_logs {

// Throws common::InputError naming the file, the line and the bad field and value (a missing
// or non-numeric column, a negative or non-integer ID, a duplicate ID, a non-finite position),
// or "no beacon" for a file without one; std::runtime_error if it cannot be opened.
localization::BeaconMap read_beacon_list(const std::string& path);
localization::BeaconMap parse_beacon_list(const std::string& text, const std::string& where);

}  // namespace losmimo::mrpt_logs
