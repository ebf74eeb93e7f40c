#include "losmimo/fusion/scene/scene.h"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/opengl/CEllipsoid3D.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CPointCloud.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/opengl/CText.h>
#include <mrpt/opengl/stock_objects.h>
#include <mrpt/serialization/CArchive.h>

#include "losmimo/placement/common/atomic_file.h"

namespace losmimo::scene {

namespace {
using mrpt::opengl::COpenGLScene;

struct Rgb {
  float r, g, b;
};
constexpr Rgb kTrueColor{0.0f, 0.6f, 0.0f};
constexpr Rgb kBelievedColor{1.0f, 0.55f, 0.0f};
constexpr Rgb kEllipsoidColor{0.2f, 0.4f, 1.0f};
constexpr float kEllipsoidAlpha = 0.35f;
constexpr Rgb kBsColor{0.7f, 0.0f, 0.0f};
constexpr Rgb kBeaconColor{0.8f, 0.0f, 0.8f};
constexpr float kPathPointPx = 4.0f;
constexpr float kMarkerPointPx = 8.0f;

// The bounding box of every finite position, for the size of the axes.
struct Extent {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(HUGE_VAL), hi = Eigen::Vector3d::Constant(-HUGE_VAL);
  void add(const Eigen::Vector3d& p) {
    if (!p.allFinite()) return;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  double diagonal_m() const { return (hi.array() >= lo.array()).all() ? (hi - lo).norm() : 0.0; }
};

class Builder {
 public:
  explicit Builder(COpenGLScene& scene) : scene_(scene) {}

  void points(const std::string& name, const std::vector<Eigen::Vector3d>& p_m, Rgb c, float px) {
    if (p_m.empty()) return;
    auto cloud = mrpt::opengl::CPointCloud::Create();
    for (const Eigen::Vector3d& p : p_m) cloud->insertPoint(p.x(), p.y(), p.z());
    cloud->setPointSize(px);
    add(cloud, name, c);
  }

  void path(const std::string& name, const std::vector<Eigen::Vector3d>& p_m, Rgb c) {
    if (p_m.size() < 2) return;
    auto lines = mrpt::opengl::CSetOfLines::Create();
    for (std::size_t i = 1; i < p_m.size(); ++i) {
      const Eigen::Vector3d &a = p_m[i - 1], &b = p_m[i];
      lines->appendLine(a.x(), a.y(), a.z(), b.x(), b.y(), b.z());
    }
    lines->setLineWidth(2.0f);
    add(lines, name, c);
  }

  void ellipsoid(const std::string& name, const Eigen::Vector3d& mean_m, const Eigen::Matrix3d& cov_m2) {
    auto e = mrpt::opengl::CEllipsoid3D::Create();
    mrpt::math::CMatrixDouble33 cov;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) cov(i, j) = cov_m2(i, j);
    e->setCovMatrix(cov);
    e->setQuantiles(static_cast<float>(kEllipsoidSigmas));
    e->setLocation(mean_m.x(), mean_m.y(), mean_m.z());
    add(e, name, kEllipsoidColor, kEllipsoidAlpha);
    ++stats_.ellipsoids;
  }

  void add(const mrpt::opengl::CRenderizable::Ptr& object, const std::string& name, Rgb c, float alpha = 1.0f) {
    object->setName(name);
    object->setColor(c.r, c.g, c.b, alpha);
    scene_.insert(object);
    ++stats_.objects;
  }

  SceneStats& stats() { return stats_; }

 private:
  COpenGLScene& scene_;
  SceneStats stats_;
};

// Finite positions only; the others counted as skipped.
std::vector<Eigen::Vector3d> finite(const std::vector<Eigen::Vector3d>& p_m, int& skipped) {
  std::vector<Eigen::Vector3d> kept;
  for (const Eigen::Vector3d& p : p_m) {
    if (p.allFinite()) {
      kept.push_back(p);
    } else {
      ++skipped;
    }
  }
  return kept;
}

// A covariance an ellipsoid can show: finite, symmetric to rounding, no negative eigenvalue
// beyond rounding.
bool drawable(const Eigen::Matrix3d& cov_m2) {
  if (!cov_m2.allFinite()) return false;
  const double scale = cov_m2.cwiseAbs().maxCoeff();
  if ((cov_m2 - cov_m2.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale) return false;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov_m2, Eigen::EigenvaluesOnly);
  return eig.eigenvalues().minCoeff() >= -1e-12 * scale;
}

void add_track(Builder& b, const Track& t) {
  int& skipped = b.stats().skipped;
  const std::vector<Eigen::Vector3d> truth = finite(t.true_m, skipped);
  b.points(t.name + "/true_points", truth, kTrueColor, kPathPointPx);
  b.path(t.name + "/true_path", truth, kTrueColor);
  const std::vector<Eigen::Vector3d> belief = finite(t.believed_m, skipped);
  b.points(t.name + "/believed_points", belief, kBelievedColor, kPathPointPx);
  b.path(t.name + "/believed_path", belief, kBelievedColor);
  if (t.believed_cov_m2.empty()) return;
  for (const int k : ellipsoid_indices(static_cast<int>(t.believed_m.size()))) {
    const Eigen::Vector3d& mean = t.believed_m[k];
    const Eigen::Matrix3d& cov = t.believed_cov_m2[k];
    if (!mean.allFinite() || !drawable(cov)) {
      ++skipped;
      continue;
    }
    b.ellipsoid(t.name + "/cov/" + std::to_string(k), mean, 0.5 * (cov + cov.transpose()));
  }
}

void check(const SceneContent& c) {
  std::set<std::string> names;
  for (const Track& t : c.tracks) {
    if (t.name.empty()) throw std::invalid_argument("scene: a track without a name");
    if (!names.insert(t.name).second) throw std::invalid_argument("scene: track name '" + t.name + "' repeated");
    if (!t.believed_cov_m2.empty() && t.believed_cov_m2.size() != t.believed_m.size()) {
      throw std::invalid_argument("scene: track '" + t.name + "' has " + std::to_string(t.believed_cov_m2.size()) +
                                  " covariances for " + std::to_string(t.believed_m.size()) + " beliefs");
    }
  }
}

// gzip with a fixed header (no time stamp, no file name): the same bytes for the same input.
std::string gzip(const unsigned char* data, std::size_t size) {
  z_stream zs{};
  constexpr int kGzipWindowBits = 15 + 16;
  if (deflateInit2(&zs, 6, Z_DEFLATED, kGzipWindowBits, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw std::runtime_error("scene: zlib deflateInit2 failed");
  std::string out(deflateBound(&zs, size), '\0');
  zs.next_in = const_cast<unsigned char*>(data);
  zs.avail_in = static_cast<uInt>(size);
  zs.next_out = reinterpret_cast<unsigned char*>(out.data());
  zs.avail_out = static_cast<uInt>(out.size());
  const int rc = deflate(&zs, Z_FINISH);
  out.resize(zs.total_out);
  deflateEnd(&zs);
  if (rc != Z_STREAM_END) throw std::runtime_error("scene: zlib deflate failed");
  return out;
}
}  // namespace

std::vector<int> ellipsoid_indices(int num_beliefs) {
  std::vector<int> k;
  if (num_beliefs <= 0) return k;
  const int stride = std::max(1, (num_beliefs + kEllipsoidsPerTrack - 1) / kEllipsoidsPerTrack);
  for (int i = 0; i < num_beliefs; i += stride) k.push_back(i);
  if (k.back() != num_beliefs - 1) k.push_back(num_beliefs - 1);
  return k;
}

std::string scene_file_bytes(const SceneContent& content, SceneStats* stats) {
  check(content);
  COpenGLScene scene;
  Builder b(scene);
  Extent extent;
  for (Eigen::Index m = 0; m < content.bs_elements_m.cols(); ++m) extent.add(content.bs_elements_m.col(m));
  for (const Beacon& beacon : content.beacons) extent.add(beacon.position_m);
  for (const Track& t : content.tracks) {
    for (const Eigen::Vector3d& p : t.true_m) extent.add(p);
    for (const Eigen::Vector3d& p : t.believed_m) extent.add(p);
  }
  const double axis_m = extent.diagonal_m() > 0.0 ? kFrameFraction * extent.diagonal_m() : 1.0;
  auto frame = mrpt::opengl::stock_objects::CornerXYZSimple(static_cast<float>(axis_m), 2.0f);
  frame->setName("frame");
  scene.insert(frame);
  ++b.stats().objects;

  std::vector<Eigen::Vector3d> bs;
  for (Eigen::Index m = 0; m < content.bs_elements_m.cols(); ++m) bs.push_back(content.bs_elements_m.col(m));
  b.points("bs_array", finite(bs, b.stats().skipped), kBsColor, kMarkerPointPx);

  std::vector<Eigen::Vector3d> beacons;
  for (const Beacon& beacon : content.beacons) beacons.push_back(beacon.position_m);
  b.points("beacons", finite(beacons, b.stats().skipped), kBeaconColor, kMarkerPointPx);
  for (const Beacon& beacon : content.beacons) {
    if (!beacon.position_m.allFinite()) continue;
    auto label = mrpt::opengl::CText::Create(std::to_string(beacon.id));
    label->setLocation(beacon.position_m.x(), beacon.position_m.y(), beacon.position_m.z());
    b.add(label, "beacon/" + std::to_string(beacon.id), kBeaconColor);
  }
  for (const Track& t : content.tracks) add_track(b, t);

  mrpt::io::CMemoryStream memory;
  auto archive = mrpt::serialization::archiveFrom(memory);
  archive << scene;
  if (stats) *stats = b.stats();
  return gzip(static_cast<const unsigned char*>(memory.getRawBufferData()), memory.getTotalBytesCount());
}

SceneStats write_scene_file(const SceneContent& content, const std::string& path) {
  SceneStats stats;
  const std::string bytes = scene_file_bytes(content, &stats);
  common::write_file_atomically(path, bytes);
  return stats;
}

}  // namespace losmimo::scene
