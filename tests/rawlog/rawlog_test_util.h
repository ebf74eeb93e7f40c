#pragma once
// Shared fixtures of the rawlog tests: a small mission and file helpers.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <system_error>

#include <unistd.h>

#include "losmimo/placement/common/ini_config.h"
#include "losmimo/fusion/rawlog/mission/log.h"
#include "losmimo/fusion/rawlog/mission/mission.h"
#include "support/files.h"

namespace losmimo::test_support {

// 2 x 2 BS, 4 UAVs, 12 iterations at most; EKF + Ceres (CSI from the loop), UAV 1 without
// beacon for epochs 3-6: every stream and an outage, in well under a second. `closed_loop_keys`:
// further "key = value" lines of [closed_loop] (e.g. "faults = unresponsive:2:4\n").
inline rawlog::MissionConfig small_mission(const std::string& filter = "ekf", bool refine = true,
                                           const std::string& closed_loop_keys = "") {
  common::IniConfig ini = common::IniConfig::from_string(
      "[scenario]\nbs_rows = 2\nbs_cols = 2\nnum_uavs = 4\n"
      "[errors]\nsigma_act_m = 0.02\n"
      "[placement]\nmax_iterations = 12\n"
      "[closed_loop]\nfilter = " +
          filter + "\nrefine = " + (refine ? "true" : "false") + "\nnum_particles = 300\noutages = 1:3:4\n" +
          closed_loop_keys + "[mission]\nseed = 11\nstart_seed = 5\n",
      "small_mission");
  return rawlog::load_mission_config(ini);
}

inline rawlog::MissionLog load_log(const std::string& path) {
  rawlog_io::RawlogReader reader = rawlog_io::RawlogReader::open_file(path);
  return rawlog::load_mission_log(reader);
}

// A scratch folder of this process's own, removed when it exits. ctest runs every case as its own
// process, two at a time: cases that record one shared log under the same name (a function-local
// static) would otherwise read each other's half-written file.
inline const std::filesystem::path& process_temp_dir() {
  struct Dir {
    std::filesystem::path path;
    ~Dir() {
      std::error_code ignored;
      std::filesystem::remove_all(path, ignored);
    }
  };
  static const Dir dir{std::filesystem::temp_directory_path() / "losmimo_rawlog_tests" /
                       std::to_string(static_cast<long long>(::getpid()))};
  return dir.path;
}

inline std::string temp_path(const std::string& name) {
  std::filesystem::create_directories(process_temp_dir());
  return (process_temp_dir() / name).string();
}

inline void write_file_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream f(path, std::ios::binary);
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

inline std::string source_path(const std::string& relative) { return std::string(LOSMIMO_SOURCE_DIR) + "/" + relative; }

}  // namespace losmimo::test_support
