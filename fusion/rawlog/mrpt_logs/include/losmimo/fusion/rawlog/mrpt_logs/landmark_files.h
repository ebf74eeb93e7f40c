#pragma once
// MRPT's ground-truth files beside the kf-slam datasets (mrpt-common):
//  - landmarks (kf-slam_*_ground_truth.txt): one landmark per line, whitespace-separated, x y z
//    [m, map frame] first and the landmark ID last (the columns between are ignored);
//  - robot path (kf-slam_*_ground_truth_robot_path.txt): '%' comment lines, then one row
//    "x y z yaw pitch roll" [m, rad] per sensory frame: row k is the pose at the log's k-th
//    sensory frame (0-based; checked in tests/rawlog/bearing_replay_test.cpp: the readings of
//    frame k agree with row k to the sensor noise, with no other row).
// Empty lines and lines starting with '#', '%' or "//" are skipped in both.

#include <string>
#include <vector>

#include "losmimo/localization/pose/landmark_model.h"
#include "losmimo/localization/pose/range_model.h"

namespace losmimo::mrpt_logs {

// Throws common::InputError naming the file, the line and the bad field and value (fewer than
// four columns, a non-numeric or non-finite coordinate, a negative or non-integer ID, a
// duplicate ID), or "no landmark" for a file without one; std::runtime_error if it cannot be
// opened.
localization::BeaconMap read_landmark_file(const std::string& path);
localization::BeaconMap parse_landmark_file(const std::string& text, const std::string& where);

// Throws common::InputError naming the line and column, or "no row"; std::runtime_error if the
// file cannot be opened.
std::vector<localization::Pose6> read_robot_path(const std::string& path);
std::vector<localization::Pose6> parse_robot_path(const std::string& text, const std::string& where);

}  // namespace losmimo::mrpt_logs
