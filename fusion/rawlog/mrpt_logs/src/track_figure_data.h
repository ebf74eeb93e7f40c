// The data files of a replay's track.png, shared by the range-only and bearing-range figures.
#pragma once

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "losmimo/localization/pose/range_model.h"

namespace losmimo::mrpt_logs {

// 2-sigma ellipses of the beliefs' (x, y) block, about 20 along the track, as gnuplot's
// "with ellipses" takes them: x,y,major,minor,angle (full axes in metres, angle in degrees).
// Rows: anything with belief.mean (x, y first) and belief.cov (x, y block top-left).
template <typename Rows>
void write_ellipses_dat(const Rows& track, const std::filesystem::path& path) {
  std::ofstream f(path);
  const std::size_t every = std::max<std::size_t>(1, track.size() / 20);
  for (std::size_t k = 0; k < track.size(); k += every) {
    const auto& b = track[k].belief;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(b.cov.template topLeftCorner<2, 2>());
    const Eigen::Vector2d l = es.eigenvalues().cwiseMax(0.0);
    const Eigen::Vector2d major = es.eigenvectors().col(1);
    f << b.mean(0) << "," << b.mean(1) << "," << 4.0 * std::sqrt(l(1)) << "," << 4.0 * std::sqrt(l(0)) << ","
      << std::atan2(major(1), major(0)) * 180.0 / 3.14159265358979323846 << "\n";
  }
  if (!f) throw std::runtime_error(path.string() + ": write failed");
}

// One "id,x,y,z" row per beacon or landmark.
inline void write_map_dat(const localization::BeaconMap& map, const std::filesystem::path& path) {
  std::ofstream f(path);
  for (const auto& [id, p] : map.beacons()) f << id << "," << p.x() << "," << p.y() << "," << p.z() << "\n";
  if (!f) throw std::runtime_error(path.string() + ": write failed");
}

}  // namespace losmimo::mrpt_logs
