#pragma once
// A .3Dscene read back through MRPT as stock SceneViewer3D reads it (a CFileGZInputStream and
// CArchive >> COpenGLScene; its imports say so), its objects by name: the tests check the
// file, not the builder's own data.
#include <exception>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/opengl/CEllipsoid3D.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CPointCloud.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/serialization/CArchive.h>

namespace losmimo::test_support {

struct LoadedScene {
  bool loaded = false;
  std::map<std::string, mrpt::opengl::CRenderizable::Ptr> by_name;
  std::size_t objects = 0;  // top-level objects, named or not

  template <typename T>
  typename T::Ptr get(const std::string& name) const {
    const auto it = by_name.find(name);
    return it == by_name.end() ? nullptr : std::dynamic_pointer_cast<T>(it->second);
  }
  bool has(const std::string& name) const { return by_name.count(name) > 0; }
  // The points of a CPointCloud (empty when there is none of that name).
  std::vector<Eigen::Vector3d> points(const std::string& name) const {
    std::vector<Eigen::Vector3d> p;
    if (const auto cloud = get<mrpt::opengl::CPointCloud>(name)) {
      for (std::size_t i = 0; i < cloud->size(); ++i) {
        const auto q = cloud->getPoint3Df(i);
        p.emplace_back(q.x, q.y, q.z);
      }
    }
    return p;
  }
  // The names starting with `prefix`.
  std::vector<std::string> names_with(const std::string& prefix) const {
    std::vector<std::string> n;
    for (const auto& [name, object] : by_name) {
      if (name.rfind(prefix, 0) == 0) n.push_back(name);
    }
    return n;
  }
};

inline LoadedScene load_scene(const std::string& path) {
  LoadedScene s;
  mrpt::opengl::COpenGLScene scene;
  try {
    mrpt::io::CFileGZInputStream f(path);
    mrpt::serialization::archiveFrom(f) >> scene;
    s.loaded = true;
  } catch (const std::exception&) {
    return s;
  }
  const auto viewport = scene.getViewport("main");
  if (!viewport) return s;
  for (const auto& object : *viewport) {
    ++s.objects;
    if (object) s.by_name[object->getName()] = object;
  }
  return s;
}

}  // namespace losmimo::test_support
