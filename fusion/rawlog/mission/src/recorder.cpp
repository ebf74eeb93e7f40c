#include "losmimo/placement/common/format.h"
#include "losmimo/placement/common/hash.h"
#include "losmimo/fusion/rawlog/mission/recorder.h"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <memory>
#include <ostream>
#include <random>
#include <sstream>
#include <stdexcept>

#include <mrpt/io/CMemoryStream.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CObservationBeaconRanges.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationRawDAQ.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/serialization/CArchive.h>

#include "losmimo/fusion/rawlog/mission/format.h"
#include "losmimo/fusion/rawlog/mrpt_logs/mrpt_app_config.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/common/seed.h"
#include "losmimo/placement/metrics.h"
#include "stock_streams.h"

namespace losmimo::rawlog {

namespace {

using detail::bs_ranges_obs;
using detail::kTimeOrigin_s;

struct GzClose {
  void operator()(gzFile_s* f) const { gzclose(f); }
};

// The gzip file and the bookkeeping behind the integrity marks.
class RawlogWriter {
 public:
  RawlogWriter(const std::string& path, int level)
      : path_(path), file_(gzopen(path.c_str(), ("wb" + std::to_string(std::clamp(level, 1, 9))).c_str())) {
    if (!file_) throw std::runtime_error(path + ": cannot open for writing");
  }

  void write(const mrpt::obs::CObservation& obs) {
    mrpt::io::CMemoryStream mem;
    auto archive = mrpt::serialization::archiveFrom(mem);
    archive << obs;
    const auto n = static_cast<std::size_t>(mem.getTotalBytesCount());
    digest_ = common::fnv1a64(mem.getRawBufferData(), n, digest_);
    if (n > 0 && gzwrite(file_.get(), mem.getRawBufferData(), static_cast<unsigned>(n)) != static_cast<int>(n))
      throw std::runtime_error(path_ + ": write failed");
    bytes_ += n;
    ++objects_;
    ++label_counts_[obs.sensorLabel];
  }

  // A mark: its text gets the object count and the digest of everything since the last mark.
  void mark(const std::string& label, const std::string& body, double t_s) {
    mrpt::obs::CObservationComment c;
    c.sensorLabel = label;
    c.timestamp = mrpt::Clock::fromDouble(t_s);
    std::ostringstream text;
    text << "losmimo " << label << "\nobjects = " << objects_ << "\ndigest = " << common::format_hex64(digest_) << "\n"
         << body;
    // The mark's own text, up to here, so that no line of it changes unnoticed.
    c.text = with_text_digest(text.str());
    digest_ = common::kFnvOffset;
    write(c);
    digest_ = common::kFnvOffset;  // the mark itself is not part of the next digest
    if (gzflush(file_.get(), Z_SYNC_FLUSH) != Z_OK) throw std::runtime_error(path_ + ": flush failed");
  }

  void close() {
    const int rc = gzclose(file_.release());
    if (rc != Z_OK) throw std::runtime_error(path_ + ": close failed");
  }

  std::int64_t objects() const { return objects_; }
  std::uint64_t bytes() const { return bytes_; }
  const std::map<std::string, std::int64_t>& label_counts() const { return label_counts_; }

 private:
  std::string path_;
  std::unique_ptr<gzFile_s, GzClose> file_;
  std::uint64_t digest_ = common::kFnvOffset;
  std::int64_t objects_ = 0;
  std::uint64_t bytes_ = 0;
  std::map<std::string, std::int64_t> label_counts_;
};

mrpt::obs::CObservationRobotPose pose_obs(const std::string& label, double t_s, const Eigen::Vector3d& p,
                                          const Eigen::Matrix3d& cov) {
  mrpt::obs::CObservationRobotPose o;
  o.sensorLabel = label;
  o.timestamp = mrpt::Clock::fromDouble(t_s);
  o.pose.mean = mrpt::poses::CPose3D(p.x(), p.y(), p.z(), 0.0, 0.0, 0.0);
  o.pose.cov.setZero();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) o.pose.cov(i, j) = cov(i, j);
  return o;
}

mrpt::obs::CObservationRawDAQ daq_obs(const std::string& label, double t_s, std::vector<double> values) {
  mrpt::obs::CObservationRawDAQ o;
  o.sensorLabel = label;
  o.timestamp = mrpt::Clock::fromDouble(t_s);
  o.AIN_channel_count = static_cast<std::uint16_t>(values.size());
  o.AIN_interleaved = true;
  o.AIN_double = std::move(values);
  return o;
}

// The dead reckoning as MRPT odometry: the cumulative reading (x, y; heading 0, the BS frame's
// axes), so that stock apps' increments between readings are the measured displacements.
mrpt::obs::CObservationOdometry odometry_obs(const std::string& label, double t_s, const Eigen::Vector2d& xy) {
  mrpt::obs::CObservationOdometry o;
  o.sensorLabel = label;
  o.timestamp = mrpt::Clock::fromDouble(t_s);
  o.odometry = mrpt::poses::CPose2D(xy.x(), xy.y(), 0.0);
  return o;
}

std::string flags(const std::vector<char>& v) { return std::string(v.begin(), v.end()); }

class Recorder : public fusion::ClosedLoopObserver {
 public:
  Recorder(const MissionConfig& config, const RecordOptions& options)
      : config_(config),
        options_(options),
        writer_(options.out_path, options.compression_level),
        model_(config.placement.scenario),
        csi_rng_(recorder_csi_seed(config.seed)) {}

  void on_start(const std::vector<std::uint64_t>& filter_seeds) override {
    const int nr = static_cast<int>(filter_seeds.size());
    filter_degraded_.assign(nr, '0');
    degraded_.assign(nr, '0');
    modes_.assign(nr, '-');
    since_beacon_.assign(nr, 0);
    odometry_m_.assign(nr, Eigen::Vector2d::Zero());
    mrpt::obs::CObservationComment c;
    c.sensorLabel = kLabelConfig;
    c.timestamp = mrpt::Clock::fromDouble(kTimeOrigin_s);
    std::ostringstream text;
    text << kRawlogMagic << " " << kRawlogFormatVersion << "\n"
         << mission_to_ini(config_) << "\n[rawlog]\nformat_version = " << kRawlogFormatVersion << "\nnum_uavs = " << nr
         << "\nnum_bs_antennas = " << config_.placement.scenario.num_bs_antennas()
         << "\nepoch_origin_s = " << common::format_exact(kTimeOrigin_s) << "\nfilter_seeds = ";
    for (int m = 0; m < nr; ++m) text << (m ? ", " : "") << filter_seeds[m];
    text << "\ncsi_source = "
         << (config_.closed_loop.refine && config_.closed_loop.refinement.use_csi ? "loop" : "recorder") << "\n";
    c.text = text.str();
    writer_.write(c);
  }

  void on_epoch(const fusion::EpochObservation& e) override {
    const double t = time_s(e.epoch);
    const int m = e.uav;
    epochs_ = std::max(epochs_, e.epoch + 1);
    // Dead reckoning first: in a reader that knows nothing of the marks, the displacement opens
    // the UAV's next epoch and everything after it belongs there (log.h).
    if (e.measured_displacement_m) {
      const auto& n = config_.closed_loop.filter.noise;
      const double s = detail::dr_sigma_m(n, *e.measured_displacement_m);
      writer_.write(
          pose_obs(uav_label(m, UavStream::kDr), t, *e.measured_displacement_m, s * s * Eigen::Matrix3d::Identity()));
      odometry_m_[m] += e.measured_displacement_m->head<2>();
    }
    writer_.write(odometry_obs(uav_label(m, UavStream::kOdometry), t, odometry_m_[m]));
    writer_.write(pose_obs(uav_label(m, UavStream::kTruth), t, e.true_position_m, Eigen::Matrix3d::Zero()));
    if (e.beacon) {
      mrpt::obs::CObservationBearingRange b;
      b.sensorLabel = uav_label(m, UavStream::kBeacon);
      b.timestamp = mrpt::Clock::fromDouble(t);
      b.validCovariances = false;
      b.sensor_std_range = static_cast<float>(config_.closed_loop.simulator.sigma_range_m);
      b.sensor_std_yaw = static_cast<float>(config_.closed_loop.simulator.sigma_angle_rad);
      b.sensor_std_pitch = b.sensor_std_yaw;
      b.maxSensorDistance = 1e6f;
      mrpt::obs::CObservationBearingRange::TMeasurement z;
      z.range = static_cast<float>(e.beacon->range_m);
      z.yaw = static_cast<float>(e.beacon->azimuth_rad);
      z.pitch = static_cast<float>(-e.beacon->elevation_rad);  // MRPT: pitch = -elevation
      z.landmarkID = 0;                                        // the BS
      z.covariance.setZero();
      b.sensedData.push_back(z);
      writer_.write(b);
      writer_.write(daq_obs(uav_label(m, UavStream::kBeacon64), t,
                            {e.beacon->range_m, e.beacon->azimuth_rad, e.beacon->elevation_rad}));
      writer_.write(bs_ranges_obs(uav_label(m, UavStream::kBsRanges), t, e.beacon->range_m,
                                  config_.closed_loop.simulator.sigma_range_m));
    }
    const fusion::CsiMeasurement csi =
        e.csi ? *e.csi
              : fusion::simulate_csi(model_, e.true_position_m, config_.placement.scenario.noise_variance(), csi_rng_);
    std::vector<double> iq;
    iq.reserve(2 * csi.y.size());
    for (Eigen::Index k = 0; k < csi.y.size(); ++k) {
      iq.push_back(csi.y(k).real());
      iq.push_back(csi.y(k).imag());
    }
    writer_.write(daq_obs(uav_label(m, UavStream::kCsi), t, std::move(iq)));
    writer_.write(pose_obs(uav_label(m, UavStream::kBelief), t, e.filter_belief.mean_m, e.filter_belief.cov_m2));
    if (config_.closed_loop.refine)
      writer_.write(pose_obs(uav_label(m, UavStream::kRefined), t, e.belief.mean_m, e.belief.cov_m2));
    filter_degraded_[m] = e.filter_belief.degraded ? '1' : '0';
    degraded_[m] = e.belief.degraded ? '1' : '0';
    since_beacon_[m] = e.filter_belief.epochs_since_beacon;
    current_epoch_ = e.epoch;
    epoch_open_ = true;
  }

  void on_move(const fusion::MoveObservation& mv) override {
    const double mode = mv.escape ? kMoveEscape : (mv.mode == fusion::UavMode::kBf ? kMoveBf : kMoveGd);
    if (!mv.escape) modes_[mv.uav] = static_cast<char>(mv.mode);
    writer_.write(daq_obs(uav_label(mv.uav, UavStream::kMove), time_s(mv.iteration - 1) + 0.5 * config_.epoch_period_s,
                          {static_cast<double>(mv.iteration), mode, mv.commanded_m.x(), mv.commanded_m.y(),
                           mv.commanded_m.z(), mv.actual_m.x(), mv.actual_m.y(), mv.actual_m.z()}));
  }

  void on_iteration_end(int iteration, const placement::Swarm& swarm) override {
    close_epoch(iteration - 1, placement::inverse_condition_number(swarm.channel().H()));
  }

  void close_epoch(int epoch, double icn_after_moves) {
    if (!epoch_open_) return;
    std::ostringstream body;
    body << "epoch = " << epoch << "\nmark = " << marks_ << "\nfilter_degraded = " << flags(filter_degraded_)
         << "\ndegraded = " << flags(degraded_) << "\nepochs_since_beacon = ";
    for (std::size_t m = 0; m < since_beacon_.size(); ++m) body << (m ? "," : "") << since_beacon_[m];
    body << "\nmodes = " << flags(modes_) << "\nicn_after_moves = " << common::format_exact(icn_after_moves) << "\n";
    writer_.mark(kLabelEpochEnd, body.str(), time_s(epoch) + 0.9 * config_.epoch_period_s);
    ++marks_;
    epoch_open_ = false;
    std::fill(modes_.begin(), modes_.end(), '-');
    if (options_.after_epoch_mark) options_.after_epoch_mark(epoch);
  }

  RecordResult finish(const fusion::ClosedLoopRun& r) {
    close_epoch(current_epoch_, r.run.trace.empty() ? 0.0 : r.run.trace.back().icn);
    const int final_epoch = r.run.iterations;
    if (final_epoch > 0) {
      for (int m = 0; m < r.run.final_m.cols(); ++m) {
        writer_.write(pose_obs(uav_label(m, UavStream::kTruth), time_s(final_epoch), r.run.final_m.col(m),
                               Eigen::Matrix3d::Zero()));
      }
    }
    std::ostringstream body;
    body << "epochs = " << epochs_ << "\nmarks = " << marks_
         << "\nfinal_truth_epoch = " << (final_epoch > 0 ? final_epoch : -1) << "\niterations = " << r.run.iterations
         << "\nstatus = " << placement::to_string(r.run.status)
         << "\nfinal_icn = " << common::format_exact(r.run.trace.empty() ? 0.0 : r.run.trace.back().icn) << "\n";
    if (r.run.faulted()) {  // only then: the logs of runs without a fault stay byte for byte
      std::string reason = r.run.fault;
      std::replace(reason.begin(), reason.end(), '\n', ' ');  // one "key = value" line
      body << "fault_uav = " << r.run.fault_uav << "\nfault = " << reason << "\n";
    }
    for (const auto& [label, n] : writer_.label_counts()) body << "count." << label << " = " << n << "\n";
    writer_.mark(kLabelEndOfLog, body.str(), time_s(final_epoch) + 0.95 * config_.epoch_period_s);
    writer_.close();
    RecordResult out;
    out.run = r;
    out.objects = writer_.objects();
    out.uncompressed_bytes = writer_.bytes();
    out.epochs = epochs_;
    out.label_counts = writer_.label_counts();
    return out;
  }

 private:
  double time_s(int epoch) const { return kTimeOrigin_s + epoch * config_.epoch_period_s; }

  const MissionConfig& config_;
  const RecordOptions& options_;
  RawlogWriter writer_;
  placement::ChannelModel model_;
  std::mt19937_64 csi_rng_;
  std::vector<char> filter_degraded_, degraded_, modes_;
  std::vector<int> since_beacon_;
  std::vector<Eigen::Vector2d> odometry_m_;  // per UAV: the ODOMETRY reading (sum of the DR x, y)
  int epochs_ = 0, marks_ = 0, current_epoch_ = 0;
  bool epoch_open_ = false;
};

}  // namespace

std::uint64_t recorder_csi_seed(std::uint64_t mission_seed) {
  return common::tagged_seed(mission_seed, kRecorderCsiStreamTag);
}

RecordResult record_mission(const MissionConfig& config, const RecordOptions& options) {
  Recorder recorder(config, options);
  const fusion::ClosedLoopRun run = fusion::run_closed_loop(config.placement, mission_start_positions_m(config),
                                                            config.closed_loop, config.seed, &recorder);
  return recorder.finish(run);
}

localization::BeaconMap bs_ranges_beacon_map() {
  localization::BeaconMap map;
  map.add(kBsBeaconId, Eigen::Vector3d::Zero());
  return map;
}

std::string mission_beacons_ini_text(const MissionConfig& config) {
  std::ostringstream s;
  s << mrpt_logs::beacons_ini_text(bs_ranges_beacon_map(), detail::stock_beacon_ranges_std_m(config));
  // The prior every UAV starts from: the start cube's x-y extent; heading 0, the odometry's
  // axes being the BS frame's.
  const placement::Scenario& sc = config.placement.scenario;
  const double h = 0.5 * sc.cube_side_m;
  s << "\n[LocalizationExperiment]\ninit_PDF_mode = 1\n"
    << "init_PDF_min_x = " << common::format_exact(sc.cube_center_m.x() - h)
    << "\ninit_PDF_max_x = " << common::format_exact(sc.cube_center_m.x() + h)
    << "\ninit_PDF_min_y = " << common::format_exact(sc.cube_center_m.y() - h)
    << "\ninit_PDF_max_y = " << common::format_exact(sc.cube_center_m.y() + h)
    << "\ninit_PDF_min_yaw_deg = 0\ninit_PDF_max_yaw_deg = 0\n";
  return s.str();
}

std::string beacons_ini_path(const std::string& log_path) {
  const std::string ext = ".rawlog";
  const bool has_ext =
      log_path.size() > ext.size() && log_path.compare(log_path.size() - ext.size(), ext.size(), ext) == 0;
  return (has_ext ? log_path.substr(0, log_path.size() - ext.size()) : log_path) + ".beacons.ini";
}

}  // namespace losmimo::rawlog
