// The scene builder (fusion/scene) on hand-made content, read back through MRPT's own loader.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>

#include <mrpt/opengl/CText.h>
#include "losmimo/fusion/scene/scene.h"
#include "scene_reader.h"
#include "temp_dir.h"

namespace losmimo::scene {
namespace {
namespace fs = std::filesystem;
using test_support::load_scene;

constexpr double kFloatTol_m = 1e-4;  // MRPT keeps positions as float: ~6e-5 m at 1 km
constexpr double kExact = 1e-12;

fs::path temp_file(const std::string& name) {
  fs::create_directories(test_support::scene_temp_root());
  return test_support::scene_temp_root() / name;
}

// A 2 x 2 array at 0.25 m, two beacons, one UAV with 3 true and 25 believed positions near 1 km.
SceneContent hand_content() {
  SceneContent c;
  c.bs_elements_m.resize(3, 4);
  c.bs_elements_m << 0, 0, 0, 0,     //
      -0.125, 0.125, -0.125, 0.125,  //
      -0.125, -0.125, 0.125, 0.125;
  c.beacons = {{7, Eigen::Vector3d(1.0, 2.0, 3.0)}, {12, Eigen::Vector3d(-4.0, 5.5, 0.0)}};
  Track t;
  t.name = "uav01";
  t.true_m = {{1000.0, 1.0, 2.0}, {1000.5, 1.5, 2.5}, {1001.0, 2.0, 3.0}};
  for (int k = 0; k < 25; ++k) {
    t.believed_m.emplace_back(1000.0 + 0.1 * k, -2.0 + 0.01 * k, 3.0);
    Eigen::Matrix3d P = Eigen::Vector3d(0.01 * (k + 1), 0.02, 0.03).asDiagonal();
    P(0, 1) = P(1, 0) = 0.001;
    t.believed_cov_m2.push_back(P);
  }
  c.tracks.push_back(t);
  return c;
}

TEST(SceneFile, HandContent_EveryObjectReadsBackThroughMrpt) {
  const SceneContent c = hand_content();
  const fs::path path = temp_file("hand.3Dscene");
  const SceneStats stats = write_scene_file(c, path.string());
  const auto s = load_scene(path.string());
  ASSERT_TRUE(s.loaded);
  // frame, bs_array, beacons, 2 labels, true points + path, believed points + path, 9 ellipsoids
  EXPECT_EQ(s.objects, 18u);
  EXPECT_EQ(stats.objects, 18);
  EXPECT_EQ(stats.skipped, 0);
  ASSERT_TRUE(s.has("frame"));

  const auto bs = s.points("bs_array");
  ASSERT_EQ(bs.size(), 4u);
  EXPECT_NEAR(bs[3].y(), 0.125, kFloatTol_m);
  EXPECT_NEAR(bs[3].z(), 0.125, kFloatTol_m);
  EXPECT_NEAR(bs[0].y(), -0.125, kFloatTol_m);

  const auto beacons = s.points("beacons");
  ASSERT_EQ(beacons.size(), 2u);
  EXPECT_NEAR(beacons[1].x(), -4.0, kFloatTol_m);
  EXPECT_NEAR(beacons[1].y(), 5.5, kFloatTol_m);
  const auto label = s.get<mrpt::opengl::CText>("beacon/12");
  ASSERT_TRUE(label);
  EXPECT_EQ(label->getString(), "12");
  EXPECT_NEAR(label->getPoseX(), -4.0, kFloatTol_m);

  const auto truth = s.points("uav01/true_points");
  ASSERT_EQ(truth.size(), 3u);
  EXPECT_NEAR(truth[1].x(), 1000.5, kFloatTol_m);
  EXPECT_NEAR(truth[2].z(), 3.0, kFloatTol_m);
  const auto true_path = s.get<mrpt::opengl::CSetOfLines>("uav01/true_path");
  ASSERT_TRUE(true_path);
  EXPECT_EQ(true_path->getLineCount(), 2u);
  double x0, y0, z0, x1, y1, z1;
  true_path->getLineByIndex(1, x0, y0, z0, x1, y1, z1);
  EXPECT_NEAR(x0, 1000.5, kFloatTol_m);
  EXPECT_NEAR(z1, 3.0, kFloatTol_m);

  EXPECT_EQ(s.points("uav01/believed_points").size(), 25u);
  const auto believed_path = s.get<mrpt::opengl::CSetOfLines>("uav01/believed_path");
  ASSERT_TRUE(believed_path);
  EXPECT_EQ(believed_path->getLineCount(), 24u);

  // 25 beliefs: stride ceil(25 / 10) = 3, so 0, 3, ..., 24 (24 is also the last).
  EXPECT_EQ(s.names_with("uav01/cov/").size(), 9u);
  EXPECT_EQ(stats.ellipsoids, 9);
  for (const int k : {0, 3, 6, 9, 12, 15, 18, 21, 24}) {
    const auto e = s.get<mrpt::opengl::CEllipsoid3D>("uav01/cov/" + std::to_string(k));
    ASSERT_TRUE(e) << k;
    EXPECT_NEAR(e->getPoseX(), 1000.0 + 0.1 * k, kFloatTol_m);  // MRPT stores object poses as float
    EXPECT_NEAR(e->getPoseY(), -2.0 + 0.01 * k, kFloatTol_m);
    const auto P = e->getCovMatrix();
    EXPECT_NEAR(P(0, 0), 0.01 * (k + 1), kExact);
    EXPECT_NEAR(P(1, 0), 0.001, kExact);
    EXPECT_NEAR(P(2, 2), 0.03, kExact);
    EXPECT_NEAR(e->getQuantiles(), kEllipsoidSigmas, 1e-6);
  }
  EXPECT_FALSE(s.has("uav01/cov/1"));
}

TEST(SceneFile, EllipsoidIndices_HandValues) {
  EXPECT_EQ(ellipsoid_indices(0), std::vector<int>{});
  EXPECT_EQ(ellipsoid_indices(1), std::vector<int>{0});
  EXPECT_EQ(ellipsoid_indices(10), (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
  EXPECT_EQ(ellipsoid_indices(11), (std::vector<int>{0, 2, 4, 6, 8, 10}));
  EXPECT_EQ(ellipsoid_indices(21), (std::vector<int>{0, 3, 6, 9, 12, 15, 18, 20}));
}

TEST(SceneFile, NonFiniteAndIndefinite_LeftOutAndCounted) {
  SceneContent c = hand_content();
  Track& t = c.tracks[0];
  t.true_m[1].y() = std::numeric_limits<double>::quiet_NaN();
  t.believed_cov_m2[3](0, 0) = -1.0;  // an eigenvalue below 0
  t.believed_cov_m2[6](2, 2) = std::numeric_limits<double>::infinity();
  SceneStats stats;
  const std::string bytes = scene_file_bytes(c, &stats);
  EXPECT_EQ(stats.skipped, 3);
  EXPECT_EQ(stats.ellipsoids, 7);
  const fs::path path = temp_file("skipped.3Dscene");
  write_scene_file(c, path.string());
  const auto s = load_scene(path.string());
  ASSERT_TRUE(s.loaded);
  const auto truth = s.points("uav01/true_points");
  ASSERT_EQ(truth.size(), 2u);
  EXPECT_NEAR(truth[1].x(), 1001.0, kFloatTol_m);  // the path joins the finite neighbours
  EXPECT_FALSE(s.has("uav01/cov/3"));
  EXPECT_FALSE(s.has("uav01/cov/6"));
  EXPECT_TRUE(s.has("uav01/cov/9"));
}

TEST(SceneFile, SameContent_SameBytes_OtherContent_OtherBytes) {
  const std::string a = scene_file_bytes(hand_content());
  EXPECT_EQ(a, scene_file_bytes(hand_content()));
  ASSERT_GE(a.size(), 2u);  // gzip, as COpenGLScene::saveToFile writes
  EXPECT_EQ(static_cast<unsigned char>(a[0]), 0x1f);
  EXPECT_EQ(static_cast<unsigned char>(a[1]), 0x8b);
  SceneContent other = hand_content();
  other.tracks[0].believed_m[4].x() += 1e-6;
  EXPECT_NE(a, scene_file_bytes(other));
  // The reader can tell: a truncated file does not load.
  const fs::path cut = temp_file("cut.3Dscene");
  std::ofstream(cut, std::ios::binary) << a.substr(0, a.size() / 2);
  EXPECT_FALSE(load_scene(cut.string()).loaded);
}

TEST(SceneFile, InconsistentContent_Refused) {
  SceneContent c = hand_content();
  c.tracks[0].believed_cov_m2.pop_back();
  EXPECT_THROW(scene_file_bytes(c), std::invalid_argument);
  c = hand_content();
  c.tracks.push_back(c.tracks[0]);
  EXPECT_THROW(scene_file_bytes(c), std::invalid_argument);
  c = hand_content();
  c.tracks[0].name.clear();
  EXPECT_THROW(scene_file_bytes(c), std::invalid_argument);
}

TEST(SceneFile, UnwritableFolder_ThrowsAndLeavesNothing) {
  const fs::path dir = temp_file("no_such_folder");
  const fs::path path = dir / "x.3Dscene";
  EXPECT_THROW(write_scene_file(hand_content(), path.string()), std::runtime_error);
  EXPECT_FALSE(fs::exists(dir));
}

}  // namespace
}  // namespace losmimo::scene
