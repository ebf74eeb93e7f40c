#include "losmimo/fusion/rawlog/mrpt_logs/mrpt_app_config.h"
#include "losmimo/placement/common/text.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include <mrpt/config/CConfigFile.h>

#include "losmimo/placement/common/format.h"
#include "losmimo/placement/common/input_error.h"

namespace losmimo::mrpt_logs {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;
// The stock apps are 2-D: the robot is on the map's z = 0 plane (a box of +- 1 mm keeps the
// prior's z variance positive).
constexpr double kFlatZ_m = 1e-3;
const char* const kCreation = "MetricMap_landmarksMap_00_creationOpts";
const char* const kLikelihood = "MetricMap_landmarksMap_00_likelihoodOpts";

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

class Reader {
 public:
  explicit Reader(const std::string& path) : path_(path), cfg_(path) {}

  std::optional<std::string> text(const std::string& section, const std::string& key) {
    used_.insert(lower(section) + "\n" + lower(key));
    const std::string v = common::trim(cfg_.read_string(section, key, "", false));
    if (v.empty()) return std::nullopt;
    return v;
  }
  std::string where(const std::string& section, const std::string& key) const {
    return path_ + ": [" + section + "] " + key;
  }
  std::optional<double> number(const std::string& section, const std::string& key) {
    const auto v = text(section, key);
    if (!v) return std::nullopt;
    return common::parse_double(*v, where(section, key), "[" + section + "] " + key);
  }
  double required(const std::string& section, const std::string& key) {
    const auto v = number(section, key);
    if (!v) throw common::InputError(where(section, key) + ": missing", "[" + section + "] " + key);
    return *v;
  }
  std::optional<long long> integer(const std::string& section, const std::string& key, long long lo, long long hi) {
    const auto v = text(section, key);
    if (!v) return std::nullopt;
    return common::parse_integer(*v, where(section, key), lo, hi, "[" + section + "] " + key);
  }
  std::vector<std::string> unused() const {
    std::vector<std::string> out;
    std::vector<std::string> sections;
    cfg_.getAllSections(sections);
    for (const std::string& s : sections) {
      std::vector<std::string> keys;
      cfg_.getAllKeys(s, keys);
      for (const std::string& k : keys)
        if (!used_.count(lower(s) + "\n" + lower(k))) out.push_back("[" + s + "] " + k);
    }
    return out;
  }

 private:
  std::string path_;
  mrpt::config::CConfigFile cfg_;
  std::set<std::string> used_;
};

std::string resolve(const std::string& file, const std::string& config_path) {
  if (file.empty()) return file;
  const std::filesystem::path p(file);
  if (p.is_absolute()) return file;
  return (std::filesystem::path(config_path).parent_path() / p).lexically_normal().string();
}

}  // namespace

MrptAppConfig read_mrpt_app_config(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw common::InputError(path + ": no such configuration file");
  Reader r(path);
  MrptAppConfig c;
  if (const auto n = r.integer(kCreation, "nBeacons", 0, 100000)) {
    for (long long q = 1; q <= *n; ++q) {
      char prefix[32];
      std::snprintf(prefix, sizeof prefix, "beacon_%03lld_", q);
      const std::string p(prefix);
      const auto id = r.integer(kCreation, p + "ID", 0, 2147483647LL);
      if (!id)
        throw common::InputError(r.where(kCreation, p + "ID") + ": missing (nBeacons = " + std::to_string(*n) + ")");
      const Eigen::Vector3d xyz(r.required(kCreation, p + "X"), r.required(kCreation, p + "Y"),
                                r.number(kCreation, p + "Z").value_or(0.0));
      if (c.beacons.find(static_cast<std::int32_t>(*id))) {
        throw common::InputError(r.where(kCreation, p + "ID") + ": ID " + std::to_string(*id) + " listed twice");
      }
      c.beacons.add(static_cast<std::int32_t>(*id), xyz);
    }
  }
  if (const auto s = r.number(kLikelihood, "beaconRangesStd")) {
    if (!(*s > 0.0))
      throw common::InputError(r.where(kLikelihood, "beaconRangesStd") + " = " + std::to_string(*s) + ": must be > 0");
    c.range_sigma_m = *s;
  }
  if (const auto u = r.integer(kLikelihood, "beaconRangesUseObservationStd", 0, 1)) c.use_observation_std = *u == 1;
  if (const auto n = r.integer("PF_options", "sampleSize", 1, 10000000)) c.particles = static_cast<int>(*n);

  const auto ox = r.number("OdometryEstimation", "odometry_X");
  const auto oy = r.number("OdometryEstimation", "odometry_Y");
  const auto ophi = r.number("OdometryEstimation", "odometry_PHI");
  if (ox || oy || ophi) {
    c.start_pose = Eigen::Vector3d(ox.value_or(0.0), oy.value_or(0.0), ophi.value_or(0.0) * kDegToRad);
    localization::PoseBox box;
    box.min = Eigen::Vector4d((*c.start_pose)(0) - 0.5, (*c.start_pose)(1) - 0.5, -kFlatZ_m, -kPi);
    box.max = Eigen::Vector4d((*c.start_pose)(0) + 0.5, (*c.start_pose)(1) + 0.5, kFlatZ_m, kPi);
    c.prior = box;
  }
  const char* const kExp = "LocalizationExperiment";
  const auto mode = r.integer(kExp, "init_PDF_mode", 0, 1);
  const auto min_x = r.number(kExp, "init_PDF_min_x");
  if (mode && *mode == 1 && min_x) {
    localization::PoseBox box;
    box.min = Eigen::Vector4d(*min_x, r.required(kExp, "init_PDF_min_y"), -kFlatZ_m,
                              r.number(kExp, "init_PDF_min_yaw_deg").value_or(-180.0) * kDegToRad);
    box.max = Eigen::Vector4d(r.required(kExp, "init_PDF_max_x"), r.required(kExp, "init_PDF_max_y"), kFlatZ_m,
                              r.number(kExp, "init_PDF_max_yaw_deg").value_or(180.0) * kDegToRad);
    for (int k : {0, 1, 3}) {
      if (box.min(k) > box.max(k)) {
        throw common::InputError(path + ": [" + std::string(kExp) + "] init_PDF_min_* above init_PDF_max_*");
      }
    }
    c.prior = box;
  }
  if (const auto gt = r.text("ro-localization", "groundTruthFile")) c.ground_truth_file = resolve(*gt, path);
  if (const auto log = r.text("ro-localization", "rawlog_file"))
    c.rawlog_file = resolve(*log, path);
  else if (const auto log2 = r.text(kExp, "rawlog_file"))
    c.rawlog_file = resolve(*log2, path);
  c.unused_keys = r.unused();
  return c;
}

bool is_kf_slam_config(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) return false;
  const mrpt::config::CConfigFile cfg(path);
  return cfg.sectionExists("RangeBearingKFSLAM") || cfg.sectionExists("MappingApplication");
}

KfSlamConfig read_kf_slam_config(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw common::InputError(path + ": no such configuration file");
  Reader r(path);
  KfSlamConfig c;
  const char* const kApp = "MappingApplication";
  const char* const kSlam = "RangeBearingKFSLAM";
  if (const auto v = r.text(kApp, "rawlog_file")) c.rawlog_file = resolve(*v, path);
  if (const auto v = r.text(kApp, "ground_truth_file")) c.landmarks_file = resolve(*v, path);
  if (const auto v = r.text(kApp, "ground_truth_file_robot")) c.robot_path_file = resolve(*v, path);
  const auto positive = [&](const char* key) -> std::optional<double> {
    const auto v = r.number(kSlam, key);
    if (v && !(*v > 0.0 && std::isfinite(*v))) {
      throw common::InputError(r.where(kSlam, key) + " = " + common::format_double(*v) + ": must be > 0",
                               std::string("[") + kSlam + "] " + key);
    }
    return v;
  };
  const auto range = positive("std_sensor_range");
  const auto yaw = positive("std_sensor_yaw_deg");
  const auto pitch = positive("std_sensor_pitch_deg");
  if (range || yaw || pitch) {
    // A key the config leaves out takes the replay's default (landmark_filter.h: 0.01 m, 0.1 deg).
    c.sensor_sigma =
        Eigen::Vector3d(range.value_or(0.01), yaw.value_or(0.1) * kDegToRad, pitch.value_or(0.1) * kDegToRad);
  }
  if (const auto z = r.number(kSlam, "std_odo_z_additional")) {
    if (!(*z >= 0.0 && std::isfinite(*z)))
      throw common::InputError(r.where(kSlam, "std_odo_z_additional") + ": must be >= 0");
    c.odometry_z_sigma_additional_m = *z;
  }
  const auto xy = r.number(kSlam, "stdXY_no_odo");
  const auto phi = r.number(kSlam, "stdPhi_no_odo_deg");
  if (xy || phi) c.no_odometry_sigma = Eigen::Vector2d(xy.value_or(0.1), phi.value_or(2.0) * kDegToRad);
  c.unused_keys = r.unused();
  return c;
}

std::vector<Eigen::Vector3d> read_relative_ground_truth(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw common::InputError(path + ": cannot open ground-truth file");
  std::vector<Eigen::Vector3d> rows;
  std::string line;
  int line_no = 0;
  while (std::getline(f, line)) {
    ++line_no;
    std::istringstream in(line);
    std::vector<std::string> cols;
    std::string c;
    while (cols.size() < 4 && in >> c) cols.push_back(c);
    if (cols.empty() || cols[0][0] == '#' || cols[0][0] == '%') continue;
    const std::string at = path + ":" + std::to_string(line_no);
    if (cols.size() < 4)
      throw common::InputError(at + ": expected 'k x y phi', got " + std::to_string(cols.size()) + " column(s)");
    rows.emplace_back(common::parse_double(cols[1], at, "x"), common::parse_double(cols[2], at, "y"),
                      common::parse_double(cols[3], at, "phi"));
  }
  if (rows.empty()) throw common::InputError(path + ": no ground-truth row");
  return rows;
}

std::string beacons_ini_text(const localization::BeaconMap& beacons, std::optional<double> range_sigma_m) {
  if (beacons.empty()) throw common::InputError("beacons.ini: no beacon to write (empty beacon map)");
  if (range_sigma_m && !(*range_sigma_m > 0.0))
    throw common::InputError("beacons.ini: beaconRangesStd = " + std::to_string(*range_sigma_m) + ": must be > 0");
  std::ostringstream s;
  s.precision(17);
  s << "[MetricMap]\nlandmarksMap_count = 1\n\n";
  s << "[" << kCreation << "]\nnBeacons = " << beacons.size() << "\n";
  int q = 0;
  for (const auto& [id, p] : beacons.beacons()) {
    char prefix[32];
    std::snprintf(prefix, sizeof prefix, "beacon_%03d_", ++q);
    s << prefix << "ID = " << id << "\n"
      << prefix << "X = " << p.x() << "\n"
      << prefix << "Y = " << p.y() << "\n"
      << prefix << "Z = " << p.z() << "\n";
  }
  // Ranges only: no landmarks from 2-D scans (the stock configs' setting).
  s << "\n[MetricMap_landmarksMap_00_insertOpts]\ninsert_Landmarks_from_range_scans = 0\n";
  if (range_sigma_m) s << "\n[" << kLikelihood << "]\nbeaconRangesStd = " << *range_sigma_m << "\n";
  return s.str();
}

void write_beacons_ini(const localization::BeaconMap& beacons, const std::string& path,
                       std::optional<double> range_sigma_m) {
  const std::string text = beacons_ini_text(beacons, range_sigma_m);
  std::ofstream f(path);
  if (!(f << text)) throw std::runtime_error(path + ": cannot write");
}

}  // namespace losmimo::mrpt_logs
