#pragma once
// A scratch folder of this test process's own, removed when it exits (ctest runs every case as
// its own process, two at a time).
#include <filesystem>
#include <string>
#include <system_error>

#include <unistd.h>

namespace losmimo::test_support {

inline const std::filesystem::path& scene_temp_root() {
  struct Dir {
    std::filesystem::path path;
    ~Dir() {
      std::error_code ignored;
      std::filesystem::remove_all(path, ignored);
    }
  };
  static const Dir dir{std::filesystem::temp_directory_path() / "losmimo_scene_tests" /
                       std::to_string(static_cast<long long>(::getpid()))};
  return dir.path;
}

// A fresh, empty folder `name` in it.
inline std::filesystem::path scene_temp_dir(const std::string& name) {
  const std::filesystem::path d = scene_temp_root() / name;
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

}  // namespace losmimo::test_support
