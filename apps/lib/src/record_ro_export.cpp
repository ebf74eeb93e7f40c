#include "record_ro_export.h"

#include <filesystem>
#include <fstream>
#include <ostream>
#include <set>

#include "losmimo/fusion/rawlog/mission/log.h"
#include "losmimo/fusion/rawlog/mission/ro_export.h"
#include "losmimo/fusion/rawlog/io/reader.h"

namespace losmimo::apps {

namespace {

void write_text(const std::string& path, const std::string& text) {
  std::ofstream f(path);
  if (!(f << text) || !f.flush()) throw std::runtime_error(path + ": cannot write");
}

std::string file_name(const std::string& path) { return std::filesystem::path(path).filename().string(); }

}  // namespace

RoExportOutputs RoExportOutputs::create(const std::string& log_path, const std::vector<int>& uavs, int num_uavs,
                                        bool replace) {
  std::set<int> seen;
  for (int u : uavs) {
    if (u < 0 || u >= num_uavs)
      throw common::InputError("--ro-export: UAV " + std::to_string(u) +
                                   " is not in the mission ([scenario] num_uavs = " + std::to_string(num_uavs) +
                                   ": UAVs 0 .. " + std::to_string(num_uavs - 1) + ")",
                               "--ro-export");
    if (!seen.insert(u).second)
      throw common::InputError("--ro-export: UAV " + std::to_string(u) + " is given twice", "--ro-export");
  }
  RoExportOutputs out;
  try {
    for (int u : uavs) {
      const rawlog::RoExportPaths p = rawlog::ro_export_paths(log_path, u);
      Uav entry;
      entry.uav = u;
      entry.log_output_dir = p.log_output_dir;
      out.uavs_.push_back(std::move(entry));
      for (const std::string* path : {&p.rawlog, &p.ini, &p.ground_truth})
        out.uavs_.back().files.push_back(StagedFile::create(*path, replace));
    }
  } catch (...) {
    out.discard();
    throw;
  }
  return out;
}

void RoExportOutputs::write(const std::string& log_path, std::ostream& out) {
  if (uavs_.empty()) return;
  rawlog_io::RawlogReader reader = rawlog_io::RawlogReader::open_file(log_path);
  const rawlog::MissionLog log = rawlog::load_mission_log(reader);
  for (Uav& u : uavs_) {
    const rawlog::RoExport ro = rawlog::build_ro_export(log, u.uav);
    StagedFile &rawlog_file = u.files[0], &ini = u.files[1], &truth = u.files[2];
    rawlog::write_ro_rawlog(ro, rawlog_file.path());
    write_text(truth.path(), rawlog::ro_ground_truth_text(ro));
    write_text(ini.path(),
               rawlog::ro_localization_ini_text(ro, {file_name(rawlog_file.final_path()), file_name(truth.final_path()),
                                                     file_name(u.log_output_dir)}));
    for (StagedFile& f : u.files) f.publish();
    int ranges = 0;
    for (const rawlog::RoFrame& f : ro.frames) ranges += f.range_m ? 1 : 0;
    out << "losmimo-record: UAV " << u.uav << " for stock ro-localization: " << rawlog_file.final_path() << " ("
        << ro.frames.size() << " frames, " << ranges << " with a range), " << ini.final_path() << ", "
        << truth.final_path() << "\n";
  }
}

void RoExportOutputs::discard() {
  for (const Uav& u : uavs_)
    for (const StagedFile& f : u.files) {
      std::error_code ignored;
      std::filesystem::remove(f.path(), ignored);
    }
}

}  // namespace losmimo::apps
