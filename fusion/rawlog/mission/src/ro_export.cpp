#include "losmimo/fusion/rawlog/mission/ro_export.h"

#include <zlib.h>

#include <algorithm>
#include <iomanip>
#include <memory>
#include <sstream>
#include <stdexcept>

#include <mrpt/io/CMemoryStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/serialization/CArchive.h>

#include "losmimo/placement/common/format.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/fusion/rawlog/mrpt_logs/mrpt_app_config.h"
#include "losmimo/fusion/rawlog/mission/recorder.h"
#include "stock_streams.h"

namespace losmimo::rawlog {

namespace {

std::string uav_name(int uav) {
  std::ostringstream s;
  s << "UAV " << uav;
  return s.str();
}

// The (action, sensory frame) pair of one frame, serialized.
void append_frame(const RoExport& ro, const RoFrame& f, mrpt::serialization::CArchive& archive) {
  const double t_s = detail::kTimeOrigin_s + f.epoch * ro.epoch_period_s;
  mrpt::poses::CPosePDFGaussian change;
  change.mean = mrpt::poses::CPose2D(f.increment_m.x(), f.increment_m.y(), 0.0);
  change.cov.setZero();
  change.cov(0, 0) = change.cov(1, 1) = f.increment_sigma_m * f.increment_sigma_m;
  change.cov(2, 2) = kRoHeadingSigma_rad * kRoHeadingSigma_rad;
  mrpt::obs::CActionRobotMovement2D move;
  move.timestamp = mrpt::Clock::fromDouble(t_s);
  // Not emOdometry: MRPT serializes that as the raw increment plus a motion model's parameters
  // and recomputes the covariance from the model when reading; any other method keeps the PDF.
  move.estimationMethod = mrpt::obs::CActionRobotMovement2D::emScan2DMatching;
  move.poseChange = mrpt::poses::CPosePDFGaussian::Create(change);
  mrpt::obs::CActionCollection actions;
  actions.insert(move);
  mrpt::obs::CSensoryFrame frame;
  if (f.range_m)
    frame.insert(std::make_shared<mrpt::obs::CObservationBeaconRanges>(
        detail::bs_ranges_obs(uav_label(ro.uav, UavStream::kBsRanges), t_s, *f.range_m, ro.range_sigma_m)));
  archive << actions << frame;
}

struct GzClose {
  void operator()(gzFile_s* f) const { gzclose(f); }
};

}  // namespace

RoExport build_ro_export(const MissionLog& log, int uav) {
  if (!log.ours || !log.config)
    throw common::InputError("the log was not written by losmimo-record (no mission config): nothing to export");
  if (uav < 0 || uav >= log.num_uavs)
    throw common::InputError("UAV " + std::to_string(uav) + " is not in the log: it has " +
                                 std::to_string(log.num_uavs) + " UAVs (0 .. " + std::to_string(log.num_uavs - 1) + ")",
                             "uav");
  const MissionConfig& config = *log.config;
  RoExport ro;
  ro.uav = uav;
  ro.range_sigma_m = config.closed_loop.simulator.sigma_range_m;
  ro.beacon_ranges_std_m = detail::stock_beacon_ranges_std_m(config);
  ro.epoch_period_s = config.epoch_period_s;
  for (std::size_t k = 0; k < log.epochs.size(); ++k) {
    if (static_cast<std::size_t>(uav) >= log.epochs[k].size() || !log.epochs[k][uav].reported) continue;
    const LoggedUavEpoch& e = log.epochs[k][uav];
    const std::string where = uav_name(uav) + ", epoch " + std::to_string(k);
    if (!e.truth_m) throw common::InputError(where + ": no true position (TRUTH) in the log");
    RoFrame f;
    f.epoch = static_cast<int>(k);
    if (e.displacement_m && !ro.frames.empty()) {  // the first frame starts the track: no motion before it
      f.increment_m = e.displacement_m->head<2>();
      f.increment_sigma_m = detail::dr_sigma_m(config.closed_loop.filter.noise, *e.displacement_m);
    } else {
      f.increment_sigma_m = config.closed_loop.filter.noise.dr_sigma_floor_m;
    }
    f.increment_sigma_m = std::max(f.increment_sigma_m, kRoMinIncrementSigma_m);
    if (e.beacon) f.range_m = e.beacon->range_m;
    f.truth_m = e.truth_m->head<2>();
    if (ro.frames.empty()) {
      if (!e.filter_belief) throw common::InputError(where + ": no filter belief (BELIEF) in the log");
      ro.start_m = e.filter_belief->mean_m.head<2>();
    }
    ro.frames.push_back(f);
  }
  if (ro.frames.empty()) throw common::InputError(uav_name(uav) + " reported no epoch in the log: nothing to export");
  return ro;
}

void write_ro_rawlog(const RoExport& ro, const std::string& path) {
  mrpt::io::CMemoryStream mem;
  auto archive = mrpt::serialization::archiveFrom(mem);
  for (const RoFrame& f : ro.frames) append_frame(ro, f, archive);
  std::unique_ptr<gzFile_s, GzClose> file(gzopen(path.c_str(), "wb6"));
  if (!file) throw std::runtime_error(path + ": cannot open for writing");
  const auto n = static_cast<std::size_t>(mem.getTotalBytesCount());
  if (n > 0 && gzwrite(file.get(), mem.getRawBufferData(), static_cast<unsigned>(n)) != static_cast<int>(n))
    throw std::runtime_error(path + ": write failed");
  if (gzclose(file.release()) != Z_OK) throw std::runtime_error(path + ": write failed (closing)");
}

std::string ro_ground_truth_text(const RoExport& ro) {
  std::ostringstream s;
  for (std::size_t j = 0; j < ro.frames.size(); ++j) {
    const Eigen::Vector2d rel = ro.frames[j].truth_m - ro.start_m;
    s << j << ' ' << common::format_exact(rel.x()) << ' ' << common::format_exact(rel.y()) << " 0\n";
  }
  return s.str();
}

std::string ro_localization_ini_text(const RoExport& ro, const RoIniPaths& paths) {
  std::ostringstream s;
  s << "# Stock ro-localization (Debian mrpt-apps) on " << uav_name(ro.uav)
    << "'s stream of a losmimo log; in this folder: ro-localization THIS.ini < /dev/null\n"
    << "# (without a display, MRPT_WXSUBSYS_TIMEOUT_MS=100 shortens its GUI start-up timeout).\n";
  s << mrpt_logs::beacons_ini_text(bs_ranges_beacon_map(), ro.beacon_ranges_std_m);
  s << "\n[ro-localization]\nrawlog_file = " << paths.rawlog << "\ngroundTruthFile = " << paths.ground_truth
    << "\nlogOutput_dir = " << paths.log_output_dir << "\nrandom_seed = " << kRoRandomSeed
    << "\nexperimentRepetitions = 1\n3DSceneFrequency = 1000000000\nSAVE_3D_TO_VIDEO = 0\n";
  s << "\n[OdometryEstimation]\nodometry_X = " << common::format_exact(ro.start_m.x())
    << "\nodometry_Y = " << common::format_exact(ro.start_m.y()) << "\nodometry_PHI = 0\n";
  s << "\n[PF_options]\nPF_algorithm = 0\nresamplingMethod = 0\nadaptiveSampleSize = 0\nBETA = 0.5\nsampleSize = "
    << kRoParticles << "\n";
  s << "\n[RO_MODEL]\nprobabilityChangingBias = 0\nchangingBiasUnifRange = 0\nmixtureProposalRatio = 0\n";
  return s.str();
}

RoExportPaths ro_export_paths(const std::string& log_path, int uav) {
  const std::string ext = ".rawlog";
  const bool has_ext =
      log_path.size() > ext.size() && log_path.compare(log_path.size() - ext.size(), ext.size(), ext) == 0;
  std::ostringstream stem;
  stem << (has_ext ? log_path.substr(0, log_path.size() - ext.size()) : log_path) << ".uav" << std::setw(2)
       << std::setfill('0') << uav;
  const std::string b = stem.str();
  return {b + ".ro.rawlog", b + ".ro.ini", b + ".ro_truth.txt", b + ".ro_out"};
}

}  // namespace losmimo::rawlog
