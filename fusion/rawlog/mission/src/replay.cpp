#include "losmimo/placement/common/format.h"
#include "losmimo/fusion/rawlog/mission/replay.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <ostream>

#include "losmimo/fusion/estimation_step.h"
#include "losmimo/localization/position/estimation_errors.h"
#include "losmimo/localization/position/beacon_model.h"
#include "losmimo/localization/position/initial_belief.h"
#include "losmimo/placement/channel.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/metrics.h"
#include "losmimo/placement/swarm_shape.h"

namespace losmimo::rawlog {

namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

// Mean and the covariance's upper triangle, bit for bit: the log's CPose3DPDFGaussian keeps
// the upper triangle only, and Ceres' covariance can be asymmetric in the last bit.
bool bitwise_equal(const localization::Belief& a, const localization::Belief& b) {
  if (std::memcmp(a.mean_m.data(), b.mean_m.data(), 3 * sizeof(double)) != 0) return false;
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j)
      if (std::memcmp(&a.cov_m2(i, j), &b.cov_m2(i, j), sizeof(double)) != 0) return false;
  return true;
}

// The link metrics of positions q (3 x Nr) into row m.
void link_metrics(const placement::ChannelModel& model, double noise_variance, const Eigen::Matrix3Xd& q,
                  ReplayEpochMetrics& row) {
  const placement::LinkMetrics l = placement::evaluate_link(model.matrix(q), noise_variance);
  row.icn = l.icn;
  row.sinr_nv_db = placement::to_db(l.sinr.nv(0));
  row.sinr_zf_db = placement::to_db(l.sinr.zf(0));
  row.sinr_mf_db = placement::to_db(l.sinr.mf(0));
  row.sum_rate_zf_bps_hz = l.sum_rate_zf_bps_hz;
}

// One epoch's positions and errors, gathered UAV by UAV.
struct EpochColumns {
  Eigen::Matrix3Xd truth_m, estimate_m;         // 3 x Nr
  std::vector<Eigen::Matrix2d> lateral_cov_m2;  // per UAV: the belief's (y, z) covariance
  bool all_truth = true;
  localization::ErrorAccumulator errors;
};

// One replay of a mission log: the per-UAV estimators (fusion::UavEstimator, as the closed loop
// runs them), the beliefs silent UAVs hold, and the sums over the epochs.
class MissionReplay {
 public:
  MissionReplay(const MissionLog& log, const ReplayOptions& options);
  ReplayResult run();

 private:
  ReplayEpochMetrics epoch(int k);
  ReplayUavEpoch uav_epoch(int k, int m, EpochColumns& columns, ReplayEpochMetrics& row);
  void compare_with_log(const LoggedUavEpoch& in, const localization::Belief& filtered,
                        const localization::Belief& belief);
  void epoch_metrics(const EpochColumns& columns, ReplayEpochMetrics& row);
  void add_final_positions();

  const MissionLog& log_;
  const MissionConfig config_;
  const placement::Scenario& scenario_;  // config_'s
  fusion::ClosedLoopConfig cl_;          // with the options' estimator and refinement
  const int nr_;
  const placement::ChannelModel model_;
  std::vector<fusion::UavEstimator> uavs_;
  std::vector<localization::Belief> held_filtered_, held_belief_;  // silent UAVs keep these
  localization::ErrorAccumulator errors_, filter_errors_;
  placement::SwarmShapeAccumulator shape_;  // the epochs with every UAV's truth
  double icn_sum_ = 0.0;
  int icn_epochs_ = 0;
  ReplayResult out_;
};

MissionReplay::MissionReplay(const MissionLog& log, const ReplayOptions& options)
    : log_(log),
      config_(log.config ? *log.config : MissionConfig{}),
      scenario_(config_.placement.scenario),
      cl_(config_.closed_loop),
      nr_(log.num_uavs),
      model_(scenario_),
      held_filtered_(nr_),
      held_belief_(nr_) {
  const localization::FilterKind recorded_kind = cl_.filter_kind;
  const bool recorded_refine = cl_.refine;
  cl_.filter_kind = options.estimator.value_or(recorded_kind);
  cl_.refine = options.refine.value_or(recorded_refine);
  out_.estimator = localization::to_string(cl_.filter_kind) + (cl_.refine ? "+ceres" : "");
  out_.same_as_recorded = log.ours && cl_.filter_kind == recorded_kind && cl_.refine == recorded_refine;

  const fusion::EstimatorConfig estimator{cl_.filter_kind, cl_.filter, cl_.refine, cl_.refinement};
  const localization::Belief prior = localization::start_cube_prior(scenario_, cl_.filter);
  for (int m = 0; m < nr_; ++m) {
    const std::uint64_t seed = m < static_cast<int>(log.filter_seeds.size()) ? log.filter_seeds[m] : m;
    uavs_.emplace_back(scenario_, estimator, prior, seed);
  }
}

ReplayResult MissionReplay::run() {
  const int num_epochs = static_cast<int>(log_.epochs.size());
  for (int k = 0; k < num_epochs; ++k) out_.epochs.push_back(epoch(k));
  out_.mean_icn = icn_epochs_ > 0 ? icn_sum_ / icn_epochs_ : kNan;
  add_final_positions();
  out_.final_icn = out_.epochs.back().icn;
  out_.final_sinr_zf_db = out_.epochs.back().sinr_zf_db;
  out_.rmse_m = errors_.rmse_m();
  out_.lateral_rmse_m = errors_.lateral_rmse_m();
  out_.average_nees = errors_.average_nees();
  out_.common_lateral_rms_m = shape_.common_lateral_rms_m();
  out_.shape_lateral_rmse_m = shape_.shape_lateral_rmse_m();
  out_.shape_nees_per_dof = shape_.shape_nees_per_dof();
  out_.filter_rmse_m = filter_errors_.rmse_m();
  return std::move(out_);
}

ReplayEpochMetrics MissionReplay::epoch(int k) {
  ReplayEpochMetrics row;
  row.epoch = k;
  EpochColumns columns{Eigen::Matrix3Xd(3, nr_),
                       Eigen::Matrix3Xd(3, nr_),
                       std::vector<Eigen::Matrix2d>(static_cast<std::size_t>(nr_)),
                       true,
                       {}};
  for (int m = 0; m < nr_; ++m) out_.estimates.push_back(uav_epoch(k, m, columns, row));
  errors_ += columns.errors;
  epoch_metrics(columns, row);
  out_.silent_uav_epochs += row.silent_uavs;
  out_.fallback_uav_epochs += row.fallback_uavs;
  if (row.fallback_uavs > 0) ++out_.fallback_epochs;
  return row;
}

ReplayUavEpoch MissionReplay::uav_epoch(int k, int m, EpochColumns& columns, ReplayEpochMetrics& row) {
  static const LoggedUavEpoch kNothing;  // foreign rows are ragged (log.cpp)
  const LoggedUavEpoch& in = m < static_cast<int>(log_.epochs[k].size()) ? log_.epochs[k][m] : kNothing;
  // Ours: nothing arrived from the UAV in this epoch; the loop kept its belief (fusion/src/closed_loop.cpp).
  const bool silent = log_.ours && k > 0 && !in.reported;
  // Ours: '-' = the UAV was not commanded in iteration k + 1 (silent, or the run stopped).
  const bool commanded = !(log_.ours && k < static_cast<int>(log_.modes.size()) &&
                           static_cast<int>(log_.modes[k].size()) == nr_ && log_.modes[k][m] == '-');
  std::optional<localization::BeaconMeasurement> z;  // as the estimator consumed it
  localization::Belief filtered = held_filtered_[m], belief = held_belief_[m];
  if (!silent) {
    fusion::EpochMeasurements measurements{in.displacement_m, in.beacon, {}};
    if (in.csi) measurements.csi.push_back(*in.csi);
    const fusion::EpochEstimate est =
        k == 0 ? uavs_[m].start(std::move(measurements)) : uavs_[m].step(std::move(measurements));
    filtered = est.filter_belief;
    belief = est.belief;
    z = est.beacon;
  }
  held_filtered_[m] = filtered;
  held_belief_[m] = belief;
  compare_with_log(in, filtered, belief);

  ReplayUavEpoch est;
  est.epoch = k;
  est.uav = m;
  est.filter_belief = filtered;
  est.belief = belief;
  est.silent = silent;
  est.has_beacon = z.has_value();
  if (silent) ++row.silent_uavs;
  if (z) {
    ++out_.num_beacons;
    ++row.beacons;
    if (!in.beacon_exact) ++out_.num_inexact_beacons;
  }
  if (belief.degraded && cl_.fallback_to_bf && commanded) ++row.fallback_uavs;
  columns.estimate_m.col(m) = belief.mean_m;
  columns.lateral_cov_m2[static_cast<std::size_t>(m)] = belief.cov_m2.bottomRightCorner<2, 2>();
  if (in.truth_m) {
    est.has_truth = true;
    est.truth_m = *in.truth_m;
    columns.truth_m.col(m) = *in.truth_m;
    const Eigen::Vector3d e = belief.mean_m - *in.truth_m;
    est.error_m = e.norm();
    est.lateral_error_m = e.tail<2>().norm();
    est.nees = localization::nees(belief, *in.truth_m);
    columns.errors.add(belief, *in.truth_m);
    filter_errors_.add(filtered.mean_m, *in.truth_m);
  } else {
    columns.all_truth = false;
  }
  return est;
}

// With the recorded estimator: the replayed beliefs against the logged ones.
void MissionReplay::compare_with_log(const LoggedUavEpoch& in, const localization::Belief& filtered,
                                     const localization::Belief& belief) {
  if (!out_.same_as_recorded) return;
  if (in.filter_belief) {
    ++out_.filter_beliefs_compared;
    if (bitwise_equal(filtered, *in.filter_belief)) ++out_.filter_beliefs_bitwise_equal;
  }
  if (!cl_.refine || !in.refined_belief) return;
  ++out_.refined_beliefs_compared;
  if (bitwise_equal(belief, *in.refined_belief)) ++out_.refined_beliefs_bitwise_equal;
  if (std::memcmp(belief.mean_m.data(), in.refined_belief->mean_m.data(), 3 * sizeof(double)) == 0)
    ++out_.refined_means_bitwise_equal;
  const double scale = in.refined_belief->cov_m2.cwiseAbs().maxCoeff();
  if (scale > 0.0) {
    const Eigen::Matrix3d diff = (belief.cov_m2 - in.refined_belief->cov_m2).triangularView<Eigen::Upper>();
    out_.refined_cov_max_rel_diff = std::max(out_.refined_cov_max_rel_diff, diff.cwiseAbs().maxCoeff() / scale);
  }
}

// The epoch's errors, and its link metrics at the true and estimated positions when every
// UAV's truth is known (nan otherwise).
void MissionReplay::epoch_metrics(const EpochColumns& columns, ReplayEpochMetrics& row) {
  row.rmse_m = columns.errors.rmse_m();
  row.lateral_rmse_m = columns.errors.lateral_rmse_m();
  row.mean_nees = columns.errors.average_nees();
  if (!columns.all_truth) {
    row.icn = row.icn_estimated = row.sinr_nv_db = row.sinr_zf_db = row.sinr_mf_db = kNan;
    row.sum_rate_zf_bps_hz = kNan;
    return;
  }
  link_metrics(model_, scenario_.noise_variance(), columns.truth_m, row);
  shape_.add(columns.truth_m, columns.estimate_m, columns.lateral_cov_m2);
  ReplayEpochMetrics est_row;
  link_metrics(model_, scenario_.noise_variance(), columns.estimate_m, est_row);
  row.icn_estimated = est_row.icn;
  icn_sum_ += row.icn;
  ++icn_epochs_;
}

// The positions after the last iteration, when the log has them: link metrics only.
void MissionReplay::add_final_positions() {
  if (!log_.final_truth_m || log_.final_truth_m->cols() != nr_) return;
  ReplayEpochMetrics row;
  row.epoch = *log_.final_truth_epoch;
  row.final_positions = true;
  link_metrics(model_, scenario_.noise_variance(), *log_.final_truth_m, row);
  row.icn_estimated = row.rmse_m = row.lateral_rmse_m = row.mean_nees = kNan;
  out_.epochs.push_back(row);
}

}  // namespace

ReplayResult replay_mission(const MissionLog& log, const ReplayOptions& options) {
  if (log.num_uavs == 0 || log.epochs.empty())
    throw common::InputError("rawlog holds no epoch of any UAV: nothing to replay");
  return MissionReplay(log, options).run();
}

std::vector<std::pair<std::string, std::string>> replay_summary_rows(const MissionLog& log, const ReplayResult& r,
                                                                     bool stable) {
  std::vector<std::pair<std::string, std::string>> s = {
      {"estimator", r.estimator},
      {"log", log.ours ? "losmimo" : "foreign"},
      {"complete",
       log.complete || (!log.ours && log.read_status.stop == rawlog_io::RawlogStop::kEnd) ? "true" : "false"},
      {"uavs", std::to_string(log.num_uavs)},
      {"epochs", std::to_string(log.epochs.size())},
      {"rmse_m", common::format_csv(r.rmse_m)},
      {"lateral_rmse_m", common::format_csv(r.lateral_rmse_m)},
      {"average_nees", common::format_csv(r.average_nees)},
      {"common_lateral_m", common::format_csv(r.common_lateral_rms_m)},
      {"shape_lateral_rmse_m", common::format_csv(r.shape_lateral_rmse_m)},
      {"shape_nees", common::format_csv(r.shape_nees_per_dof)},
      {"filter_rmse_m", common::format_csv(r.filter_rmse_m)},
      {"mean_icn", common::format_csv(r.mean_icn)},
      {"final_icn", common::format_csv(r.final_icn)},
      {"final_sinr_zf_db", common::format_csv(r.final_sinr_zf_db)},
      {"fallback_uav_epochs", std::to_string(r.fallback_uav_epochs)},
      {"fallback_epochs", std::to_string(r.fallback_epochs)},
      {"beacons", std::to_string(r.num_beacons)},
      {"beacons_from_float", std::to_string(r.num_inexact_beacons)},
      {"same_as_recorded", r.same_as_recorded ? "true" : "false"},
      {"filter_beliefs_bitwise_equal",
       std::to_string(r.filter_beliefs_bitwise_equal) + "/" + std::to_string(r.filter_beliefs_compared)},
      {"refined_means_bitwise_equal",
       std::to_string(r.refined_means_bitwise_equal) + "/" + std::to_string(r.refined_beliefs_compared)},
  };
  if (!stable) {
    s.push_back({"refined_beliefs_bitwise_equal",
                 std::to_string(r.refined_beliefs_bitwise_equal) + "/" + std::to_string(r.refined_beliefs_compared)});
    s.push_back({"refined_cov_max_rel_diff", common::format_csv(r.refined_cov_max_rel_diff)});
  }
  // The recorded run's end (END_OF_LOG); summary.csv has it for a run ended by a fault only, so
  // that the other golden summaries stay as they were.
  if (!log.run_end.status.empty() && (log.run_faulted() || !stable)) {
    s.push_back({"status", log.run_end.status});
    if (log.run_faulted()) {
      s.push_back({"fault_uav", std::to_string(log.run_end.fault_uav)});
      s.push_back({"fault", log.run_end.fault.empty() ? "(not in the log)" : log.run_end.fault});
    }
  }
  if (r.silent_uav_epochs > 0) s.push_back({"silent_uav_epochs", std::to_string(r.silent_uav_epochs)});
  for (const auto& [what, n] : log.skipped) s.push_back({"skipped " + what, std::to_string(n)});
  return s;
}

namespace {

// A CSV field, quoted (RFC 4180) when it holds a comma, a quote or a line break (a fault reason).
std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string q = "\"";
  for (char c : text) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::ofstream open_out(const std::filesystem::path& p) {
  std::ofstream f(p);
  if (!f) throw std::runtime_error(p.string() + ": cannot write");
  return f;
}

}  // namespace

void write_replay_csv(const MissionLog& log, const ReplayResult& r, const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw std::runtime_error(dir + ": cannot create directory: " + ec.message());
  const std::filesystem::path d(dir);
  {
    std::ofstream f = open_out(d / "estimates.csv");
    f << "epoch,uav,x_true,y_true,z_true,x_est,y_est,z_est,sigma_x_m,sigma_y_m,sigma_z_m,error_m,"
         "lateral_error_m,nees,degraded,beacon\n";
    for (const ReplayUavEpoch& e : r.estimates) {
      const Eigen::Vector3d& q = e.belief.mean_m;
      const Eigen::Vector3d t = e.has_truth ? e.truth_m : Eigen::Vector3d::Constant(kNan);
      f << e.epoch << "," << e.uav << "," << common::format_csv(t.x()) << "," << common::format_csv(t.y()) << ","
        << common::format_csv(t.z()) << "," << common::format_csv(q.x()) << "," << common::format_csv(q.y()) << ","
        << common::format_csv(q.z()) << "," << common::format_csv(std::sqrt(e.belief.cov_m2(0, 0))) << ","
        << common::format_csv(std::sqrt(e.belief.cov_m2(1, 1))) << ","
        << common::format_csv(std::sqrt(e.belief.cov_m2(2, 2))) << ","
        << (e.has_truth ? common::format_csv(e.error_m) : "nan") << ","
        << (e.has_truth ? common::format_csv(e.lateral_error_m) : "nan") << ","
        << (e.has_truth ? common::format_csv(e.nees) : "nan") << "," << (e.belief.degraded ? 1 : 0) << ","
        << (e.has_beacon ? 1 : 0) << "\n";
    }
    if (!f) throw std::runtime_error((d / "estimates.csv").string() + ": write failed");
  }
  {
    std::ofstream f = open_out(d / "epochs.csv");
    f << "epoch,final,icn,icn_estimated,sinr_nv_db,sinr_zf_db,sinr_mf_db,sum_rate_zf_bps_hz,rmse_m,"
         "lateral_rmse_m,mean_nees,fallback_uavs,beacons\n";
    for (const ReplayEpochMetrics& e : r.epochs) {
      f << e.epoch << "," << (e.final_positions ? 1 : 0) << "," << common::format_csv(e.icn) << ","
        << common::format_csv(e.icn_estimated) << "," << common::format_csv(e.sinr_nv_db) << ","
        << common::format_csv(e.sinr_zf_db) << "," << common::format_csv(e.sinr_mf_db) << ","
        << common::format_csv(e.sum_rate_zf_bps_hz) << "," << common::format_csv(e.rmse_m) << ","
        << common::format_csv(e.lateral_rmse_m) << "," << common::format_csv(e.mean_nees) << "," << e.fallback_uavs
        << "," << e.beacons << "\n";
    }
    if (!f) throw std::runtime_error((d / "epochs.csv").string() + ": write failed");
  }
  {
    std::ofstream f = open_out(d / "summary.csv");
    f << "key,value\n";
    for (const auto& [k, v] : replay_summary_rows(log, r, true)) f << csv_field(k) << "," << csv_field(v) << "\n";
    if (!f) throw std::runtime_error((d / "summary.csv").string() + ": write failed");
  }
}

}  // namespace losmimo::rawlog
