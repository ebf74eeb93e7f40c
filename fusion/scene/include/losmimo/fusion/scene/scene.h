#pragma once
// A run drawn as an MRPT 3-D scene (`.3Dscene`, an mrpt::opengl::COpenGLScene serialized with
// MRPT's CArchive and gzip-compressed, as COpenGLScene::saveToFile writes it), for MRPT's stock
// viewer: `SceneViewer3D FILE.3Dscene` (Debian's mrpt-apps). docs/scenes.md describes the contents.
//
// Frame: the data's own, metres: losmimo's BS frame (BS array in the y-z plane at the origin,
// boresight +x, z up) for missions and experiment runs, the log's map frame for MRPT's logs.
// The scene neither moves nor rescales anything, so a position read back equals the input up to
// float rounding (MRPT stores points, line ends and object poses as float: ~6e-5 m at 1 km);
// covariances keep doubles.
//
// Objects, each named (CRenderizable::getName) so that a user or a test can find it:
//   frame                    CSetOfObjects  x (red), y (green), z (blue) axes at the origin,
//                                           kFrameFraction of the scene's extent long
//   bs_array                 CPointCloud    one point per BS antenna element (dark red)
//   beacons                  CPointCloud    one point per beacon or anchor (magenta)
//   beacon/<id>              CText          the beacon's ID, at the beacon
//   <track>/true_points      CPointCloud    the true positions, one per epoch (green)
//   <track>/true_path        CSetOfLines    the same joined in time order (green)
//   <track>/believed_points  CPointCloud    the belief means, one per epoch (orange)
//   <track>/believed_path    CSetOfLines    joined (orange)
//   <track>/cov/<k>          CEllipsoid3D   the 3x3 position covariance of belief k, centred on
//                                           its mean, kEllipsoidSigmas "sigmas" (translucent blue),
//                                           at the beliefs ellipsoid_indices() names
// An object with nothing to show is left out (no truth: no true_points / true_path; a path of
// one point has no line). A non-finite position is left out of its points and path, a covariance
// that is non-finite or not positive semi-definite gets no ellipsoid; both are counted in
// SceneStats::skipped.
#include <string>
#include <vector>

#include <Eigen/Core>

namespace losmimo::scene {

// One moving body (a UAV, or the robot of an MRPT log), in the scene frame.
struct Track {
  std::string name;                              // object-name prefix, e.g. "uav01", "gd_fig1/uav03"
  std::vector<Eigen::Vector3d> true_m;           // true positions, in time order (empty: unknown)
  std::vector<Eigen::Vector3d> believed_m;       // belief means, in time order (empty: none)
  std::vector<Eigen::Matrix3d> believed_cov_m2;  // empty, or one per believed_m (m^2)
};

struct Beacon {
  int id = 0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
};

struct SceneContent {
  Eigen::Matrix3Xd bs_elements_m = Eigen::Matrix3Xd(3, 0);  // 3 x Nt (none: no bs_array)
  std::vector<Beacon> beacons;                              // none: no beacons object
  std::vector<Track> tracks;
};

// About 10 ellipsoids per track whatever its length: belief 0, every stride-th after it, and
// the last (stride = ceil(n / kEllipsoidsPerTrack), at least 1).
inline constexpr int kEllipsoidsPerTrack = 10;
// The ellipsoids' size in MRPT's "quantiles": 3 holds 97.1% of a 3-D Gaussian's mass.
inline constexpr double kEllipsoidSigmas = 3.0;
inline constexpr double kFrameFraction = 0.05;

// The indices (ascending) of the beliefs of a track of `num_beliefs` that get an ellipsoid.
std::vector<int> ellipsoid_indices(int num_beliefs);

struct SceneStats {
  int objects = 0;  // top-level objects in the scene
  int ellipsoids = 0;
  int skipped = 0;  // non-finite positions and unusable covariances left out
};

// The scene's file content (gzip of the serialized COpenGLScene), the same bytes for the same
// content. Throws std::invalid_argument if a track has covariances but not one per belief, or a
// track name is empty or repeated.
std::string scene_file_bytes(const SceneContent& content, SceneStats* stats = nullptr);

// Writes scene_file_bytes atomically (common/atomic_file.h: `<path>.tmp`, renamed over `path`);
// throws std::runtime_error naming the file if it cannot be written.
SceneStats write_scene_file(const SceneContent& content, const std::string& path);

}  // namespace losmimo::scene
